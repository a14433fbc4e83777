#!/usr/bin/env bash
# The scripted sidewinding search (lab/sidewinding_search/sidewinding_search.py), kept as a record under
# docs/results/sidewinding-search/ with every run's row in docs/results/sidewinding/search-*.csv:
# a random scan of the gait box at 100 elements, then (1 + 1) steps at the optimizer's fixed
# bend scales from the best points it found. Each run is one thread, 5 to 15 s on 2 shared
# cores.
#
#   lab/sidewinding_search/sidewinding_search.sh [RANDOM_RUNS [LOCAL_STEPS]]    # default 120 20
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh sidewinding-search "$0" "$@"
fi
. tools/build.sh
use_slither
slither="$SLITHER"
mkdir -p docs/results/sidewinding
day="$(date -u +%Y-%m-%d)"
for mode in random local; do
    csv="docs/results/sidewinding/search-$mode-$day.csv"
    rm -f "$csv"
    if [ "$mode" = random ]; then n="${1:-120}"; seed=1; else n="${2:-20}"; seed=11; fi
    python3 lab/sidewinding_search/sidewinding_search.py "$slither" "$mode" "$n" "$seed" "$csv"
    echo "rows: $csv"
    echo
done
