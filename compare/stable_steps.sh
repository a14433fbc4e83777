#!/usr/bin/env bash
# PyElastica 1.0's cost at its largest stable step, per element count, on its own S-start scene
# (compare/pyelastica_s_start.py, the whole 4 s): for each "ELEMENTS:STABLE:UNSTABLE" triple it
# runs the stable step (timed) and the next larger step, which must fling the rod (the run is
# unstable when its positions turn non-finite or the body rises above 50 diameters). Writes
# one CSV row per run. A stable step that is not stable, or an unstable one that is not,
# exits 1 with the row named: the triple is then not PyElastica's limit and must be remeasured.
#
#   compare/stable_steps.sh OUT.csv [ELEMENTS:STABLE:UNSTABLE ...]
#
# Default triples (measured with this script): 50:1e-4:1.2e-4 100:7e-5:8e-5 200:3.5e-5:4e-5
# 400:1.8e-5:2e-5 800:9e-6:1e-5. Uses compare/.venv (created by compare/run.sh).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
[ $# -ge 1 ] || { echo "usage: compare/stable_steps.sh OUT.csv [ELEMENTS:STABLE:UNSTABLE ...]" >&2; exit 2; }
out_csv="$1"; shift
triples=("$@")
[ ${#triples[@]} -gt 0 ] || triples=(50:1e-4:1.2e-4 100:7e-5:8e-5 200:3.5e-5:4e-5 400:1.8e-5:2e-5 800:9e-6:1e-5)
for t in "${triples[@]}"; do
    [[ "$t" =~ ^[0-9]+:[0-9.eE+-]+:[0-9.eE+-]+$ ]] || { echo "compare/stable_steps.sh: '$t' is not ELEMENTS:STABLE:UNSTABLE (e.g. 200:3.5e-5:4e-5)" >&2; exit 2; }
done
py="$here/.venv/bin/python"
[ -x "$py" ] || { echo "compare/stable_steps.sh: $here/.venv is missing: run compare/run.sh once to create it" >&2; exit 2; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
echo "elements,dt,role,stable,max_height_over_a,v_s_over_v_m,wall_per_sim_second,us_per_step" > "$out_csv"
status=0
for t in "${triples[@]}"; do
    IFS=: read -r n stable unstable <<< "$t"
    for role in stable unstable; do
        dt="${!role}"
        "$py" "$here/pyelastica_s_start.py" --elements "$n" --dt "$dt" --out "$tmp/r.json" >/dev/null
        row="$("$py" - "$tmp/r.json" "$n" "$dt" "$role" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
n, dt, role = sys.argv[2:5]
print(f"{n},{dt},{role},{str(r['stable']).lower()},{r['max_height_over_a']:.4g},"
      f"{r['v_s_over_v_m']:.5f},{r['wall_per_sim_second']:.4f},{r['us_per_step']:.2f}")
EOF
)"
        echo "$row" | tee -a "$out_csv"
        got="$(echo "$row" | cut -d, -f4)"
        if { [ "$role" = stable ] && [ "$got" != true ]; } || { [ "$role" = unstable ] && [ "$got" != false ]; }; then
            echo "compare/stable_steps.sh: $n elements at dt $dt was expected $role: $dt is not PyElastica's largest stable step pair; remeasure" >&2
            status=1
        fi
    done
done
exit $status
