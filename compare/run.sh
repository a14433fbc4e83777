#!/usr/bin/env bash
# Back-to-back timing of PyElastica 1.0 on its own S-start scene against slither on the same
# scene (problems/pyelastica_s_start.toml), in one window on one machine. Not part of CI.
#
#   compare/run.sh                  # from anywhere; results in compare/out/
#   compare/run.sh --elements 200   # both codes at 200 elements; results in compare/out_200/
#   compare/run.sh --elements 100 --pe-steps "2e-5 4e-5 1e-5"   # other meshes: PyElastica's steps
#
# 1. compare/.venv: a virtual environment with pyelastica==1.0.0 and numpy from PyPI
#    (created once; delete the folder to reinstall; falls back to the newest 1.x if 1.0.0 is gone).
# 2. cargo build --release (honours CARGO_TARGET_DIR).
# 3. PyElastica at dt 2e-5, 1e-4 (its largest stable step) and 1e-5 (for its converged value),
#    timing only the time stepping after an in-process warm-up that compiles numba's kernels;
#    then slither at the file's dt 2e-3 and at 1e-3, 5e-4 (4x smaller) and 1.25e-4 (16x
#    smaller, for its converged value), adaptive BDF2 on both scenes, and the converged
#    S-start (problems/s_start.toml with BDF2 at 5e-3 and 6e-3 s and the semi-smooth contact).
#    All in one window.
# 4. The table: wall seconds per simulated second, the ratio PyElastica / slither, and each
#    row's v_s/v_m error against its own code's converged value: the finest run of that code
#    (PyElastica dt 1e-5, slither dt 1.25e-4), whose own error is bounded by its change from
#    the next coarser run (printed). Time-step error only: neither code is mesh-converged at
#    50 elements.
# With --elements N both codes run at N elements: PyElastica at its own measured steps for
# that mesh (below), slither at the file's steps (an implicit step is set by accuracy, not
# stability).
#
# Every run is kept as a dated record, docs/results/pyelastica-compare/<date>.md (machine,
# with --elements N: pyelastica-compare-N/;
# build, load, the whole output), by tools/record.sh; SLITHER_NO_RECORD=1 skips it.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
args=("$@")
elements=50
pe_steps=""
while [ $# -gt 0 ]; do
    case "$1" in
        --elements) elements="$2"; shift 2 ;;
        --pe-steps) pe_steps="$2"; shift 2 ;;
        *) echo "compare/run.sh: unknown argument $1 (usage: compare/run.sh [--elements N] [--pe-steps "MID MAX FINE"])" >&2; exit 2 ;;
    esac
done
case "$elements" in
    ''|*[!0-9]*) echo "compare/run.sh: --elements must be a positive integer, got '$elements'" >&2; exit 2 ;;
esac
[ "$elements" -ge 4 ] || { echo "compare/run.sh: --elements must be at least 4" >&2; exit 2; }
venv="$here/.venv"
if [ "$elements" = 50 ]; then out="$here/out"; else out="$here/out_$elements"; fi
# PyElastica's steps: an intermediate one, its largest stable step and a fine one (its
# converged value), measured on this scene over the whole 4 s: at 50 elements 2e-5, 1e-4
# (1.2e-4 flings the rod 4,000 diameters up) and 1e-5; at 200 elements 2e-5, 3.5e-5 (4e-5
# flings it 39,000 diameters up) and 1e-5 (within 0.01 % of 2.5e-6).
# Other meshes: pass --pe-steps "MID MAX FINE".
case "$elements" in
    50) pe_steps="${pe_steps:-2e-5 1e-4 1e-5}" ;;
    200) pe_steps="${pe_steps:-2e-5 3.5e-5 1e-5}" ;;
    *) [ -n "${pe_steps:-}" ] || { echo "compare/run.sh: at $elements elements pass --pe-steps \"MID MAX FINE\" (PyElastica's steps; its stability limit is measured for 50 and 200 only)" >&2; exit 2; } ;;
esac
if [ -z "${SLITHER_RECORDING:-}" ] && [ -z "${SLITHER_NO_RECORD:-}" ]; then
    # Records per mesh: pyelastica-compare (50 elements), pyelastica-compare-N otherwise.
    record=pyelastica-compare
    [ "$elements" = 50 ] || record="pyelastica-compare-$elements"
    exec "$repo/tools/record.sh" "$record" "$here/run.sh" "${args[@]}"
