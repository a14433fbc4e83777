#!/usr/bin/env bash
# Which step or error tolerance makes the S-start cheapest at a given accuracy: the scene of
# problems/s_start.toml at 100 and 200 elements with implicit Euler at fixed steps, BDF2 at
# fixed steps and adaptive BDF2 at several error tolerances (`[time] error_tolerance`, first
# step 1e-3 s), each run 4 times with mu_forward raised by 0, 1, 2 and 3 parts in 1e6 (a
# trajectory of the S-start is a sample of a scatter of about 0.5 %, so one run cannot rank
# two settings). Per setting: the mean and spread of v_s/v_m, the mean error against 0.3201
# (the middle of the converged 0.3197 to 0.3205, implicit Euler at 400 elements; record
# accuracy-s-start), steps, Newton iterations per step, conic fallbacks and the mean wall
# time of one run (runs one after another). Kept as a dated record
# docs/results/adaptive-choice/<date>.md.
#
#   lab/adaptive_choice/adaptive_choice.sh         # 64 runs, about 4 min
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh adaptive-choice "$0" "$@"
fi
. tools/build.sh
use_slither
slither="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
grep -q '^mu_forward = 0.55 ' problems/s_start.toml || { echo "problems/s_start.toml: mu_forward is not 0.55" >&2; exit 1; }
# One setting: elements, label, then the [time] and [solver] lines that replace dt and integrator.
run() {
    local n="$1" label="$2" time_lines="$3" integrator="$4"
    for k in 0 1 2 3; do
        local f="$tmp/s_${n}_${label}_$k.toml"
        sed -e "s/^elements = .*/elements = $n/" \
            -e "s/^mu_forward = 0.55 /mu_forward = 0.55000$k /" \
            -e "s/^dt = .*/$time_lines/" \
            -e "s/^integrator = .*/integrator = \"$integrator\"/" \
            -e "s/^interval = .*/interval = 0.04/" problems/s_start.toml >"$f"
        grep -q "^mu_forward = 0.55000$k " "$f"
        "$slither" run "$f" --out "$tmp/out" --no-plots --quiet
        jq -r --arg n "$n" --arg l "$label" '"\($n) \($l) \(.v_s_over_v_m) \(.wall_time_s) \(.stats.newton_iterations) \(.stats.steps) \(.stats.semismooth_fallbacks) \(.stats.step_halvings)"' \
            "$tmp/out/summary.json" >>"$tmp/rows"
    done
}
for n in 100 200; do
    for dt in 5e-4 1e-3; do
        run "$n" "implicit-Euler-$dt" "dt = $dt" implicit
    done
    for dt in 3.6e-3 5e-3; do
        run "$n" "BDF2-$dt" "dt = $dt" bdf2
    done
    for tol in 5e-6 2e-5 5e-5 1e-4; do
        run "$n" "adaptive-BDF2-$tol" "dt = 1e-3\nadaptive = true\nerror_tolerance = $tol" bdf2
    done
done
python3 - "$tmp/rows" <<'PY'
import statistics, sys
ref = 0.3201
rows = [l.split() for l in open(sys.argv[1])]
keys = []
for r in rows:
    if (r[0], r[1]) not in keys:
        keys.append((r[0], r[1]))
print("| elements | setting | v_s/v_m mean | sd | mean error | largest error | steps | Newton it/step | fallbacks | halvings | wall s per run |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
best = {}
for n, label in keys:
    rs = [r for r in rows if (r[0], r[1]) == (n, label)]
    v = [float(r[2]) for r in rs]
    err = [100 * (x / ref - 1) for x in v]
    wall = statistics.mean(float(r[3]) for r in rs)
    it = sum(int(r[4]) for r in rs) / sum(int(r[5]) for r in rs)
    steps = statistics.mean(int(r[5]) for r in rs)
    fb = sum(int(r[6]) for r in rs)
    halv = sum(int(r[7]) for r in rs)
    mean_err = statistics.mean(err)
    worst = max(err, key=abs)
    print(f"| {n} | {label} | {statistics.mean(v):.5f} | {statistics.stdev(v):.5f} | {mean_err:+.2f} % "
          f"| {worst:+.2f} % | {steps:.0f} | {it:.2f} | {fb} | {halv} | {wall:.2f} |")
    if abs(worst) <= 1.0 and (n not in best or wall < best[n][1]):
        best[n] = (label, wall, mean_err, worst)
for n, (label, wall, mean_err, worst) in sorted(best.items(), key=lambda x: int(x[0])):
    print(f"{n} elements: cheapest with every run within 1 %: {label}, {wall:.2f} s per run "
          f"(mean error {mean_err:+.2f} %, largest {worst:+.2f} %)")
PY
