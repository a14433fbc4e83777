#!/usr/bin/env bash
# How well the S-start's converged v_s/v_m is known: the scene of problems/s_start.toml at 400
# elements with BDF2 at fixed steps from 3.6e-3 s down to 2.25e-4 s (the implicit Euler ladder
# is in the records s-start-reference and accuracy-s-start), then two ensembles of 8 runs each
# (`--ensemble 8`: friction and initial shape perturbed by about 1e-3, the step on a ladder
# from 0.4 to 2.5 times the file's) from implicit Euler at 5e-4 s and from BDF2 at 1.8e-3 s.
# Prints every run and, pooled over the runs at small steps (implicit Euler at most 7.5e-4 s,
# BDF2 at most 2.1e-3 s, where neither integrator's values drift with the step), the mean, the
# standard deviation and the range. Kept as a dated record docs/results/converged-s-start/<date>.md.
#
#   lab/converged_s_start/converged_s_start.sh        # 21 runs at 400 elements, about 4 min on 2 cores
#                                                     # (contact on the curve; 20 min with node contacts)
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh converged-s-start "$0" "$@"
fi
. tools/build.sh
use_slither
slither="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
grep -q '^integrator = "bdf2"' problems/s_start.toml || { echo "problems/s_start.toml: not BDF2" >&2; exit 1; }
scene() { # elements dt integrator -> file
    local f="$tmp/s_$1_$2_$3.toml"
    sed -e "s/^elements = .*/elements = $1/" -e "s/^dt = .*/dt = $2/" \
        -e "s/^integrator = .*/integrator = \"$3\"/" problems/s_start.toml >"$f"
    echo "$f"
}
echo "| integrator | step (s) | v_s/v_m | Newton it/step | fallbacks | halvings | wall s |"
echo "|---|---|---|---|---|---|---|"
for dt in 3.6e-3 1.8e-3 9e-4 4.5e-4 2.25e-4; do
    f="$(scene 400 "$dt" bdf2)"
    "$slither" run "$f" --out "$tmp/out" --no-plots --quiet
    jq -r --arg dt "$dt" '"| BDF2 | \($dt) | \(.v_s_over_v_m * 100000 | round / 100000) | \(.stats.newton_iterations / .stats.steps * 100 | round / 100) | \(.stats.semismooth_fallbacks) | \(.stats.step_halvings) | \(.wall_time_s * 10 | round / 10) |"' "$tmp/out/summary.json"
    jq -r --arg dt "$dt" '"bdf2 \($dt) \(.v_s_over_v_m)"' "$tmp/out/summary.json" >>"$tmp/rows"
done
for spec in "implicit 5e-4" "bdf2 1.8e-3"; do
    set -- $spec
    f="$(scene 400 "$2" "$1")"
    "$slither" run "$f" --out "$tmp/ens_$1" --no-plots --quiet --ensemble 8
    jq -r --arg i "$1" '.ensemble.members[] | "\($i) \(.dt) \(.observables.v_s_over_v_m)"' "$tmp/ens_$1/summary.json" >>"$tmp/rows"
done
python3 - "$tmp/rows" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
members = [r for r in rows if len(r) == 3]
print()
print("Every run (the ladder above, then the ensembles' members), step and v_s/v_m:")
print()
print("| integrator | step (s) | v_s/v_m |")
print("|---|---|---|")
for i, dt, v in members:
    print(f"| {i} | {float(dt):.3e} | {float(v):.5f} |")
small = {"implicit": 7.5e-4, "bdf2": 2.1e-3}
print()
print("| runs at small steps | n | mean | sd | min | max |")
print("|---|---|---|---|---|---|")
pooled = []
for i in ("implicit", "bdf2"):
    v = [float(r[2]) for r in members if r[0] == i and float(r[1]) <= small[i]]
    pooled += v
    print(f"| {i} (step <= {small[i]:.2e} s) | {len(v)} | {statistics.mean(v):.5f} | {statistics.stdev(v):.5f} | {min(v):.5f} | {max(v):.5f} |")
print(f"| both | {len(pooled)} | {statistics.mean(pooled):.5f} | {statistics.stdev(pooled):.5f} | {min(pooled):.5f} | {max(pooled):.5f} |")
PY
