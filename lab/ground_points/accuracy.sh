#!/usr/bin/env bash
# `slither run problems/s_start.toml --accuracy 0.01` with ground contact at the nodes and on
# the curve ([solver] ground_points), one after the other: the model each chooses, its
# estimate and answer, and the elapsed time; kept as the dated record
# docs/results/ground-points-accuracy/<date>.md.
#
#   lab/ground_points/accuracy.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points-accuracy "$0" "$@"
fi
. tools/build.sh
use_slither
bin="$SLITHER"
for points in nodes curve; do
    echo "== ground_points = $points"
    t0=$(date +%s.%N)
    "$bin" run problems/s_start.toml --out "out/ground_points_accuracy/$points" --no-plots \
        --accuracy 0.01 --set "solver.ground_points=\"$points\"" 2>&1 | grep -E "^accuracy 0.01|v_s/v_m ="
    t1=$(date +%s.%N)
    echo "elapsed $(echo "$t1 - $t0" | bc) s"
done
