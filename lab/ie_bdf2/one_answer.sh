#!/usr/bin/env bash
# Issue 55's table re-measured on the bundled S-start (a Kelvin-Voigt rod with a damping time
# of 5 ms): v_s/v_m of implicit Euler and BDF2 at fixed steps from 5e-4 to 6.25e-5 s, at 100 and
# 200 elements, with each halving's change and the gap between the two integrators; then the
# elastic rod (rod.damping_time = 0) at 200 elements for comparison. Kept as a dated record
# docs/results/ie-bdf2-one-answer/<date>.md. About 10 minutes on 2 cores.
#
#   lab/ie_bdf2/one_answer.sh
#
# SLITHER names a built binary to use instead of building one (`cargo build --release`).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ie-bdf2-one-answer "$0" "$@"
fi
if [ -n "${SLITHER:-}" ]; then
    slither="$SLITHER"
else
    cargo build --release --quiet
    slither="${CARGO_TARGET_DIR:-target}/release/slither"
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
grep -q '^damping_time = 5e-3' problems/s_start.toml || { echo "problems/s_start.toml: damping time is not 5e-3" >&2; exit 1; }
run() { # elements dt integrator damping -> prints "elements dt integrator damping v wall"
    "$slither" run problems/s_start.toml --out "$tmp/out" --no-plots --quiet --force \
        --set rod.elements="$1" --set time.dt="$2" --set solver.integrator="$3" \
        --set rod.damping_time="$4"
    jq -r --arg e "$1" --arg dt "$2" --arg i "$3" --arg d "$4" \
        '"\($e) \($dt) \($i) \($d) \(.v_s_over_v_m) \(.wall_time_s)"' "$tmp/out/summary.json"
}
for el in 100 200; do
    for dt in 5e-4 2.5e-4 1.25e-4 6.25e-5; do
        for i in implicit bdf2; do run "$el" "$dt" "$i" 5e-3 >>"$tmp/rows"; done
    done
done
for dt in 2.5e-4 1.25e-4; do
    for i in implicit bdf2; do run 200 "$dt" "$i" 0 >>"$tmp/rows"; done
done
python3 - "$tmp/rows" <<'PY'
import sys
rows = [l.split() for l in open(sys.argv[1])]
v = {(int(e), float(dt), i, float(d)): (float(x), float(w)) for e, dt, i, d, x, w in rows}
print("| elements | damping time (s) | integrator | step (s) | v_s/v_m | change from the step twice as large | wall s |")
print("|---|---|---|---|---|---|---|")
for (e, dt, i, d), (x, w) in v.items():
    prev = v.get((e, 2 * dt, i, d))
    change = f"{100 * (x - prev[0]) / prev[0]:+.3f} %" if prev else ""
    print(f"| {e} | {d:g} | {i} | {dt:g} | {x:.5f} | {change} | {w:.1f} |")
print()
print("Gap between the integrators, (BDF2 - implicit Euler) / implicit Euler:")
print()
print("| elements | damping time (s) | step (s) | gap |")
print("|---|---|---|---|")
for (e, dt, i, d), (x, w) in v.items():
    if i == "implicit" and (e, dt, "bdf2", d) in v:
        b = v[(e, dt, "bdf2", d)][0]
        print(f"| {e} | {d:g} | {dt:g} | {100 * (b - x) / x:+.3f} % |")
PY
