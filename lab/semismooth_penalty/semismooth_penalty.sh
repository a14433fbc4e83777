#!/usr/bin/env bash
# The semi-smooth Newton's penalty ([solver] semi_smooth_penalty, a multiple of each contact
# node's inertia stiffness): it decides the branch each iterate takes, not the solution. Runs,
# with lab/programs/contact_scaling.rs and for each penalty, the bundled S-start (100 elements,
# BDF2 at 3.6e-3 s), 200 elements with BDF2 at 3.6e-3 and 5e-3 s, and the whole S-start with
# implicit Euler at 5e-4 s on 200 and 400 elements. Keeps the output as a dated record
# docs/results/semismooth-penalty/<date>.md.
#
#   lab/semismooth_penalty/semismooth_penalty.sh [PENALTIES]   # default 1,3,10,30; about 4 minutes
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh semismooth-penalty "$0" --inner "${1:-1,3,10,30}"
fi
penalties="$2"
case "$penalties" in *[!0-9.,e-]*) echo "semismooth_penalty.sh: PENALTIES are comma-separated positive numbers" >&2; exit 2 ;; esac
. tools/build.sh
bin="$(lab_program contact_scaling)"
for pen in ${penalties//,/ }; do
    args=(--contact semi-smooth --penalty "$pen" --duration full)
    "$bin" "${args[@]}" --elements 100 --dt 3.6e-3 --integrator bdf2
    "$bin" "${args[@]}" --elements 200 --dt 3.6e-3,5e-3 --integrator bdf2
    "$bin" "${args[@]}" --elements 200,400 --dt 5e-4
done