fi
cd "$repo"
mkdir -p "$out"
read -r pe_dt_mid pe_dt_max pe_dt_fine <<< "$pe_steps"
export PE_DTS="$pe_dt_mid $pe_dt_max $pe_dt_fine" ELEMENTS="$elements"
echo "elements $elements; PyElastica steps $PE_DTS"

if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet --upgrade pip
    "$venv/bin/pip" install --quiet "pyelastica==1.0.0" numpy \
        || "$venv/bin/pip" install --quiet "pyelastica>=1,<2" numpy
fi
pe_version="$("$venv/bin/python" -c 'import importlib.metadata as m; print(m.version("pyelastica"))')"
echo "PyElastica $pe_version, numba $("$venv/bin/python" -c 'import numba; print(numba.__version__)'), numpy $("$venv/bin/python" -c 'import numpy; print(numpy.__version__)')"

cargo build --release
slither="${CARGO_TARGET_DIR:-$repo/target}/release/slither"

echo "load before: $(cat /proc/loadavg)"
i=0
for dt in $PE_DTS; do
    echo "== PyElastica, $elements elements, dt $dt"
    "$venv/bin/python" "$here/pyelastica_s_start.py" --dt "$dt" --elements "$elements" \
        --out "$out/pyelastica_$i.json" >/dev/null
    i=$((i + 1))
done
# The scene files at N elements (the files' own meshes are 50 and 100).
for name in pyelastica_s_start s_start; do
    sed -e "s/^elements = [0-9]* *\(#.*\)\?$/elements = $elements/" "problems/$name.toml" > "$out/$name.toml"
    grep -q "^elements = $elements" "$out/$name.toml"
done
echo "== slither, problems/pyelastica_s_start.toml at $elements elements"
"$slither" run "$out/pyelastica_s_start.toml" --out "$out/slither" --no-plots --quiet
for dt in 1e-3 5e-4 1.25e-4; do
    echo "== slither, dt $dt"
    sed -e "s/^dt = 2e-3/dt = $dt/" "$out/pyelastica_s_start.toml" > "$out/slither_dt$dt.toml"
    grep -q "^dt = $dt" "$out/slither_dt$dt.toml"
    "$slither" run "$out/slither_dt$dt.toml" --out "$out/slither_dt$dt" --no-plots --quiet
done
# Adaptive BDF2 at its default error tolerance: on PyElastica's scene and on the
# bundled S-start (problems/s_start.toml), each as the file with integrator and adaptive set.
for name in pyelastica_s_start s_start; do
    echo "== slither, BDF2 adaptive, problems/$name.toml"
    f="$out/${name}_bdf2_adaptive.toml"
    sed -e 's/^dt = .*/dt = 2e-3\nadaptive = true/' "$out/$name.toml" > "$f"
    # (problems/s_start.toml has a [solver] table with the integrator already.)
    if grep -q '^integrator = ' "$f"; then
        sed -i 's/^integrator = .*/integrator = "bdf2"/' "$f"
    else
        sed -i 's/^\[ground\]/[solver]\nintegrator = "bdf2"\n\n[ground]/' "$f"
    fi
    grep -q '^adaptive = true' "$out/${name}_bdf2_adaptive.toml"
    grep -q '^integrator = "bdf2"' "$out/${name}_bdf2_adaptive.toml"
    "$slither" run "$out/${name}_bdf2_adaptive.toml" --out "$out/${name}_bdf2_adaptive" \
        --no-plots --quiet
done
# The converged S-start: problems/s_start.toml at N elements with BDF2 at fixed steps and the
# semi-smooth contact Newton, at 5e-3 s and at 6e-3 s, the cheapest step measured at 200
# elements (9,669 Newton iterations against 10,806 at 5e-3 s; 7.2e-3 s takes 9,866, 8.5e-3 s
# 9,279 with a conic fallback). Both are within 0.6 % of the converged 0.3189 (guide, "Speed
# against accuracy").
for cdt in 5e-3 6e-3; do
    echo "== slither, converged S-start: problems/s_start.toml, BDF2 at $cdt s, semi-smooth contact"
    f="$out/s_start_converged_$cdt.toml"
    sed -e "s/^dt = .*/dt = $cdt/" -e 's/^integrator = .*/integrator = "bdf2"\ncontact = "semi-smooth"/' \
        "$out/s_start.toml" > "$f"
    grep -q "^dt = $cdt" "$f"
    grep -q '^contact = "semi-smooth"' "$f"
    "$slither" run "$f" --out "$out/s_start_converged_$cdt" --no-plots --quiet
