#!/usr/bin/env bash
# Where the semi-smooth Newton starts each step: the force variables (and, with implicit
# Euler, the velocities) extrapolated over the last two steps, against an older build that
# starts from the last step's forces and the scheme's predictor. Runs, with
# examples/contact_scaling.rs (semi-smooth contact, default penalty and memory), the whole
# S-start with implicit Euler at 5e-4 s on 200 and 400 elements, its first 1.5 s on 800
# elements, the heavy S-start on 200 elements, 200 elements with BDF2 at 3.6e-3 and 5e-3 s
# and the bundled file; each configuration with the old build first, then this one, in one
# window. Prints, per run, the steps by their Newton iteration count too. Keeps the output as
# a dated record docs/results/semismooth-start/<date>.md.
#
#   CONTACT_SCALING_OLD=/path/to/old/contact_scaling scripts/semismooth_start.sh
#   # about 5 minutes; without CONTACT_SCALING_OLD only this build runs
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
if [ "${1:-}" != "--inner" ]; then
    exec scripts/record.sh semismooth-start "$0" --inner
fi
cargo build --release --quiet --example contact_scaling
new="${CARGO_TARGET_DIR:-target}/release/examples/contact_scaling"
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
