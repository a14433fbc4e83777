#!/usr/bin/env bash
# `slither run problems/s_start.toml --accuracy 0.01 --no-plots` with an old build on the
# bundled file of its commit and with this build on this commit's, in turn, K rounds in one
# window: the elapsed time of each run, medians and their ratio, and each answer and estimate.
# Kept as the dated record docs/results/ground-points-accuracy-paired/<date>.md.
#
#   lab/ground_points/accuracy_paired.sh OLD_BINARY OLD_COMMIT [K]   # K rounds (default 3)
#
# Issue 53 measured it against the build of bcae2e7, the last whose bundled S-start had its
# ground contacts at the nodes: about 4 min for 3 rounds on 2 cores.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ $# -lt 2 ]; then
    echo "usage: lab/ground_points/accuracy_paired.sh OLD_BINARY OLD_COMMIT [K]" >&2
    exit 2
fi
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points-accuracy-paired "$0" "$@"
fi
old_bin="$1"
old_commit="$2"
rounds="${3:-3}"
. tools/build.sh
use_slither
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
git show "$old_commit:problems/s_start.toml" >"$tmp/old.toml"
echo "old: $old_bin on problems/s_start.toml of $old_commit ($(grep -c '^ground_points = "curve"' "$tmp/old.toml" | sed 's/^0$/contact at the nodes/; s/^1$/contact on the curve/'))"
echo "new: $SLITHER on problems/s_start.toml of $(git rev-parse --short HEAD) ($(grep -c '^ground_points = "curve"' problems/s_start.toml | sed 's/^0$/contact at the nodes/; s/^1$/contact on the curve/'))"
for k in $(seq 1 "$rounds"); do
    for which in old new; do
        if [ "$which" = old ]; then bin="$old_bin"; file="$tmp/old.toml"; else bin="$SLITHER"; file=problems/s_start.toml; fi
        rm -rf "$tmp/$which" # a fresh directory: --accuracy reuses the probe runs it finds there
        t0=$(date +%s.%N)
        "$bin" run "$file" --out "$tmp/$which" --no-plots --quiet --force --accuracy 0.01 >"$tmp/$which.log" 2>&1
        t1=$(date +%s.%N)
        e=$(echo "$t1 - $t0" | bc)
        echo "$which $e" >>"$tmp/times"
        jq -r --arg w "$which" --arg k "$k" --arg e "$e" '"round \($k) \($w): \($e) s elapsed; \(.accuracy.elements) el., dt \(.accuracy.dt) s, v_s/v_m \(.v_s_over_v_m * 1e5 | round / 1e5), estimate \(.accuracy.estimated_error * 1e4 | round / 100) %"' "$tmp/$which/summary.json"
    done
done
median() { grep "^$1 " "$tmp/times" | awk '{print $2}' | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
mo=$(median old)
mn=$(median new)
echo "median elapsed: old $mo s, new $mn s, new / old $(echo "scale=4; $mn / $mo" | bc)"
