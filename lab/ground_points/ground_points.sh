#!/usr/bin/env bash
# Ground contact at the nodes against between them ([solver] ground_points), measured on the
# bundled S-start: mesh scan, scatter about a trend, couple-shift ensembles, converged values
# and cost (lab/ground_points/ground_points.py); kept as the dated record
# docs/results/ground-points/<date>.md.
#
#   lab/ground_points/ground_points.sh [--fine] [--jobs N] [--points nodes,curve]
#                                      [--read-back nodes=BUILD]
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh ground-points "$0" "$@"
fi
. tools/build.sh
use_slither
exec python3 lab/ground_points/ground_points.py "$@"
