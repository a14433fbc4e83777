#!/usr/bin/env bash
# Issue 55's table re-measured on the bundled S-start (a Kelvin-Voigt rod with a damping time
# of 10 ms): v_s/v_m of implicit Euler and BDF2 at fixed steps from 5e-4 to 6.25e-5 s, at 100 and
# 200 elements, with each halving's change and the gap between the two integrators; the jitter
# of each mesh (three steps 5 to 10 % from 1.25e-4 s) and the halving criterion against it;
# then the elastic rod (rod.damping_time = 0) at 200 elements for comparison. Kept as a dated
# record docs/results/ie-bdf2-one-answer/<date>.md. About 3 minutes on 2 cores (contact on the
# curve; 5 with node contacts).
#
#   lab/ie_bdf2/one_answer.sh
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ie-bdf2-one-answer "$0" "$@"
fi
. tools/build.sh
use_slither
slither="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
grep -q '^damping_time = 1e-2' problems/s_start.toml || { echo "problems/s_start.toml: damping time is not 1e-2" >&2; exit 1; }
run() { # elements dt integrator damping -> prints "elements dt integrator damping v wall"
    local out="$tmp/out-$1-$2-$3-$4"
    "$slither" run problems/s_start.toml --out "$out" --no-plots --quiet --force \
        --set rod.elements="$1" --set time.dt="$2" --set solver.integrator="$3" \
        --set rod.damping_time="$4"
    jq -r --arg e "$1" --arg dt "$2" --arg i "$3" --arg d "$4" \
        '"\($e) \($dt) \($i) \($d) \(.v_s_over_v_m) \(.wall_time_s)"' "$out/summary.json"
}
# Two runs at a time (2 cores); the rows are sorted by the analysis.
for el in 100 200; do
    for dt in 5e-4 2.5e-4 1.25e-4 6.25e-5; do
        for i in implicit bdf2; do run "$el" "$dt" "$i" 1e-2 >>"$tmp/rows" & done
        wait
    done
    # The jitter of one mesh: steps a few per cent either side of 1.25e-4 s.
    for dt in 1.1875e-4 1.3125e-4 1.375e-4; do
        for i in implicit bdf2; do run "$el" "$dt" "$i" 1e-2 >>"$tmp/jitter" & done
        wait
    done
done
for dt in 2.5e-4 1.25e-4; do
    for i in implicit bdf2; do run 200 "$dt" "$i" 0 >>"$tmp/rows" & done
    wait
done
python3 - "$tmp/rows" "$tmp/jitter" <<'PY'
import statistics, sys
rows = sorted((l.split() for l in open(sys.argv[1])),
              key=lambda r: (float(r[3]) == 0, int(r[0]), -float(r[1]), r[2]))
v = {(int(e), float(dt), i, float(d)): (float(x), float(w)) for e, dt, i, d, x, w in rows}
jit = [l.split() for l in open(sys.argv[2])]
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
print()
print("The halving criterion: each halving below 1e-3 s moves v_s/v_m by at most the error the")
print("integrator's order predicts from the two larger steps (the previous change times 1/2 for")
print("implicit Euler, 1/4 for BDF2). The floor is the jitter of one mesh: the range of v_s/v_m")
print("over 1.1875e-4, 1.25e-4, 1.3125e-4 and 1.375e-4 s (steps 5 to 10 % apart, which no order")
print("resolves).")
print()
print("| elements | integrator | changes at 2.5e-4, 1.25e-4, 6.25e-5 s | predicted bounds (last two) | jitter range | met | met above the floor |")
print("|---|---|---|---|---|---|---|")
for e in [100, 200]:
    for i, r in [("implicit", 0.5), ("bdf2", 0.25)]:
        xs = [v[(e, dt, i, 1e-2)][0] for dt in [5e-4, 2.5e-4, 1.25e-4, 6.25e-5]]
        ch = [100 * (b - a) / a for a, b in zip(xs, xs[1:])]
        bounds = [r * abs(ch[0]), r * abs(ch[1])]
        js = [float(x) for ee, dt, ii, d, x, w in jit if int(ee) == e and ii == i] + [xs[2]]
        floor = 100 * (max(js) - min(js)) / statistics.mean(js)
        met = all(abs(c) <= b for c, b in zip(ch[1:], bounds))
        met_floor = all(abs(c) <= max(b, floor) for c, b in zip(ch[1:], bounds))
        print(f"| {e} | {i} | " + ", ".join(f"{c:+.3f} %" for c in ch) + " | "
              + ", ".join(f"{b:.3f} %" for b in bounds) + f" | {floor:.3f} % ({len(js)} steps) | "
              + ("yes" if met else "no") + " | " + ("yes" if met_floor else "no") + " |")
PY
