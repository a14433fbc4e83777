#!/usr/bin/env bash
# `slither run problems/s_start.toml --accuracy 0.01` with ground contact at the nodes and on
# the curve ([solver] ground_points), one after the other: the model each chooses, its
# estimate and answer, and the elapsed time; then the curve at `--accuracy 0.005` (what an
# estimate of at most 0.5 % costs); every run of the curve's selections. Kept as the dated record
# docs/results/ground-points-accuracy/<date>.md.
#
#   lab/ground_points/accuracy.sh       # about 2 min on 2 cores
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points-accuracy "$0" "$@"
fi
. tools/build.sh
use_slither
bin="$SLITHER"
for case in "nodes 0.01" "curve 0.01" "curve 0.005"; do
    read -r points target <<<"$case"
    echo "== ground_points = $points, --accuracy $target"
    out="out/ground_points_accuracy/$points"
    [ "$target" = 0.01 ] || out="$out-$target"
    t0=$(date +%s.%N)
    "$bin" run problems/s_start.toml --out "$out" --no-plots \
        --accuracy "$target" --set "solver.ground_points=\"$points\"" 2>&1 | grep -E "^accuracy $target|v_s/v_m ="
    t1=$(date +%s.%N)
    echo "elapsed $(echo "$t1 - $t0" | bc) s"
    if [ "$points" = curve ]; then
        echo "runs (elements, step s, v_s/v_m, wall s):"
        jq -r '.accuracy.runs | sort_by(.elements, -.dt)[] | "  \(.elements) \(.dt) \(.v_s_over_v_m * 1e6 | round / 1e6) \(.wall_time_s * 100 | round / 100)"' "$out/summary.json"
    fi
done
