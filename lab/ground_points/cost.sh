#!/usr/bin/env bash
# What contact between the nodes costs: whole `slither run problems/s_start.toml --no-plots
# --quiet` processes (the bundled S-start: BDF2 at 3.6e-3 s) at 100 and 200 elements, with
# `solver.ground_points` "nodes" and "curve", in turn, K rounds in one window with one build.
# Prints every run, each case's medians (wall time, Newton iterations per step) and the
# curve's ratios to the nodes'; kept as the dated record docs/results/ground-points-cost/<date>.md.
#
#   lab/ground_points/cost.sh [K]       # K rounds (default 7); about 8 s per round
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points-cost "$0" "$@"
fi
k="${1:-7}"
case "$k" in '' | *[!0-9]*) echo "cost.sh: K must be a whole number, got '$k'" >&2; exit 2 ;; esac
. tools/build.sh
use_slither
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
for round in $(seq 1 "$k"); do
    for n in 100 200; do
        for points in nodes curve; do
            t0="$(date +%s.%N)"
            "$SLITHER" run problems/s_start.toml --out "$tmp/out" --no-plots --quiet --force \
                --set rod.elements="$n" --set solver.ground_points="\"$points\""
            t1="$(date +%s.%N)"
            jq -r --arg r "$round" --arg n "$n" --arg p "$points" \
                --arg w "$(awk "BEGIN { print $t1 - $t0 }")" \
                '"\($r) \($n) \($p) \($w) \(.newton_iterations_mean) \(.stats.steps) \(.v_s_over_v_m)"' \
                "$tmp/out/summary.json" | tee -a "$tmp/rows"
        done
    done
done
python3 - "$tmp/rows" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
med = {}
print("\n| elements | contact | median wall s | median iterations/step | v_s/v_m |")
print("|---|---|---|---|---|")
for n in ["100", "200"]:
    for p in ["nodes", "curve"]:
        sel = [r for r in rows if r[1] == n and r[2] == p]
        w = statistics.median(float(r[3]) for r in sel)
        it = statistics.median(float(r[4]) for r in sel)
        med[(n, p)] = (w, it)
        print(f"| {n} | {p} | {w:.3f} | {it:.2f} | {float(sel[0][6]):.5f} |")
print("\n| elements | curve / nodes, wall time | curve / nodes, iterations per step |")
print("|---|---|---|")
for n in ["100", "200"]:
    (wn, itn), (wc, itc) = med[(n, "nodes")], med[(n, "curve")]
    print(f"| {n} | {wc / wn:.3f} | {itc / itn:.3f} |")
PY
