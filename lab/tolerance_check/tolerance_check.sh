#!/usr/bin/env bash
# Do the solver's stopping rules decide the answer? Every bundled scene at the default
# [solver] tolerances and 100x tighter (lab/programs/tolerance_check.rs), kept as a dated record
# docs/results/tolerance-check/<date>.md. About 15 s of simulation on one core.
#
#   lab/tolerance_check/tolerance_check.sh [SCENE.toml ...]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
. tools/build.sh
check="$(lab_program tolerance_check)"
exec tools/record.sh tolerance-check "$check" "$@"
