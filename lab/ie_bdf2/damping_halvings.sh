#!/usr/bin/env bash
# Issue 55's halving criterion against the damping time: v_s/v_m of the bundled S-start at 100
# elements, implicit Euler and BDF2, contacts at the nodes and on the curve, damping times of
# 5 ms (the bundled file's) and 10 ms, at fixed steps from 5e-4 to 6.25e-5 s, with each
# halving's change. Kept as the dated record docs/results/damping-halvings/<date>.md. About
# 5 minutes on 2 cores.
#
#   lab/ie_bdf2/damping_halvings.sh
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh damping-halvings "$0" "$@"
fi
. tools/build.sh
use_slither
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
run() { # tau points integrator dt -> appends "tau points integrator dt v"
    local out="$tmp/$1-$2-$3-$4"
    "$SLITHER" run problems/s_start.toml --out "$out" --no-plots --quiet --force \
        --set rod.elements=100 --set rod.damping_time="$1" --set solver.ground_points="\"$2\"" \
        --set solver.integrator="$3" --set time.dt="$4"
    jq -r --arg t "$1" --arg p "$2" --arg i "$3" --arg d "$4" \
        '"\($t) \($p) \($i) \($d) \(.v_s_over_v_m)"' "$out/summary.json" >>"$tmp/rows"
}
for tau in 5e-3 1e-2; do
    for points in nodes curve; do
        for i in implicit bdf2; do
            for dt in 5e-4 2.5e-4 1.25e-4 6.25e-5; do run "$tau" "$points" "$i" "$dt" & done
            wait
        done
    done
done
python3 - "$tmp/rows" <<'PY'
import sys
rows = [l.split() for l in open(sys.argv[1])]
v = {(float(t), p, i, float(d)): float(x) for t, p, i, d, x in rows}
steps = [5e-4, 2.5e-4, 1.25e-4, 6.25e-5]
print("| damping time (s) | contact | integrator | " + " | ".join(f"{d:g} s" for d in steps)
      + " | changes per halving | largest change |")
print("|---|---|---|---|---|---|---|---|---|")
for t in [5e-3, 1e-2]:
    for p in ["nodes", "curve"]:
        for i in ["implicit", "bdf2"]:
            xs = [v[(t, p, i, d)] for d in steps]
            ch = [100 * (b / a - 1) for a, b in zip(xs, xs[1:])]
            print(f"| {t:g} | {p} | {i} | " + " | ".join(f"{x:.5f}" for x in xs) + " | "
                  + ", ".join(f"{c:+.3f} %" for c in ch) + f" | {max(abs(c) for c in ch):.3f} % |")
PY
