#!/usr/bin/env bash
# The bundled gait design studies, each from scratch: Nelder-Mead
# (problems/optimize_s_start.toml) and the reflecting particle swarm with seed 1
# (problems/optimize_s_start_pso.toml), 40 evaluations each on the bundled S-start. Prints for
# each the start and the best point (stress, sigma, v_m, v_s, v_s/v_m, writhe, heading), the
# evaluation that found it, the termination and the wall time, and the swarm's wall time over
# Nelder-Mead's. Kept as a dated record docs/results/gait-design/<date>.md.
#
#   lab/gait_design/gait_design.sh            # a few minutes on 2 cores
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh gait-design "$0" "$@"
fi
. tools/build.sh
use_slither
slither="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
for study in optimize_s_start optimize_s_start_pso; do
    "$slither" optimize "problems/$study.toml" --out "$tmp/$study" --quiet
    jq -r --arg s "$study" '
      def pt: "stress \(.stress) Pa, sigma \(.sigma), v_m \(.speed) m/s: v_s \(.v_s) m/s, v_s/v_m \(.v_s_over_v_m), writhe max \(.writhe_max), heading \(.displacement_angle_deg) deg, regime \(.regime)";
      "== \($s) (\(.method), \(.evaluations) evaluations, \(.simulations) simulated, \(.failed) failed)",
      "start: \(.initial | pt)",
      "best:  \(.best | if . == null then "none within the heading limit" else ("evaluation \(.eval): " + pt) end)",
      "gain: \(.v_s_gain) m/s; on bound: \(.on_bound); termination: \(.termination)",
      "wall time: \(.wall_time_s) s"
    ' "$tmp/$study/optimum.json"
done
nm="$(jq .wall_time_s "$tmp/optimize_s_start/optimum.json")"
pso="$(jq .wall_time_s "$tmp/optimize_s_start_pso/optimum.json")"
awk -v a="$pso" -v b="$nm" 'BEGIN { printf "swarm / Nelder-Mead wall time: %.2f\n", a / b }'
