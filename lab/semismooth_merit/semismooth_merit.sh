#!/usr/bin/env bash
# The semi-smooth Newton's line search ([solver] semi_smooth_merit_memory): a full step is
# accepted against the largest merit of the last M accepted iterates (M = 1: monotone). Runs,
# with lab/programs/contact_scaling.rs and for each M, the bundled S-start (100 elements, BDF2 at
# 3.6e-3 s), the same at 200 elements, and the whole S-start with implicit Euler at 1e-3 s on
# 200 elements and at 5e-4 s on 200 and 400 elements. (Its records also ran the active set, the
# retired solver, on the same runs.)
# Keeps the output as a dated record docs/results/semismooth-merit/<date>.md.
#
#   lab/semismooth_merit/semismooth_merit.sh [MEMORIES]   # default 1,4,8; about 8 minutes
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh semismooth-merit "$0" --inner "${1:-1,4,8}"
fi
memories="$2"
case "$memories" in *[!0-9,]*) echo "semismooth_merit.sh: MEMORIES are comma-separated whole numbers" >&2; exit 2 ;; esac
. tools/build.sh
bin="$(lab_program contact_scaling)"
runs() {
    "$bin" "$@" --elements 100,200 --dt 3.6e-3 --integrator bdf2 --duration full
    "$bin" "$@" --elements 200 --dt 1e-3 --duration full
    "$bin" "$@" --elements 200,400 --dt 5e-4 --duration full
}
for mem in ${memories//,/ }; do
    runs --contact semi-smooth --merit-memory "$mem"
done