done
echo "load after: $(cat /proc/loadavg)"

"$venv/bin/python" - "$out" "$repo/problems/pyelastica_s_start.toml" <<'EOF'
import json, os, sys, tomllib
out, problem = sys.argv[1], sys.argv[2]
with open(problem, "rb") as f:
    p = tomllib.load(f)
sl = json.load(open(os.path.join(out, "slither", "summary.json")))
pe_dts = os.environ["PE_DTS"].split()
elements = int(os.environ["ELEMENTS"])
# Keys: "mid" (2e-5 at 50 elements), "max" (the largest stable step), "fine" (converged).
pe = {key: json.load(open(os.path.join(out, f"pyelastica_{i}.json")))
      for i, key in enumerate(("mid", "max", "fine"))}
sl_fine = {dt: json.load(open(os.path.join(out, f"slither_dt{dt}", "summary.json")))
           for dt in ("1e-3", "5e-4", "1.25e-4")}
net = "v_s_over_v_m"  # slither's definition (initial tail-to-head direction)
# Each code's converged value: its finest run; the change from the next coarser run bounds
# that run's own error (both codes change monotonically and by less with each refinement on
# this scene; see compare/README.md).
pe_conv = {"net": pe["fine"][net], "heading": pe["fine"]["v_head_instantaneous_over_v_m"]}
pe_last = abs(pe["fine"][net] - pe["mid"][net]) / abs(pe_conv["net"])
sl_conv = sl_fine["1.25e-4"]["v_s_over_v_m"]
sl_last = abs(sl_conv - sl_fine["5e-4"]["v_s_over_v_m"]) / abs(sl_conv)

rows = []
for name in ("mid", "max", "fine"):
    j = pe[name]
    if not j["stable"]:
        print(f"PyElastica at dt {j['dt']:.3g} blew up (non-finite positions)")
    rows.append((j["code"], j["dt"], j["steps"], j["wall_time_s"], j["simulated_s"],
                 j["v_head_instantaneous_over_v_m"], j[net], pe_conv["net"]))
rows.append(("slither (implicit Euler)", p["time"]["dt"], sl["steps"], sl["wall_time_s"],
             sl["t_final"], float("nan"), sl["v_s_over_v_m"], sl_conv))
for dt in ("1e-3", "5e-4", "1.25e-4"):
    s = sl_fine[dt]
    rows.append(("slither (implicit Euler)", float(dt), s["steps"], s["wall_time_s"],
                 s["t_final"], float("nan"), s["v_s_over_v_m"], sl_conv))
ad = {name: json.load(open(os.path.join(out, f"{name}_bdf2_adaptive", "summary.json")))
      for name in ("pyelastica_s_start", "s_start")}
rows.append(("slither (BDF2 adaptive, default tolerance)", float("nan"),
             ad["pyelastica_s_start"]["steps"], ad["pyelastica_s_start"]["wall_time_s"],
             ad["pyelastica_s_start"]["t_final"], float("nan"),
             ad["pyelastica_s_start"]["v_s_over_v_m"], sl_conv))
def dt_str(dt):
    if dt != dt:
        return "adaptive"
    return ("%.2e" % dt).replace(".00e", "e")


sl_rate = sl["wall_time_s"] / sl["t_final"]
print()
print("| code | dt (s) | steps | wall s | simulated s | wall s per simulated s "
      "| v_s/v_m (heading) | v_s/v_m (net) | v_s/v_m error vs own converged value "
      "| wall per simulated s / slither's at dt 2e-3 |")
