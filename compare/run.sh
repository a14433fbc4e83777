#!/usr/bin/env bash
# Back-to-back timing of PyElastica 1.0 on its own S-start scene against slither on the same
# scene (problems/pyelastica_s_start.toml), in one window on one machine. Not part of CI.
#
#   compare/run.sh            # from anywhere; results in compare/out/
#
# 1. compare/.venv: a virtual environment with pyelastica==1.0.0 and numpy from PyPI
#    (created once; delete the folder to reinstall; falls back to the newest 1.x if 1.0.0 is gone).
# 2. cargo build --release (honours CARGO_TARGET_DIR).
# 3. PyElastica at dt 2e-5, 5e-5 (its largest stable step) and 1e-5 (for its converged value),
#    timing only the time stepping after an in-process warm-up that compiles numba's kernels;
#    then slither at the file's dt 2e-3 and at 1e-3, 5e-4 (4x smaller) and 1.25e-4 (16x
#    smaller, for its converged value). All in one window.
# 4. The table: wall seconds per simulated second, the ratio PyElastica / slither, and each
#    row's v_s/v_m error against its own code's converged value: the finest run of that code
#    (PyElastica dt 1e-5, slither dt 1.25e-4), whose own error is bounded by its change from
#    the next coarser run (printed). Time-step error only: neither code is mesh-converged at
#    50 elements.
#
# Every run is kept as a dated record, docs/results/pyelastica-compare/<date>.md (machine,
# build, load, the whole output), by scripts/record.sh; SLITHER_NO_RECORD=1 skips it.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
if [ -z "${SLITHER_RECORDING:-}" ] && [ -z "${SLITHER_NO_RECORD:-}" ]; then
    exec "$repo/scripts/record.sh" pyelastica-compare "$here/run.sh" "$@"
fi
cd "$repo"
venv="$here/.venv"
out="$here/out"
mkdir -p "$out"

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
for dt in 2e-5 5e-5 1e-5; do
    echo "== PyElastica, dt $dt"
    "$venv/bin/python" "$here/pyelastica_s_start.py" --dt "$dt" --out "$out/pyelastica_dt$dt.json" >/dev/null
done
echo "== slither, problems/pyelastica_s_start.toml"
"$slither" run problems/pyelastica_s_start.toml --out "$out/slither" --no-plots --quiet
for dt in 1e-3 5e-4 1.25e-4; do
    echo "== slither, dt $dt"
    sed -e "s/^dt = 2e-3/dt = $dt/" problems/pyelastica_s_start.toml > "$out/slither_dt$dt.toml"
    grep -q "^dt = $dt" "$out/slither_dt$dt.toml"
    "$slither" run "$out/slither_dt$dt.toml" --out "$out/slither_dt$dt" --no-plots --quiet
done
# Adaptive BDF2 at its default error tolerance: on PyElastica's scene and on the
# bundled S-start (problems/s_start.toml), each as the file with integrator and adaptive set.
for name in pyelastica_s_start s_start; do
    echo "== slither, BDF2 adaptive, problems/$name.toml"
    sed -e 's/^\[ground\]/[solver]\nintegrator = "bdf2"\n\n[ground]/' \
        -e 's/^dt = 2e-3/dt = 2e-3\nadaptive = true/' \
        "problems/$name.toml" > "$out/${name}_bdf2_adaptive.toml"
    grep -q '^adaptive = true' "$out/${name}_bdf2_adaptive.toml"
    grep -q '^integrator = "bdf2"' "$out/${name}_bdf2_adaptive.toml"
    "$slither" run "$out/${name}_bdf2_adaptive.toml" --out "$out/${name}_bdf2_adaptive" \
        --no-plots --quiet
done
echo "load after: $(cat /proc/loadavg)"

"$venv/bin/python" - "$out" "$repo/problems/pyelastica_s_start.toml" <<'EOF'
import json, os, sys, tomllib
out, problem = sys.argv[1], sys.argv[2]
with open(problem, "rb") as f:
    p = tomllib.load(f)
