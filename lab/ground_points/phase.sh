#!/usr/bin/env bash
# The bundled phase study (problems/phase_s_start.toml, [accuracy] target 1.5 %) with ground
# contact at the nodes and on the curve ([solver] ground_points): the model each selection
# chooses, the study's elapsed time, and the cells whose label changes (phase_compare.py).
#   1. On the study's base before this comparison (problems/s_start_coarse.toml, an elastic
#      rod): the curve's selection alone (`slither run --accuracy 0.015`, the selection the
#      study makes).
#   2. On the base with the bundled S-start's damping time (rod.damping_time = 10 ms, which
#      problems/phase_s_start_base.toml now has): both whole studies, one after the other.
# Kept as the dated record docs/results/ground-points-phase/<date>.md.
#
#   lab/ground_points/phase.sh          # about 10 min on 2 cores
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points-phase "$0" "$@"
fi
. tools/build.sh
use_slither
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# The model a selection chose: from a study's accuracy.json (`.selection`) or a run's
# summary.json (`.accuracy`).
choice() {
    jq -r '(.selection // .accuracy) as $s | "chosen: \($s.elements // .elements) elements, \($s.integrator) at \($s.dt // .dt) s, estimate \($s.estimated_error * 10000 | round / 100) %, probes \($s.probes_wall_time_s * 10 | round / 10) s"' "$1"
}
echo "== 1. elastic base (problems/s_start_coarse.toml), contact on the curve: the selection"
t0="$(date +%s.%N)"
"$SLITHER" run problems/s_start_coarse.toml --out "$tmp/elastic_curve" --no-plots --quiet \
    --accuracy 0.015 --set solver.ground_points='"curve"'
t1="$(date +%s.%N)"
choice "$tmp/elastic_curve/summary.json"
echo "elapsed $(awk "BEGIN { printf \"%.1f\", $t1 - $t0 }") s (the selection and the chosen model's run)"
for points in nodes curve; do
    echo
    echo "== 2. base with damping time 10 ms, contact: $points"
    t0="$(date +%s.%N)"
    "$SLITHER" phase problems/phase_s_start.toml --out "$tmp/damped_$points" --quiet \
        --set rod.damping_time=0.01 --set solver.ground_points="\"$points\""
    t1="$(date +%s.%N)"
    choice "$tmp/damped_$points/accuracy.json"
    # (The cells' own wall times: phase_compare.py's last line.)
    echo "study elapsed $(awk "BEGIN { printf \"%.1f\", $t1 - $t0 }") s"
done
echo
python3 lab/self_contact_phase_verified/phase_compare.py "$tmp/damped_nodes/phase.csv" \
    "$tmp/damped_curve/phase.csv" "nodes" "curve"
