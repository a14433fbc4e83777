#!/usr/bin/env bash
# What keeping the bending and twist Hessian over a step's iterates ([solver] hessian_reuse)
# saves, and what it changes: the S-start in a few resolutions, each run with hessian_reuse = 0
# (the Hessian assembled at every iterate) and with the default, alternately, K times in one
# window. Prints per case the median wall time of each (summary.json's wall_time_s: the
# simulation, not the output), their ratio, Newton iterations, the iterations that kept the
# Hessian, and v_s/v_m. Kept as a dated record docs/results/hessian-reuse/<date>.md.
#
#   lab/hessian_reuse/hessian_reuse.sh [K]      # K repeats (default 5); about 1 minute per repeat
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh hessian-reuse "$0" --inner "${1:-5}"
fi
k="$2"
case "$k" in '' | *[!0-9]*) echo "hessian_reuse.sh: K must be a whole number, got '$k'" >&2; exit 2 ;; esac
. tools/build.sh
use_slither
bin="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# case name, elements, dt, duration (0: the file's), integrator
cases=(
    "50el-implicit 50 2e-3 0 implicit"
    "bundled-100el-bdf2 100 3e-3 0 bdf2"
    "200el-first-0.6s 200 1e-3 0.6 implicit"
    "400el-first-0.4s 400 1e-3 0.4 implicit"
)
for c in "${cases[@]}"; do
    read -r name n dt dur integ <<<"$c"
    for reuse in 0 default; do
        f="$tmp/$name-$reuse.toml"
        sed -e "s/^elements = .*/elements = $n/" -e "s/^dt = .*/dt = $dt/" problems/s_start.toml >"$f"
        [ "$dur" != 0 ] && sed -i "s/^duration = .*/duration = $dur/" "$f"
        sed -i '/^integrator = /d; /^hessian_reuse = /d' "$f"
        grep -q '^\[solver\]' "$f" || printf '\n[solver]\n' >>"$f"
        extra="integrator = \"$integ\""
        [ "$reuse" = 0 ] && extra="$extra\nhessian_reuse = 0.0"
        sed -i "/^\[solver\]/a $extra" "$f"
    done
done
for rep in $(seq 1 "$k"); do
    for c in "${cases[@]}"; do
        read -r name _ <<<"$c"
        for reuse in 0 default; do
            "$bin" run "$tmp/$name-$reuse.toml" --out "$tmp/out-$name-$reuse-$rep" --no-plots --quiet
        done
    done
done
python3 - "$tmp" "$k" "${cases[@]}" <<'EOF'
import json, statistics, sys
tmp, k, cases = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
print(f"{'case':<18} {'reuse 0 (s)':>11} {'default (s)':>11} {'ratio':>6} {'iterations 0 / default':>23} {'kept':>6} {'v_s/v_m 0':>10} {'default':>10}")
for c in cases:
    name = c.split()[0]
    runs = {r: [json.load(open(f"{tmp}/out-{name}-{r}-{i}/summary.json")) for i in range(1, k + 1)] for r in ("0", "default")}
    wall = {r: statistics.median(s["wall_time_s"] for s in runs[r]) for r in runs}
    it = {r: runs[r][0]["stats"]["newton_iterations"] for r in runs}
    v = {r: runs[r][0]["v_s_over_v_m"] for r in runs}
    kept = runs["default"][0]["stats"]["hessian_reuses"]
    print(f"{name:<18} {wall['0']:>11.3f} {wall['default']:>11.3f} {wall['default'] / wall['0']:>6.2f} {it['0']:>11} / {it['default']:<9} {kept:>6} {v['0']:>10.6f} {v['default']:>10.6f}")
print(f"(medians of {k} alternating runs; wall time is summary.json's wall_time_s)")
EOF
