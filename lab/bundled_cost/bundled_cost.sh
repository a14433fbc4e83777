#!/usr/bin/env bash
# What the bundled S-start costs a newcomer, against the mesh and step it had before: whole
# `slither run FILE --no-plots --quiet` processes (start-up, simulation, summary) of
# problems/s_start.toml (100 elements, BDF2 at fixed steps of 3.6e-3 s) and
# problems/s_start_coarse.toml (50 elements, implicit Euler at 2e-3 s), alternately, K times in
# one window with one build. Prints each run, the medians, their ratio and each file's v_s/v_m
# with its error against the converged 0.3197 to 0.3205 (implicit Euler at 400 elements, record
# accuracy-s-start). Kept as a dated record docs/results/bundled-cost/<date>.md.
#
#   lab/bundled_cost/bundled_cost.sh [K]       # K repeats (default 7); about 3 s per repeat
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
# SLITHER_OLD names an older build: it runs problems/s_start_coarse.toml too, in the same
# rounds (the file is byte for byte the bundled S-start of builds before the move to 100
# elements), and the ratio against it is printed as well.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh bundled-cost "$0" "$@"
fi
k="${1:-7}"
case "$k" in '' | *[!0-9]*) echo "bundled_cost.sh: K must be a whole number, got '$k'" >&2; exit 2 ;; esac
. tools/build.sh
use_slither
slither="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
runs=("$slither problems/s_start.toml s_start" "$slither problems/s_start_coarse.toml s_start_coarse")
if [ -n "${SLITHER_OLD:-}" ]; then
    runs+=("$SLITHER_OLD problems/s_start_coarse.toml old_build")
    echo "old build: $SLITHER_OLD"
fi
for rep in $(seq 1 "$k"); do
    for r in "${runs[@]}"; do
        read -r bin f name <<<"$r"
        t0="$(date +%s.%N)"
        "$bin" run "$f" --out "$tmp/$name" --no-plots --quiet
        t1="$(date +%s.%N)"
        awk -v n="$name" -v a="$t0" -v b="$t1" 'BEGIN { printf "%s %.3f\n", n, b - a }' | tee -a "$tmp/times"
    done
done
v_new="$(jq .v_s_over_v_m "$tmp/s_start/summary.json")"
v_old="$(jq .v_s_over_v_m "$tmp/s_start_coarse/summary.json")"
python3 - "$tmp/times" "$v_new" "$v_old" <<'PY'
import statistics, sys
times = {}
for line in open(sys.argv[1]):
    name, t = line.split()
    times.setdefault(name, []).append(float(t))
new, old = statistics.median(times["s_start"]), statistics.median(times["s_start_coarse"])
print(f"median wall time, whole process: s_start.toml {new:.3f} s, s_start_coarse.toml {old:.3f} s")
print(f"ratio s_start / s_start_coarse: {new / old:.2f}")
if "old_build" in times:
    before = statistics.median(times["old_build"])
    print(f"old build on s_start_coarse.toml: median {before:.3f} s; ratio s_start / old build: {new / before:.2f}")
for name, v in (("s_start.toml", float(sys.argv[2])), ("s_start_coarse.toml", float(sys.argv[3]))):
    errs = ", ".join(f"{100 * (v / ref - 1):+.2f} %" for ref in (0.3197, 0.3205))
    print(f"{name}: v_s/v_m {v:.5f}, against 0.3197 and 0.3205: {errs}")
PY
