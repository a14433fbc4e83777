#!/usr/bin/env bash
# Back-to-back timing of PyElastica 1.0 on its own S-start scene against slither on the same
# scene (problems/pyelastica_s_start.toml), in one window on one machine. Not part of CI.
#
#   compare/run.sh            # from anywhere; results in compare/out/
#
# 1. compare/.venv: a virtual environment with pyelastica==1.0.0 and numpy from PyPI
#    (created once; delete the folder to reinstall; falls back to the newest 1.x if 1.0.0 is gone).
# 2. cargo build --release (honours CARGO_TARGET_DIR).
# 3. PyElastica at dt 2e-5 and 5e-5 (its largest stable step), timing only the time stepping
#    after an in-process warm-up that compiles numba's kernels; then slither.
# 4. The table: wall seconds per simulated second and the ratio PyElastica / slither.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
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
echo "== PyElastica, dt 2e-5"
"$venv/bin/python" "$here/pyelastica_s_start.py" --dt 2e-5 --out "$out/pyelastica_dt2e-5.json" >/dev/null
echo "== PyElastica, dt 5e-5"
"$venv/bin/python" "$here/pyelastica_s_start.py" --dt 5e-5 --out "$out/pyelastica_dt5e-5.json" >/dev/null
echo "== slither, problems/pyelastica_s_start.toml"
"$slither" run problems/pyelastica_s_start.toml --out "$out/slither" --no-plots --quiet
echo "load after: $(cat /proc/loadavg)"

"$venv/bin/python" - "$out" "$repo/problems/pyelastica_s_start.toml" <<'EOF'
import json, os, sys, tomllib
out, problem = sys.argv[1], sys.argv[2]
with open(problem, "rb") as f:
    p = tomllib.load(f)
sl = json.load(open(os.path.join(out, "slither", "summary.json")))
rows = []
for name in ("pyelastica_dt2e-5.json", "pyelastica_dt5e-5.json"):
    j = json.load(open(os.path.join(out, name)))
    rows.append((j["code"], j["dt"], j["steps"], j["wall_time_s"], j["simulated_s"],
                 j["v_s_over_v_m"], j["com_disp_over_T_along_initial_head_over_v_m"]))
rows.append(("slither (implicit Euler)", p["time"]["dt"], sl["steps"], sl["wall_time_s"],
             sl["t_final"], float("nan"), sl["v_s_over_v_m"]))
sl_rate = sl["wall_time_s"] / sl["t_final"]
print()
print("| code | dt (s) | steps | wall s | simulated s | wall s per simulated s "
      "| v_s/v_m (heading) | v_s/v_m (net) | PyElastica / slither |")
print("|---|---|---|---|---|---|---|---|---|")
for code, dt, steps, wall, sim, vh, vn in rows:
    rate = wall / sim
    vh_s = "-" if vh != vh else f"{vh:.4f}"
    print(f"| {code} | {dt:.0e} | {steps} | {wall:.2f} | {sim:.3f} | {rate:.3f} "
          f"| {vh_s} | {vn:.4f} | {rate / sl_rate:.2f} |")
print()
print("v_s/v_m (heading): centre-of-mass velocity along the instantaneous ground-projected")
print("tail-to-head direction, time-averaged (the PyElastica reference README's v_s).")
print("v_s/v_m (net): net centre-of-mass displacement along the initial head direction over")
print("the run time (slither's summary.json v_s_over_v_m).")
EOF
