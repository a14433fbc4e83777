#!/usr/bin/env bash
# How far the body sinks below the ground with each ground contact model ([solver]
# ground_points): the bundled S-start at its own step (BDF2 at 3.6e-3 s) and with implicit
# Euler at 5e-4 s, 100 and 200 elements; the largest depth of a node below a/2 over the run
# (summary.json's max_penetration), in m and in diameters, beside v_s/v_m and the iterations.
# Contacts on the curve hold their points, chosen at each step's start; the nodes between
# them may sink. Kept as the dated record docs/results/ground-points-penetration/<date>.md.
#
#   lab/ground_points/penetration.sh     # about 30 s
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points-penetration "$0" "$@"
fi
. tools/build.sh
use_slither
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
a=$(awk -F'[ =#]+' '/^diameter/ {print $2; exit}' problems/s_start.toml)  # the body's diameter (m)
echo "| contact | elements | integrator, step | v_s/v_m | Newton it/step | deepest node below a/2 (m) | in diameters |"
echo "|---|---|---|---|---|---|---|"
for n in 100 200; do
    for scheme in "bdf2 3.6e-3" "implicit 5e-4"; do
        read -r integrator dt <<<"$scheme"
        for points in nodes curve; do
            out="$tmp/$points-$n-$integrator"
            "$SLITHER" run problems/s_start.toml --out "$out" --no-plots --quiet --force \
                --set rod.elements="$n" --set solver.integrator="\"$integrator\"" \
                --set time.dt="$dt" --set solver.ground_points="\"$points\"" >"$out.log" 2>&1 \
                || { echo "| $points | $n | $integrator, $dt s | failed: $(tail -n 1 "$out.log") |"; continue; }
            jq -r --argjson a "$a" --arg p "$points" --arg n "$n" --arg s "$integrator, $dt s" \
                '"| \($p) | \($n) | \($s) | \(.v_s_over_v_m * 1e5 | round / 1e5) | \(.newton_iterations_mean * 100 | round / 100) | \(.max_penetration) | \(.max_penetration / $a) |"' \
                "$out/summary.json"
        done
    done
done
