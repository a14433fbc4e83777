#!/usr/bin/env bash
# The converged value with ground contact on the curve ([solver] ground_points = "curve") by
# BDF2: the bundled S-start at 400 elements with BDF2 at fixed steps of 5e-4 and 2.5e-4 s, side
# by side (two processes), to set beside implicit Euler's 400-element values at the same steps
# (record ground-points). v_s/v_m, iterations, fallbacks, halvings and wall time of each. Kept
# as the dated record docs/results/ground-points-bdf2/<date>.md.
#
#   lab/ground_points/bdf2.sh          # about 10 min on 2 cores
#   lab/ground_points/bdf2.sh nodes    # the same with contact at the nodes
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points-bdf2 "$0" "$@"
fi
points="${1:-curve}"
case "$points" in nodes | curve) ;; *) echo "bdf2.sh: unknown model '$points' (nodes or curve)" >&2; exit 2 ;; esac
. tools/build.sh
use_slither
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
steps=(5e-4 2.5e-4)
for dt in "${steps[@]}"; do
    "$SLITHER" run problems/s_start.toml --out "$tmp/$dt" --no-plots --quiet --force \
        --set rod.elements=400 --set solver.integrator='"bdf2"' --set time.dt="$dt" \
        --set solver.ground_points="\"$points\"" >"$tmp/$dt.log" 2>&1 &
done
wait
echo "contact: $points, 400 elements, BDF2 at fixed steps"
echo
echo "| step s | v_s/v_m | steps | Newton it/step | conic fallbacks | step halvings | steps at nodes | wall s |"
echo "|---|---|---|---|---|---|---|---|"
for dt in "${steps[@]}"; do
    jq -r --arg h "$dt" '"| \($h) | \(.v_s_over_v_m * 100000 | round / 100000) | \(.steps) | \(.newton_iterations_mean * 100 | round / 100) | \(.stats.semismooth_fallbacks) | \(.stats.step_halvings) | \(.stats.ground_point_fallbacks // 0) | \(.wall_time_s * 10 | round / 10) |"' "$tmp/$dt/summary.json" \
        || { echo "| $dt | failed: $(tail -n 3 "$tmp/$dt.log" | tr '\n' ' ') |"; }
done
