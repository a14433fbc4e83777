#!/usr/bin/env bash
# PyElastica 1.0's points on the work-precision chart of its own S-start scene
# (problems/pyelastica_s_start.toml), each against PyElastica's own converged v_s/v_m, beside
# slither's lines against slither's converged value (the two models differ: PyElastica's rod
# is damped and its ground is a penalty spring, so each code is judged against itself).
#
#   lab/work_precision_pe/work_precision_pe.sh            # both stages below, one record each
#   lab/work_precision_pe/work_precision_pe.sh runs       # stage 1 only
#   lab/work_precision_pe/work_precision_pe.sh chart      # stage 2 only, from stage 1's CSV
#
# 1. runs (record pyelastica-convergence, about 15 minutes): compare/pyelastica_s_start.py
#    over the whole 4 s at 50, 100 and 200 elements at PyElastica's largest stable step and at
#    half of it (the points), at 400 elements at its largest stable step 1.8e-5 and at 9e-6,
#    and at 800 elements at its largest stable step 9e-6. From 50 to 800 elements each
#    doubling halves the change of v_s/v_m (printed) and 400 and 800 elements still differ by
#    more than 1 %, so its converged value is taken as the first-order extrapolation
#    2 v_800 - v_400 (a 1600-element run at 4.5e-6 s lies 1.45 % above it: the guide,
#    speed-accuracy.md, says what that leaves open) (both at 9e-6 s; the step's share is the printed change from
#    1.8e-5 to 9e-6 s at 400 elements). The largest stable steps were measured by
#    compare/stable_steps.sh. v_s/v_m is the net definition, the centre of mass's displacement
#    along the initial head direction over T v_m, as slither's v_s_over_v_m.
#    Writes docs/images/work_precision_pyelastica_s_start_external.csv (the format of
#    `slither chart work-precision --external`), every run.
# 2. chart (record work-precision-pyelastica, several minutes): `slither chart work-precision
#    problems/pyelastica_s_start.toml --external` that CSV; figures and the chart's CSV to
#    docs/images/work_precision_pyelastica_s_start*. The chart's wall axis is the wall time of
#    the whole scene (T = 4 s); PyElastica's points are its wall seconds per simulated second
#    times T.
#
# PyElastica comes from compare/.venv (created by compare/run.sh, or here the same way).
# SLITHER names a built binary to use instead of building one (tools/build.sh). The
# machine's load is in each record; wall times on a shared machine are indicative.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
stage="${1:-all}"
case "$stage" in
    all)
        if [ -z "${SLITHER_RECORDING:-}" ]; then
            "$0" runs
            exec "$0" chart
        fi ;;
    runs)
        if [ -z "${SLITHER_RECORDING:-}" ]; then
            exec tools/record.sh pyelastica-convergence "$0" runs
        fi ;;
    chart)
        if [ -z "${SLITHER_RECORDING:-}" ]; then
            exec tools/record.sh work-precision-pyelastica "$0" chart
        fi ;;
    *) echo "usage: lab/work_precision_pe/work_precision_pe.sh [runs|chart]" >&2; exit 2 ;;
esac
csv="docs/images/work_precision_pyelastica_s_start_external.csv"
out="out/work_precision_pe"
mkdir -p "$out" docs/images

if [ "$stage" = runs ]; then
    venv="compare/.venv"
    if [ ! -x "$venv/bin/python" ]; then
        python3 -m venv "$venv"
        "$venv/bin/pip" install --quiet --upgrade pip
        "$venv/bin/pip" install --quiet "pyelastica==1.0.0" numpy \
            || "$venv/bin/pip" install --quiet "pyelastica>=1,<2" numpy
    fi
    echo "PyElastica $("$venv/bin/python" -c 'import importlib.metadata as m; print(m.version("pyelastica"))'), numba $("$venv/bin/python" -c 'import numba; print(numba.__version__)')"
    # ELEMENTS:DT pairs; the first step of each mesh is its largest stable step.
    runs=(50:1e-4 50:5e-5 100:7e-5 100:3.5e-5 200:3.5e-5 200:1.75e-5 400:1.8e-5 400:9e-6 800:9e-6)
    for r in "${runs[@]}"; do
        IFS=: read -r n dt <<< "$r"
        echo "== PyElastica, $n elements, dt $dt (load $(cut -d' ' -f1-3 /proc/loadavg))"
        "$venv/bin/python" compare/pyelastica_s_start.py --elements "$n" --dt "$dt" \
            --out "$out/pe_${n}_$dt.json" >/dev/null
    done
    "$venv/bin/python" - "$out" "$csv" "${runs[@]}" <<'EOF'
