#!/usr/bin/env bash
# `slither run problems/s_start.toml --accuracy TARGET --no-plots` against the S-start's
# converged v_s/v_m, kept as a dated record docs/results/accuracy-s-start/<date>.md: the chosen
# mesh and step, the reported value, the estimate, the actual error against the converged
# value, every probe run and the probes' total wall time.
#
#   lab/accuracy_s_start/accuracy_s_start.sh [TARGET]        # default 0.01
#
# The converged value, on the bundled file's damped rod (rod.damping_time = 10 ms) with its
# ground contact on the curve ([solver] ground_points = "curve", the bundled file's since issue
# 53): records ground-points-800 of 2026-12-06, the tenth to twelfth (800 elements: implicit
# Euler at 2.5e-4 and 5e-4 s, 0.32211 and 0.32216; BDF2 at 5e-4 s, 0.32245), ground-points
# (400 elements, implicit Euler at 2.5e-4 s, 0.32239) and converged-s-start (400 elements,
# implicit Euler's mean of 6 runs at small steps, 0.32241). The actual error is reported
# against each of these. SLITHER names a built binary to use instead of building one
# (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh accuracy-s-start "$0" "$@"
fi
target="${1:-0.01}"
. tools/build.sh
use_slither
slither="$SLITHER"
out="out/accuracy_s_start"
t0="$(date +%s.%N)"
"$slither" run problems/s_start.toml --accuracy "$target" --no-plots --quiet --out "$out"
t1="$(date +%s.%N)"
echo "whole command: $(awk "BEGIN { printf \"%.1f s\", $t1 - $t0 }")"
jq -r --argjson refs '[[0.32211, "800 el., implicit Euler 2.5e-4 s"], [0.32216, "800 el., implicit Euler 5e-4 s"], [0.32245, "800 el., BDF2 5e-4 s"], [0.32239, "400 el., implicit Euler 2.5e-4 s"], [0.32241, "400 el., implicit Euler, mean of 6 runs at small steps"]]' '
  .accuracy as $a | .v_s_over_v_m as $v |
  "probes:",
  ($a.runs[] | "  \(.elements) el., dt \(.dt // "-") s, tolerance \(.error_tolerance // "-"): v_s/v_m \(.v_s_over_v_m), \(.steps) steps, \(.wall_time_s) s, \(.status)"),
  "chosen: \($a.elements) el., dt \($a.dt // "-") s, tolerance \($a.error_tolerance // "-")",
  "answer v_s/v_m: \($v)",
  "estimated error: \($a.estimated_error) (time \($a.time_error), mesh \($a.mesh_error)), met \($a.met)",
  "extrapolated: \($a.v_s_over_v_m_extrapolated) +- \($a.v_s_over_v_m_extrapolated_uncertainty)",
  "runs: \($a.runs | length), total wall time \($a.wall_time_total_s) s, of it probes \($a.probes_wall_time_s) s; elapsed \($a.elapsed_s) s (runs in parallel)",
  ($refs[] | "actual error against \(.[0]) (\(.[1])): \((($v / .[0]) - 1) | fabs), estimate / actual \($a.estimated_error / ((($v / .[0]) - 1) | fabs))")
' "$out/summary.json"
