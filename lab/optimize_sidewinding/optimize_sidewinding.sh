#!/usr/bin/env bash
# The bundled sidewinding study (problems/optimize_sidewinding.toml: the sidewinding margin over
# stress, sigma, v_m, period, spacing and lift, from the scene the bundled one replaced), kept
# as a record under docs/results/sidewinding-optimize/: the study's log, then every
# evaluation's periodic columns from history.csv and the best point. About 40 single-thread
# simulations of 5 to 15 s each.
#
#   lab/optimize_sidewinding/optimize_sidewinding.sh
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh sidewinding-optimize "$0" "$@"
fi
. tools/build.sh
use_slither
slither="$SLITHER"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
RAYON_NUM_THREADS=1 "$slither" optimize problems/optimize_sidewinding.toml --out "$out/study"
python3 - "$out/study" <<'PY'
import csv, json, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(f"{d}/history.csv")))
print("\n| eval | period (s) | spacing (L) | lift | stress (Pa) | sigma (L) | v_m (m/s) | broadside min (deg) | turn max (deg) | displacement min (L) | stationary share min | sidewinding | margin |")
print("|---" * 13 + "|")
for r in rows:
    f = lambda k, p: f"{float(r[k]):.{p}f}"
    print(f"| {r['eval']} | {f('period', 3)} | {f('spacing', 4)} | {f('lift', 3)} | {f('stress', 0)} | {f('sigma', 4)} | {f('speed', 3)} | "
          f"{f('broadside_deg_min', 1)} | {f('turn_deg_max_abs', 2)} | {f('displacement_over_length_min', 3)} | "
          f"{f('stationary_contact_share_min', 3)} | {r['sidewinding']} | {-float(r['objective']):+.3f} |")
o = json.load(open(f"{d}/optimum.json"))
passing = [r for r in rows if r["sidewinding"] == "yes"]
print(f"\n{o['evaluations']} evaluations ({o['simulations']} simulated) in {o['wall_time_s']:.0f} s; "
      f"{len(passing)} sidewinding (first at evaluation {passing[0]['eval'] if passing else '-'}); "
      f"margin {-float(rows[0]['objective']):+.3f} at the start, {-float([r for r in rows if int(r['eval']) == o['best']['eval']][0]['objective']):+.3f} at the best (evaluation {o['best']['eval']})")
PY
