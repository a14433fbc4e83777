#!/usr/bin/env bash
# The S-start on PyElastica's scene (problems/pyelastica_s_start.toml) with both codes on the
# same muscle physics (PyElastica's muscles as a time-dependent rest curvature, issue 50), over
# the mesh: each code's extrapolated limit of v_s/v_m, the work-precision chart and the cost
# ratios at equal accuracy. Three stages, each kept as a dated record by tools/record.sh:
#
#   lab/pyelastica_same_physics/pyelastica_same_physics.sh pe        # record pyelastica-same-physics-pe
#   lab/pyelastica_same_physics/pyelastica_same_physics.sh slither   # record pyelastica-same-physics-slither
#   lab/pyelastica_same_physics/pyelastica_same_physics.sh report    # record pyelastica-same-physics
#   lab/pyelastica_same_physics/pyelastica_same_physics.sh differences   # record pyelastica-model-differences
#   lab/pyelastica_same_physics/pyelastica_same_physics.sh pe-like   # record pyelastica-same-physics-pe-like
#
# The two run stages write JSON into out/same_physics/ and may run at the same time (one core
# each on a 2-core machine); `report` reads them. PE_RUNS / SL_RUNS (space-separated
# ELEMENTS:DT) replace the default lists below.
#
# pe: compare/pyelastica_s_start.py (curvature muscles, slither's v_s beside the
#   instantaneous-head form) over the whole 4 s at 50, 100, 200, 400 and 800 elements, at the
#   largest stable step measured by compare/stable_steps.sh (1e-4, 7e-5, 3.5e-5, 1.8e-5,
#   9e-6 s) and at half of it; at 50, 100 and 200 elements also at the next larger step
#   (1.2e-4, 8e-5, 4e-5 s), which must fling the rod (the limit holds for these muscles too).
# slither: `slither run` on copies of problems/pyelastica_s_start.toml with only `elements`
#   and `dt` changed, implicit Euler (the file's integrator), at 50 to 800 elements.
# report: the tables, each code's limit by Richardson extrapolation over its three finest
#   meshes at its finest step (observed order; the uncertainty is the spread of the
#   extrapolations with orders 1 and 2 and the observed one, plus the finest step's own change
#   from the step before), the difference of the limits, the cost of each code's cheapest run
#   within 1 % and 2 % of its own limit (and of the other's), the ratios, a CSV of every run
#   and the chart docs/images/pyelastica_same_physics.png (matplotlib from compare/.venv).
# differences: PyElastica's model moved toward slither's one step at a time, at DIFF_ELEMENTS
#   (default 200) elements and DIFF_DT (default 3.5e-5 s, the largest stable step there):
#   the ground spring 10 and 100 times stiffer (its damping kept half-critical), the rod's
#   damping 0.02 -> 0, static friction equal to kinetic (slither's Coulomb law has one
#   coefficient); each change alone and cumulatively; slither's value at the same mesh beside.
# pe-like: PyElastica with all three changes (ground 100x, no rod damping, static = kinetic
#   friction) over the mesh, at the largest stable steps of `pe` (and half of it up to 400
#   elements): whether its limit moves onto slither's. `report` includes it when present.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
stage="${1:-}"
case "$stage" in
    pe|slither|pe-like)
        if [ -z "${SLITHER_RECORDING:-}" ]; then
            exec tools/record.sh "pyelastica-same-physics-$stage" "$0" "$stage"
        fi ;;
    report)
        if [ -z "${SLITHER_RECORDING:-}" ]; then
            exec tools/record.sh pyelastica-same-physics "$0" report
        fi ;;
    differences)
        if [ -z "${SLITHER_RECORDING:-}" ]; then
            exec tools/record.sh pyelastica-model-differences "$0" differences
        fi ;;
    *) echo "usage: lab/pyelastica_same_physics/pyelastica_same_physics.sh pe|slither|pe-like|report|differences" >&2; exit 2 ;;
esac
out="out/same_physics"
mkdir -p "$out" docs/images
venv="compare/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet --upgrade pip
    "$venv/bin/pip" install --quiet "pyelastica==1.0.0" numpy \
        || "$venv/bin/pip" install --quiet "pyelastica>=1,<2" numpy
fi

if [ "$stage" = pe ] || [ "$stage" = pe-like ]; then
    echo "PyElastica $("$venv/bin/python" -c 'import importlib.metadata as m; print(m.version("pyelastica"))'), numba $("$venv/bin/python" -c 'import numba; print(numba.__version__)')"
    if [ "$stage" = pe ]; then
        runs=(${PE_RUNS:-50:1e-4 50:5e-5 50:1.2e-4 100:7e-5 100:3.5e-5 100:8e-5 200:3.5e-5 200:1.75e-5 200:4e-5 400:1.8e-5 400:9e-6 800:9e-6 800:4.5e-6})
        prefix=pe
        opts=()
    else
        runs=(${PE_RUNS:-50:1e-4 50:5e-5 100:7e-5 100:3.5e-5 200:3.5e-5 200:1.75e-5 400:1.8e-5 400:9e-6 800:9e-6})
        prefix=like
        opts=(--ground-stiffness 100 --damping none --static-friction)
    fi
    for r in "${runs[@]}"; do
        IFS=: read -r n dt <<< "$r"
        echo "== PyElastica ${opts[*]}, $n elements, dt $dt (load $(cut -d' ' -f1-3 /proc/loadavg))"
        "$venv/bin/python" compare/pyelastica_s_start.py --elements "$n" --dt "$dt" "${opts[@]}" \
            --out "$out/${prefix}_${n}_$dt.json" > /dev/null
        "$venv/bin/python" - "$out/${prefix}_${n}_$dt.json" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
