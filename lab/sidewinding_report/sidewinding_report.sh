#!/usr/bin/env bash
# Sidewinding measured per cycle (the periodic observables of summary.json): the bundled
# problems/sidewinding.toml, the same at twice the elements, at half the step and at both, and
# the oblique scene it replaced (tests/fixtures/sidewinding_oblique.toml), kept as a dated
# record docs/results/sidewinding/<date>.md. Per cycle after the settling one: centroid
# displacement over L, travel angle against the cycle-mean tail-to-head axis, that axis' turn,
# lateral speed over v_m, the stationary share of the contact time and the contact patches;
# then the largest change of each between the bundled scene and the refined runs. About a
# minute of simulation on 2 cores after the build.
#
#   lab/sidewinding_report/sidewinding_report.sh
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh sidewinding "$0" "$@"
fi
. tools/build.sh
use_slither
slither="$SLITHER"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
base=problems/sidewinding.toml
n="$(sed -n 's/^elements = \([0-9]*\)$/\1/p' "$base")"
twice="s/^elements = $n\$/elements = $((2 * n))/"
sed -e "$twice" "$base" > "$out/elements.toml"
sed -e 's/^dt = 2e-3$/dt = 1e-3/' "$base" > "$out/step.toml"
sed -e "$twice" -e 's/^dt = 2e-3$/dt = 1e-3/' "$base" > "$out/both.toml"
for f in elements step both; do
    if cmp -s "$base" "$out/$f.toml"; then
        echo "sidewinding_report.sh: could not refine $base ($f)" >&2
        exit 1
    fi
done
runs=("oblique:tests/fixtures/sidewinding_oblique.toml" "bundled:$base"
      "elements_x2:$out/elements.toml" "dt_half:$out/step.toml" "both:$out/both.toml")
for r in "${runs[@]}"; do
    name="${r%%:*}"
    "$slither" run "${r#*:}" --out "$out/$name" --quiet --no-plots
done
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
names = ["oblique", "bundled", "elements_x2", "dt_half", "both"]
runs = {n: json.load(open(f"{out}/{n}/summary.json")) for n in names}
keys = [("displacement_over_length", "displacement (L)", "{:.3f}"),
        ("travel_angle_deg", "travel angle (deg)", "{:.1f}"),
        ("turn_deg", "turn (deg)", "{:+.2f}"),
        ("lateral_speed_over_v_m", "lateral speed (v_m)", "{:.3f}"),
        ("stationary_contact_share", "stationary share", "{:.3f}"),
        ("stationary_body_fraction", "body in stationary contact", "{:.3f}"),
        ("contact_patches_mean", "patches", "{:.2f}")]
for n in names:
    s = runs[n]
    p = s["periodic"]
    print(f"\n{n}: {s['problem'].split('/')[-1] if n in ('oblique', 'bundled') else n}, "
          f"{s['steps']} steps in {s['wall_time_s']:.1f} s, period {p['period']} s")
    print("| cycle | " + " | ".join(k[1] for k in keys) + " |")
    print("|---" * (len(keys) + 1) + "|")
    for c in p["cycles"]:
        print(f"| {c['index']} | " + " | ".join(f.format(c[k]) for k, _, f in keys) + " |")
    print(f"sidewinding: {p['sidewinding']}; failed: " + (", ".join(
        f"{c['quantity']} {c['value']:.3f} (needs {c['op']} {c['threshold']})"
        for c in p["sidewinding_checks"] if not c["holds"]) or "none"))
print("\nLargest change per cycle against the bundled scene:")
b = runs["bundled"]["periodic"]["cycles"]
for n in ["elements_x2", "dt_half", "both"]:
    r = runs[n]["periodic"]["cycles"]
    da = max(abs(x["travel_angle_deg"] - y["travel_angle_deg"]) for x, y in zip(b, r))
    dt = max(abs(x["turn_deg"] - y["turn_deg"]) for x, y in zip(b, r))
    rel = lambda k: max(abs(y[k] / x[k] - 1) for x, y in zip(b, r))
    print(f"{n}: travel angle {da:.2f} deg, turn {dt:.2f} deg, displacement "
          f"{100 * rel('displacement_over_length'):.1f} %, lateral speed "
          f"{100 * rel('lateral_speed_over_v_m'):.1f} %, stationary share "
          f"{100 * rel('stationary_contact_share'):.1f} %")
PY
