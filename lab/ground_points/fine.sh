#!/usr/bin/env bash
# The converged value at 800 elements with each ground contact model ([solver] ground_points):
# the bundled S-start with implicit Euler (or BDF2) at 5e-4 s (or a given step), nodes and
# curve side by side (two processes); v_s/v_m, iterations, fallbacks, halvings, steps taken at
# the nodes (a step that failed on the curve) and wall time of each, to set beside the
# 400-element values of record ground-points. Kept as the dated record
# docs/results/ground-points-800/<date>.md.
#
#   lab/ground_points/fine.sh          # nodes and curve: 20 to 100 min on 2 cores
#   lab/ground_points/fine.sh curve    # one model only (the other's row stands in its record)
#   lab/ground_points/fine.sh --bdf2 curve   # BDF2 instead of implicit Euler
#   lab/ground_points/fine.sh --dt 2.5e-4 curve   # another step (s); --bdf2 first if both
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points-800 "$0" "$@"
fi
. tools/build.sh
use_slither
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
integrator=implicit
if [ "${1:-}" = --bdf2 ]; then
    integrator=bdf2
    shift
fi
dt=5e-4
if [ "${1:-}" = --dt ]; then
    dt="${2:?fine.sh: --dt needs a step in s}"
    shift 2
fi
echo "800 elements, $integrator at $dt s"
models=("$@")
[ ${#models[@]} -gt 0 ] || models=(nodes curve)
for points in "${models[@]}"; do
    case "$points" in nodes | curve) ;; *) echo "fine.sh: unknown model '$points' (nodes or curve)" >&2; exit 2 ;; esac
done
for points in "${models[@]}"; do
    "$SLITHER" run problems/s_start.toml --out "$tmp/$points" --no-plots --quiet --force \
        --set rod.elements=800 --set solver.integrator="\"$integrator\"" --set time.dt="$dt" \
        --set solver.ground_points="\"$points\"" >"$tmp/$points.log" 2>&1 &
done
wait
echo "| contact | v_s/v_m | steps | Newton it/step | conic fallbacks | step halvings | steps at nodes | wall s |"
echo "|---|---|---|---|---|---|---|---|"
for points in "${models[@]}"; do
    # A run that stopped has no v_s/v_m in its summary: its log's last lines say why.
    if jq -e '.v_s_over_v_m != null' "$tmp/$points/summary.json" >/dev/null 2>&1; then
        jq -r --arg p "$points" '"| \($p) | \(.v_s_over_v_m * 100000 | round / 100000) | \(.steps) | \(.newton_iterations_mean * 100 | round / 100) | \(.stats.semismooth_fallbacks) | \(.stats.step_halvings) | \(.stats.ground_point_fallbacks // 0) | \(.wall_time_s * 10 | round / 10) |"' "$tmp/$points/summary.json"
    else
        echo "| $points | failed: $(tail -n 3 "$tmp/$points.log" | tr '\n' ' ') |"
    fi
done
