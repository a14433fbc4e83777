#!/usr/bin/env bash
# The semi-smooth Newton of this build against an older one, in one window: runs, with
# lab/programs/contact_scaling.rs (semi-smooth contact, the defaults of each build), the whole
# S-start with implicit Euler at 5e-4 s on 200 and 400 elements, its first 1.5 s on 800
# elements, the heavy S-start on 200 elements, 200 elements with BDF2 at 3.6e-3 and 5e-3 s
# and the bundled file; each configuration with the old build first, then this one. Prints,
# per run, the semi-smooth retries and the steps by their Newton iteration count too. Keeps
# the output as a dated record docs/results/RECORD/<date>.md (records semismooth-start: the
# extrapolated start against the build before it; semismooth-retries: the retries of a
# failed step against the build before them; semismooth-residual: the residual summed once
# per coordinate and the start on the ground against the build before them;
# semismooth-forcing: those and GMRES's fixed tolerance near the solution, the same).
#
#   CONTACT_SCALING_OLD=/path/to/old/contact_scaling lab/semismooth_ab/semismooth_ab.sh RECORD
#   # about 5 minutes; without CONTACT_SCALING_OLD only this build runs
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    record="${1:-semismooth-ab}"
    case "$record" in *[!A-Za-z0-9_-]*) echo "semismooth_ab.sh: RECORD may use only letters, digits, - and _" >&2; exit 2 ;; esac
    exec tools/record.sh "$record" "$0" --inner
fi
. tools/build.sh
new="$(lab_program contact_scaling)"
bins=()
if [ -n "${CONTACT_SCALING_OLD:-}" ]; then
    bins+=("$CONTACT_SCALING_OLD")
    echo "old build: $CONTACT_SCALING_OLD"
fi
bins+=("$new")
runs=(
    "--elements 200,400 --dt 5e-4 --duration full"
    "--elements 800 --dt 5e-4 --duration 1.5"
    "--scene problems/s_start_heavy.toml --elements 200 --dt 5e-4 --duration full"
    "--elements 200 --dt 3.6e-3,5e-3 --integrator bdf2 --duration full"
    "--elements 100 --dt 3.6e-3 --integrator bdf2 --duration full"
)
for r in "${runs[@]}"; do
    for bin in "${bins[@]}"; do
        echo
        echo "## $bin $r"
        # shellcheck disable=SC2086
        "$bin" --contact semi-smooth $r 2>&1
    done
done
