#!/usr/bin/env bash
# Why the bundled S-start runs 100 elements with BDF2 at fixed steps of 3.6e-3 s: the scene of
# problems/s_start.toml on 92 to 120 elements (every 4th) at BDF2 steps of 3e-3 and 3.6e-3 s,
# each mesh's v_s/v_m and its error against 0.3201 (the middle of the converged 0.3197 to
# 0.3205, implicit Euler at 400 elements; record accuracy-s-start), and per step the mean and
# standard deviation over the meshes: a mesh's own value scatters by about 1 % from one mesh
# to the next (record s-start-mesh-scatter), so the neighbours' mean is the mesh error the
# file's run is a sample of. Kept as a dated record docs/results/bundled-choice/<date>.md.
#
#   lab/bundled_choice/bundled_choice.sh         # 16 runs, about 20 s
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh bundled-choice "$0" "$@"
fi
. tools/build.sh
use_slither
slither="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
grep -q '^integrator = "bdf2"' problems/s_start.toml || { echo "problems/s_start.toml is not BDF2" >&2; exit 1; }
for dt in 3e-3 3.6e-3; do
    for n in 92 96 100 104 108 112 116 120; do
        f="$tmp/s_start_${n}_$dt.toml"
        sed -e "s/^elements = .*/elements = $n/" -e "s/^dt = [0-9.e-]*/dt = $dt/" problems/s_start.toml >"$f"
        "$slither" run "$f" --out "$tmp/out" --no-plots --quiet
        jq -r --arg dt "$dt" --arg n "$n" '"\($dt) \($n) \(.v_s_over_v_m) \(.wall_time_s) \(.stats.newton_iterations) \(.stats.steps) \(.stats.step_halvings)"' "$tmp/out/summary.json" >>"$tmp/rows"
    done
done
python3 - "$tmp/rows" <<'PY'
import statistics, sys
ref = 0.3201
rows = [l.split() for l in open(sys.argv[1])]
print("| BDF2 step (s) | elements | v_s/v_m | error | wall time (s) | Newton it/step | halvings |")
print("|---|---|---|---|---|---|---|")
for dt, n, v, w, it, st, h in rows:
    print(f"| {dt} | {n} | {float(v):.5f} | {100 * (float(v) / ref - 1):+.2f} % | {float(w):.2f} | {int(it) / int(st):.2f} | {h} |")
for dt in sorted({r[0] for r in rows}):
    errs = [100 * (float(r[2]) / ref - 1) for r in rows if r[0] == dt]
    wall = [float(r[3]) for r in rows if r[0] == dt]
    print(f"dt {dt} s: mean error {statistics.mean(errs):+.2f} %, standard deviation {statistics.stdev(errs):.2f} %, "
          f"largest {max(errs, key=abs):+.2f} %, mean wall time {statistics.mean(wall):.2f} s")
PY