sl = json.load(open(os.path.join(out, "slither", "summary.json")))
pe = {}
for dt in ("2e-5", "5e-5", "1e-5"):
    pe[dt] = json.load(open(os.path.join(out, f"pyelastica_dt{dt}.json")))
sl_fine = {dt: json.load(open(os.path.join(out, f"slither_dt{dt}", "summary.json")))
           for dt in ("1e-3", "5e-4", "1.25e-4")}
net = "com_disp_over_T_along_initial_head_over_v_m"
# Each code's converged value: its finest run; the change from the next coarser run bounds
# that run's own error (both codes change monotonically and by less with each refinement on
# this scene; see compare/README.md).
pe_conv = {"net": pe["1e-5"][net], "heading": pe["1e-5"]["v_s_over_v_m"]}
pe_last = abs(pe["1e-5"][net] - pe["2e-5"][net]) / abs(pe_conv["net"])
sl_conv = sl_fine["1.25e-4"]["v_s_over_v_m"]
sl_last = abs(sl_conv - sl_fine["5e-4"]["v_s_over_v_m"]) / abs(sl_conv)

rows = []
for name in ("2e-5", "5e-5", "1e-5"):
    j = pe[name]
    rows.append((j["code"], j["dt"], j["steps"], j["wall_time_s"], j["simulated_s"],
                 j["v_s_over_v_m"], j[net], pe_conv["net"]))
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
print(f"Converged v_s/v_m (net): PyElastica {pe_conv['net']:.4f} (dt 1e-5; "
      f"{100 * pe_last:.2f} % from dt 2e-5; heading definition {pe_conv['heading']:.4f}), "
      f"slither {sl_conv:.4f} (dt 1.25e-4; {100 * sl_last:.2f} % from dt 5e-4).")
print("Time-step error only: both codes are run at 50 elements.")
# Equal accuracy: for each PyElastica step, the cheapest slither row at least as accurate.
for pe_row in [r for r in rows if r[0].startswith("PyElastica")]:
    err = abs(pe_row[6] - pe_row[7]) / abs(pe_row[7])
    ok = [r for r in rows if not r[0].startswith("PyElastica")
          and abs(r[6] - r[7]) / abs(r[7]) <= max(err, 1e-12)]
    if pe_row[1] == 1e-5 or not ok:
        continue
    best = min(ok, key=lambda r: r[3] / r[4])
    print(f"Equal accuracy: PyElastica at dt {dt_str(pe_row[1])} ({100 * err:.2f} %) takes "
          f"{pe_row[3] / pe_row[4]:.3f} s per simulated s, slither at dt {dt_str(best[1])} "
          f"({100 * abs(best[6] - best[7]) / abs(best[7]):.2f} %) "
          f"{best[3] / best[4]:.3f}: {pe_row[3] / pe_row[4] / (best[3] / best[4]):.2f}x.")
b = ad["s_start"]
b_rate = b["wall_time_s"] / b["t_final"]
pe_rate = pe["2e-5"]["wall_time_s"] / pe["2e-5"]["simulated_s"]
print(f"Bundled S-start (problems/s_start.toml) by adaptive BDF2 at the default tolerance: "
      f"{b['steps']} steps, {b['wall_time_s']:.2f} s for {b['t_final']:.3f} s = {b_rate:.3f} s "
      f"per simulated s, v_s/v_m {b['v_s_over_v_m']:.4f}; PyElastica at dt 2e-5 on its scene "
      f"{pe_rate:.3f}: {pe_rate / b_rate:.1f}x.")
print()
print("v_s/v_m (heading): centre-of-mass velocity along the instantaneous ground-projected")
print("tail-to-head direction, time-averaged (the PyElastica reference README's v_s).")
print("v_s/v_m (net): net centre-of-mass displacement along the initial head direction over")
print("the run time (slither's summary.json v_s_over_v_m).")
EOF