import json, os, sys
out, csv, runs = sys.argv[1], sys.argv[2], sys.argv[3:]
net = "v_s_over_v_m"  # slither's definition (initial tail-to-head direction)
res = {}
for r in runs:
    n, dt = r.split(":")
    res[(int(n), dt)] = json.load(open(os.path.join(out, f"pe_{n}_{dt}.json")))
print("| elements | dt (s) | stable | v_s/v_m (net) | v_s/v_m (heading) | wall s | wall s per simulated s |")
print("|---|---|---|---|---|---|---|")
for (n, dt), j in res.items():
    print(f"| {n} | {dt} | {j['stable']} | {j[net]:.5f} | {j['v_head_instantaneous_over_v_m']:.5f} "
          f"| {j['wall_time_s']:.2f} | {j['wall_per_sim_second']:.3f} |")
bad = [k for k, j in res.items() if not j["stable"]]
if bad:
    sys.exit(f"unstable runs: {bad}")
# The converged value. The mesh differences at each mesh's finer step halve with every
# doubling of the mesh (first order; printed), and 400 and 800 elements still differ by more
# than 1 %, so the finest run is not the converged value: it is the first-order Richardson
# extrapolation of 400 and 800 elements at the same step, 2 v_800 - v_400.
fine = {n: res[max((k for k in res if k[0] == n), key=lambda k: -float(k[1]))][net]
        for n in sorted({k[0] for k in res})}
meshes = sorted(fine)
diffs = [fine[b] - fine[a] for a, b in zip(meshes, meshes[1:])]
print("mesh differences of v_s/v_m at each mesh's finer step: " + ", ".join(
    f"{a}->{b} {d:+.5f}" for a, b, d in zip(meshes, meshes[1:], diffs)))
print("ratios of successive differences (0.5: first order, 0.25: second): " + ", ".join(
    f"{d1 / d0:.2f}" for d0, d1 in zip(diffs, diffs[1:])))
v400, v800 = res[(400, "9e-6")][net], res[(800, "9e-6")][net]
ref = 2 * v800 - v400
r_last = diffs[-1] / diffs[-2]
ref_r = v800 + diffs[-1] * r_last / (1 - r_last)
time = abs(v400 / res[(400, "1.8e-5")][net] - 1)
print(f"converged v_s/v_m (net): {ref:.5f}, first-order extrapolation 2 v_800 - v_400 at dt 9e-6 s "
      f"(with the last observed ratio {r_last:.2f} instead of 0.5: {ref_r:.5f}, "
      f"{100 * abs(ref_r / ref - 1):.2f} % apart); 800 elements differ from it by "
      f"{100 * abs(v800 / ref - 1):.2f} %, 400 and 800 elements by {100 * abs(v400 / v800 - 1):.2f} %; "
      f"400 elements at 1.8e-5 and 9e-6 s by {100 * time:.2f} % (step)")
for n in meshes:
    ks = sorted((k for k in res if k[0] == n), key=lambda k: -float(k[1]))
    print(f"{n} elements: " + ", ".join(
        f"dt {k[1]}: v_s/v_m {res[k][net]:.5f}, error {100 * abs(res[k][net] / ref - 1):.2f} %, "
        f"{res[k]['wall_per_sim_second']:.3f} s per simulated s" for k in ks))
with open(csv, "w") as f:
    f.write("scene,code,elements,dt_s,v_s_over_v_m,reference_v_s_over_v_m,wall_s_per_simulated_s\n")
    for (n, dt), j in res.items():
        f.write(f"pyelastica_s_start.toml,{j['code']},{n},{dt},{j[net]:.6f},{ref:.6f},"
                f"{j['wall_per_sim_second']:.4f}\n")
print(f"wrote {csv}")
EOF
    exit 0
fi

# Stage 2: the chart.
[ -f "$csv" ] || { echo "lab/work_precision_pe/work_precision_pe.sh: $csv is missing: run 'lab/work_precision_pe/work_precision_pe.sh runs' first" >&2; exit 2; }
. tools/build.sh
use_slither
slither="$SLITHER"
echo "PyElastica's points ($csv):"
cat "$csv"
"$slither" chart work-precision problems/pyelastica_s_start.toml --out "$out/chart" --external "$csv"
cp "$out/chart/gait_precision.png" docs/images/work_precision_pyelastica_s_start.png
cp "$out/chart/gait_precision_centreline.png" docs/images/work_precision_pyelastica_s_start_centreline.png
cp "$out/chart/gait_precision.csv" docs/images/work_precision_pyelastica_s_start.csv
echo "figures: docs/images/work_precision_pyelastica_s_start.png, docs/images/work_precision_pyelastica_s_start_centreline.png"