print(f"   v_s/v_m {j['v_s_over_v_m']:.5f} (instantaneous head "
      f"{j['v_head_instantaneous_over_v_m']:.5f}), stable {j['stable']}, max height "
      f"{j['max_height_over_a']:.3g} a, {j['wall_per_sim_second']:.3f} wall s per simulated s, "
      f"shape check {j.get('shape_check')}")
EOF
    done
    exit 0
fi

if [ "$stage" = slither ]; then
    . tools/build.sh
    use_slither
    slither="$SLITHER"
    runs=(${SL_RUNS:-50:4e-3 50:2e-3 50:1e-3 50:5e-4 50:2.5e-4 100:4e-3 100:2e-3 100:1e-3 100:5e-4 100:2.5e-4 200:4e-3 200:2e-3 200:1e-3 200:5e-4 200:2.5e-4 400:2e-3 400:1e-3 400:5e-4 800:1e-3 800:5e-4})
    for r in "${runs[@]}"; do
        IFS=: read -r n dt <<< "$r"
        f="$out/sl_${n}_$dt.toml"
        sed -e "s/^elements = [0-9]* *\(#.*\)\?$/elements = $n/" -e "s/^dt = .*/dt = $dt/" \
            problems/pyelastica_s_start.toml > "$f"
        grep -q "^elements = $n$" "$f"
        grep -q "^dt = $dt$" "$f"
        echo "== slither, $n elements, implicit Euler dt $dt (load $(cut -d' ' -f1-3 /proc/loadavg))"
        "$slither" run "$f" --out "$out/sl_${n}_$dt" --no-plots --quiet
        "$venv/bin/python" - "$out/sl_${n}_$dt/summary.json" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
print(f"   v_s/v_m {j['v_s_over_v_m']:.5f}, {j['steps']} steps, {j['wall_time_s']:.2f} wall s")
EOF
    done
    exit 0
fi

if [ "$stage" = differences ]; then
    n="${DIFF_ELEMENTS:-200}"
    dt="${DIFF_DT:-3.5e-5}"
    d="$out/differences_$n"
    mkdir -p "$d"
    # name: the script's options
    variants=(
        "baseline:"
        "ground_10x:--ground-stiffness 10"
        "ground_100x:--ground-stiffness 100"
        "damping_0:--damping none"
        "static_eq_kinetic:--static-friction"
        "ground_100x+damping_0:--ground-stiffness 100 --damping none"
        "ground_100x+damping_0+static:--ground-stiffness 100 --damping none --static-friction"
    )
    for v in "${variants[@]}"; do
        name="${v%%:*}"
        opts="${v#*:}"
        echo "== PyElastica, $n elements, dt $dt, $name ($opts) (load $(cut -d' ' -f1-3 /proc/loadavg))"
        # shellcheck disable=SC2086
        "$venv/bin/python" compare/pyelastica_s_start.py --elements "$n" --dt "$dt" $opts \
            --out "$d/$name.json" > /dev/null
    done
    "$venv/bin/python" - "$d" "$n" "$out" <<'EOF'
import glob, json, os, sys
d, n, out = sys.argv[1], sys.argv[2], sys.argv[3]
order = ["baseline", "ground_10x", "ground_100x", "damping_0", "static_eq_kinetic",
         "ground_100x+damping_0", "ground_100x+damping_0+static"]
res = {k: json.load(open(os.path.join(d, k + ".json"))) for k in order}
base = res["baseline"]["v_s_over_v_m"]
sl = sorted(glob.glob(os.path.join(out, f"sl_{n}_*", "summary.json")),
            key=lambda f: float(f.split("_")[-1].split("/")[0]))
print(f"| PyElastica at {n} elements | v_s/v_m | change from the baseline | stable | max height / a |"
      " lowest point (m) | direction (deg) | wall s per simulated s |")
print("|---|---|---|---|---|---|---|---|")
for k in order:
    j = res[k]
    v = j["v_s_over_v_m"]
    print(f"| {k.replace('_', ' ')} | {v:.5f} | {100 * (v / base - 1):+.2f} % | {j['stable']} "
          f"| {j['max_height_over_a']:.2f} | {j['min_height_m']:.2e} | "
          f"{j['com_disp_direction_deg']:.1f} | {j['wall_per_sim_second']:.2f} |")
for f in sl:
    j = json.load(open(f))
    print(f"slither at {n} elements, implicit Euler dt {f.split('_')[-1].split('/')[0]}: "
          f"v_s/v_m {j['v_s_over_v_m']:.5f}")
EOF
    exit 0
fi

# report
"$venv/bin/python" compare/same_physics_report.py "$out" docs/images/pyelastica_same_physics
