#!/usr/bin/env bash
# The bundled S-start's headline numbers (v_s/v_m, heading, regime, steps, Newton iterations,
# wall time) from one `slither run problems/s_start.toml`, kept as a dated record
# docs/results/s-start/<date>.md. About 1 s of simulation after the build.
#
#   lab/s_start_report/s_start_report.sh [PROBLEM.toml]     # default problems/s_start.toml
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh s-start "$0" "$@"
fi
problem="${1:-problems/s_start.toml}"
. tools/build.sh
use_slither
slither="$SLITHER"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
"$slither" run "$problem" --out "$out" --quiet --no-plots
python3 - "$out/summary.json" "$problem" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"problem                 {sys.argv[2]}")
for key in ("status", "regime", "v_s", "v_s_over_v_m", "displacement_angle_deg", "writhe_max",
            "max_elevation_over_a", "steps", "newton_iterations_mean", "wall_time_s"):
    print(f"{key:24s}{s[key]}")
print(f"{'conic_solves':24s}{s['stats']['conic_solves']}")
print(f"{'semismooth_fallbacks':24s}{s['stats']['semismooth_fallbacks']}")
print(f"{'semismooth_retries':24s}{s['stats']['semismooth_retries']}")
print(f"{'wall s per simulated s':24s}{s['wall_time_s'] / s['t_final']:.3f}")
PY