print("|---|---|---|---|---|---|---|---|---|---|")
for code, dt, steps, wall, sim, vh, vn, conv in rows:
    rate = wall / sim
    vh_s = "-" if vh != vh else f"{vh:.4f}"
    ratio = f"{rate / sl_rate:.2f}"
    print(f"| {code} | {dt_str(dt)} | {steps} | {wall:.2f} | {sim:.3f} | {rate:.3f} "
          f"| {vh_s} | {vn:.4f} | {100 * (vn - conv) / abs(conv):+.2f} % | {ratio} |")
print()
print(f"Converged v_s/v_m (net): PyElastica {pe_conv['net']:.4f} (dt {dt_str(pe['fine']['dt'])}; "
      f"{100 * pe_last:.2f} % from dt {dt_str(pe['mid']['dt'])}; heading definition "
      f"{pe_conv['heading']:.4f}), slither {sl_conv:.4f} (dt 1.25e-4; {100 * sl_last:.2f} % "
      f"from dt 5e-4).")
print(f"Time-step error only: both codes are run at {elements} elements.")
# Equal accuracy: for each PyElastica step, the cheapest slither row at least as accurate.
for pe_row in [r for r in rows if r[0].startswith("PyElastica")]:
    err = abs(pe_row[6] - pe_row[7]) / abs(pe_row[7])
    ok = [r for r in rows if not r[0].startswith("PyElastica")
          and abs(r[6] - r[7]) / abs(r[7]) <= max(err, 1e-12)]
    if pe_row[1] == pe["fine"]["dt"] or not ok:
        continue
    best = min(ok, key=lambda r: r[3] / r[4])
    print(f"Equal accuracy: PyElastica at dt {dt_str(pe_row[1])} ({100 * err:.2f} %) takes "
          f"{pe_row[3] / pe_row[4]:.3f} s per simulated s, slither at dt {dt_str(best[1])} "
          f"({100 * abs(best[6] - best[7]) / abs(best[7]):.2f} %) "
          f"{best[3] / best[4]:.3f}: {pe_row[3] / pe_row[4] / (best[3] / best[4]):.2f}x.")
b = ad["s_start"]
b_rate = b["wall_time_s"] / b["t_final"]
pe_rate = pe["max"]["wall_time_s"] / pe["max"]["simulated_s"]
print(f"Bundled S-start (problems/s_start.toml at {elements} elements) by adaptive BDF2 at the "
      f"default tolerance: {b['steps']} steps, {b['wall_time_s']:.2f} s for {b['t_final']:.3f} s "
      f"= {b_rate:.3f} s per simulated s, v_s/v_m {b['v_s_over_v_m']:.4f}; PyElastica at its "
      f"largest stable step {dt_str(pe['max']['dt'])} on its scene {pe_rate:.3f}: "
      f"{pe_rate / b_rate:.1f}x.")
# The converged value: mean of 15 runs at 400 elements, implicit Euler and BDF2 at small steps
# (range 0.3173 to 0.3213; record converged-s-start).
conv, conv_lo, conv_hi = 0.3189, 0.3173, 0.3213
for cdt in ("5e-3", "6e-3"):
    c = json.load(open(os.path.join(out, f"s_start_converged_{cdt}", "summary.json")))
    c_rate = c["wall_time_s"] / c["t_final"]
    c_err = (c["v_s_over_v_m"] - conv) / conv
    print(f"Converged S-start (problems/s_start.toml at {elements} elements, BDF2 at {cdt} s, "
          f"semi-smooth contact): {c['steps']} steps, "
          f"{c['stats']['newton_iterations']} Newton iterations, {c['wall_time_s']:.2f} s for "
          f"{c['t_final']:.3f} s = {c_rate:.3f} s per simulated s, v_s/v_m "
          f"{c['v_s_over_v_m']:.4f}, {100 * c_err:+.2f} % from the converged {conv} "
          f"({conv_lo} to {conv_hi}); PyElastica at its largest stable step "
          f"{dt_str(pe['max']['dt'])} on its scene {pe_rate:.3f}: {pe_rate / c_rate:.1f}x.")
print()
print("v_s/v_m (heading): centre-of-mass velocity along the instantaneous ground-projected")
print("tail-to-head direction, time-averaged (the PyElastica reference README's v_s).")
print("v_s/v_m (net): net centre-of-mass displacement along the initial head direction over")
print("the run time (slither's summary.json v_s_over_v_m).")
EOF
