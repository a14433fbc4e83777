#!/usr/bin/env bash
# Whether the contact Newton's cost grows linearly with the mesh: the whole bundled S-start
# with implicit Euler at 5e-4 s on 200 and on 400 elements, run alternately K times in one
# window (200, 400, 200, 400, ...), and per pair of runs the ratio of their simulation wall
# times (summary.json's wall_time_s: the time stepping, not the output), with the median and
# the range over the pairs. One run of each is noisy on a shared 2-core machine (the same
# binary has taken 5.4 to 7.8 s on 200 elements), so only the median of alternating pairs is
# quoted. Kept as a dated record docs/results/linear-cost/<date>.md.
#
#   lab/linear_cost/linear_cost.sh [K]      # K pairs (default 5); about 25 s per pair
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh linear-cost "$0" --inner "${1:-5}"
fi
k="$2"
case "$k" in '' | *[!0-9]* | 0) echo "linear_cost.sh: K must be a positive whole number, got '$k'" >&2; exit 2 ;; esac
. tools/build.sh
use_slither
bin="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

for n in 200 400; do
    f="$tmp/s_start_$n.toml"
    sed -e "s/^elements = .*/elements = $n/" -e "s/^dt = .*/dt = 5e-4/" problems/s_start.toml >"$f"
    sed -i '/^integrator = /d' "$f"
    grep -q '^\[solver\]' "$f" || printf '\n[solver]\n' >>"$f"
    sed -i '/^\[solver\]/a integrator = "implicit"' "$f"
    grep -q '^elements = '"$n"'$' "$f" && grep -q '^dt = 5e-4$' "$f" || {
        echo "linear_cost.sh: could not set elements and dt in $f" >&2
        exit 1
    }
done
for rep in $(seq 1 "$k"); do
    for n in 200 400; do
        "$bin" run "$tmp/s_start_$n.toml" --out "$tmp/out-$n-$rep" --no-plots --quiet
    done
done
python3 - "$tmp" "$k" <<'EOF'
import json, statistics, sys
tmp, k = sys.argv[1], int(sys.argv[2])
runs = {n: [json.load(open(f"{tmp}/out-{n}-{i}/summary.json")) for i in range(1, k + 1)] for n in (200, 400)}
print("S-start, implicit Euler 5e-4 s, whole scene; wall s of the time stepping per run")
print()
print("| pair | 200 el. | 400 el. | ratio |")
print("|---|---|---|---|")
ratios = []
for i in range(k):
    a, b = runs[200][i]["wall_time_s"], runs[400][i]["wall_time_s"]
    ratios.append(b / a)
    print(f"| {i + 1} | {a:.2f} | {b:.2f} | {b / a:.3f} |")
print()
for n in (200, 400):
    s = runs[n][0]
    st = s["stats"]
    print(f"{n} elements: median {statistics.median(r['wall_time_s'] for r in runs[n]):.2f} s, "
          f"{st['newton_iterations'] / st['steps']:.3f} Newton iterations per step, "
          f"{st['factorizations'] / st['steps']:.3f} factorisations per step, "
          f"{st['semismooth_fallbacks']} fallbacks, v_s/v_m {s['v_s_over_v_m']:.6f}")
print(f"ratio 400 / 200: median {statistics.median(ratios):.3f}, range {min(ratios):.3f} to {max(ratios):.3f} "
      f"over {k} alternating pairs; ratio of the medians "
      f"{statistics.median(r['wall_time_s'] for r in runs[400]) / statistics.median(r['wall_time_s'] for r in runs[200]):.3f}")
EOF
