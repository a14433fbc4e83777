#!/usr/bin/env bash
# `slither run problems/s_start.toml --accuracy TARGET --no-plots` against the S-start's
# converged v_s/v_m, kept as a dated record docs/results/accuracy-s-start/<date>.md: the chosen
# mesh and step, the reported value, the estimate, the actual error against the converged
# value, every probe run and the probes' total wall time.
#
#   lab/accuracy_s_start/accuracy_s_start.sh [TARGET]        # default 0.01
#
# The converged value: implicit Euler at 400 elements gives 0.32053, 0.32024, 0.31972, 0.31965
# at 2.5e-4, 5e-4, 1.25e-4, 6.25e-5 s (the selection's own runs, and records
# s-start-reference); BDF2 at fixed steps of 2.1e-3 s and below, 0.31727 to 0.32134 (record
# converged-s-start, whose runs at small steps pool to 0.31892). The actual error is reported
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
jq -r --argjson refs '[[0.31965, "400 el., 6.25e-5 s"], [0.3202, "400 el., 5e-4 s"], [0.32053, "400 el., 2.5e-4 s"], [0.31727, "400 el., BDF2 1.8e-3 s"], [0.32134, "400 el., BDF2 2.25e-4 s"], [0.31892, "400 el., mean of 15 runs at small steps"]]' '
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
