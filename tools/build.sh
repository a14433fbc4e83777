# The lab's one build step: source this file, then ask for a binary's path.
#
#   . tools/build.sh                       # from the repository root (or give its path)
#   use_slither                            # sets and exports SLITHER: as given, else the
#   slither="$SLITHER"                     # release build of slither
#   scan="$(lab_program convergence_scan)" # $SLITHER_EXAMPLES/NAME if set, else the release
#                                          # build of lab/programs/NAME.rs (a Cargo example)
#
# Each builds with `cargo build --release --quiet` in the repository (a no-op when the build is
# current) and sends cargo's output to stderr. `use_slither` exports SLITHER, so a script it
# starts (tools/record.sh re-running the script) builds no more; `lab_program` prints the
# program's path. CARGO_TARGET_DIR is honoured. A failed build returns 1 (and fails the
# script under set -e).

_lab_repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

# The target directory of the build (CARGO_TARGET_DIR, else the repository's target/).
_lab_target() {
    echo "${CARGO_TARGET_DIR:-$_lab_repo/target}"
}

# SLITHER, the slither binary: as given, else built once and exported.
use_slither() {
    if [ -z "${SLITHER:-}" ]; then
        (cd "$_lab_repo" && cargo build --release --quiet) >&2 || return 1
        SLITHER="$(_lab_target)/release/slither"
        export SLITHER
    fi
}

# A lab program (lab/programs/NAME.rs): $SLITHER_EXAMPLES/NAME, else built.
lab_program() {
    if [ -n "${SLITHER_EXAMPLES:-}" ]; then
        echo "$SLITHER_EXAMPLES/$1"
        return
    fi
    (cd "$_lab_repo" && cargo build --release --quiet --example "$1") >&2 || return 1
    echo "$(_lab_target)/release/examples/$1"
}
