#!/usr/bin/env bash
# Criterion benchmarks (`cargo bench`, arguments passed on, e.g. `--bench s_start`), kept as a
# dated record docs/results/bench/<date>.md with the machine, build and load.
#
#   lab/bench/bench.sh --bench s_start
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
exec tools/record.sh bench cargo bench "$@"
