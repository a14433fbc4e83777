#!/usr/bin/env bash
# Where the semi-smooth contact Newton's iterations go on the S-start (problems/s_start.toml's
# scene): BDF2 at 5e-3 s on 200 elements (the converged S-start of compare/run.sh) and
# implicit Euler at 5e-4 s on 400 elements (the first 1.5 s, then the whole run in windows of
# 500 steps), each run with SLITHER_DEBUG=1 and its trace summarised by
# lab/status_anatomy/status_trace.py: how the converged statuses move from one step to the next, and how
# the steps that take many iterations spend them. Kept as a dated record
# docs/results/status-anatomy/<date>.md.
#
#   lab/status_anatomy/status_anatomy.sh         # 3 runs, about 2 min
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh status-anatomy "$0" "$@"
fi
. tools/build.sh
use_slither
slither="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
scene() { # name elements dt integrator duration label [status_trace.py options]
    local f="$tmp/$1.toml"
    sed -e "s/^elements = .*/elements = $2/" -e "s/^dt = .*/dt = $3/" \
        -e "s/^integrator = .*/integrator = \"$4\"/" -e "s/^duration = .*/duration = $5/" \
        -e "s/^interval = .*/interval = 0.05/" problems/s_start.toml >"$f"
    grep -q "^elements = $2" "$f" && grep -q "^integrator = \"$4\"" "$f"
    SLITHER_DEBUG=1 "$slither" run "$f" --out "$tmp/out_$1" --no-plots --quiet 2>"$tmp/$1.trace"
    jq -r '"\(.stats.steps) steps, \(.newton_iterations_mean) Newton iterations per step, \(.stats.semismooth_fallbacks) conic fallbacks, v_s/v_m \(.v_s_over_v_m)"' "$tmp/out_$1/summary.json"
    python3 lab/status_anatomy/status_trace.py "$tmp/$1.trace" "$6" ${7:-}
}
scene bdf2_200 200 5e-3 bdf2 3.572 "BDF2 5e-3 s, 200 elements, whole run"
scene euler_400 400 5e-4 implicit 1.5 "implicit Euler 5e-4 s, 400 elements, first 1.5 s"
scene euler_400_whole 400 5e-4 implicit 3.572 "implicit Euler 5e-4 s, 400 elements, whole run" "--window 500"
