#!/usr/bin/env bash
# Where the Newton iterations go, contact at the nodes against contact on the curve
# ([solver] ground_points): the bundled S-start (BDF2) at 100 and 200 elements and five steps
# around the bundled 3.6e-3 s (one step alone is decided by a few failed attempts of 100
# iterations each), each run's debug log split into converged and failed semi-smooth attempts
# (iterations.py); kept as the dated record docs/results/ground-points-iterations/<date>.md.
#
#   lab/ground_points/iterations.sh          # about 2 min on 2 cores
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points-iterations "$0" "$@"
fi
. tools/build.sh
use_slither
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
for n in 100 200; do
    for points in nodes curve; do
        for dt in 3.4e-3 3.5e-3 3.6e-3 3.7e-3 3.8e-3; do
            echo "$n $points $dt"
        done
    done
done | xargs -P 2 -n 3 sh -c 'SLITHER_DEBUG=1 "$0" run problems/s_start.toml --out "$1/$2_$3_$4" --no-plots --quiet --force --set rod.elements="$2" --set solver.ground_points="\"$3\"" --set time.dt="$4" >/dev/null 2>"$1/$2_$3_$4.log"' "$SLITHER" "$tmp"
python3 lab/ground_points/iterations.py "$tmp"
