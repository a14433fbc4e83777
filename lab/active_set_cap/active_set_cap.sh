#!/usr/bin/env bash
# HISTORY: this script cannot run any more. Its question was the retired active-set contact
# solver (retired in the contact-room rebuild; the measurement that justified it is the record
# docs/results/active-set-need/latest.md). It stays for its records; to rerun it, check out
# commit b95063e, the last with the active set.
# The active set's iteration cap ([solver] active_set_max_iterations): a step that reaches it
# falls back to the conic program, which costs as much as hundreds of active-set iterations at
# 400 elements. Runs the whole S-start with implicit Euler at dt 5e-4 on 400 elements for each
# cap and two trajectories (the file, and mu_forward + 1e-8: the statistics depend on the
# trajectory, which round-off changes), with lab/programs/contact_scaling.rs, and keeps the output
# as a dated record docs/results/active-set-cap/<date>.md.
#
#   lab/active_set_cap/active_set_cap.sh [CAPS] [ELEMENTS]   # default 40,60,80,100,150 and 400; ~7 min
set -euo pipefail
echo "$(basename "$0"): the active-set contact solver was retired; this script is history (see its header)" >&2
exit 2
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh active-set-cap "$0" --inner "${1:-40,60,80,100,150}" "${2:-400}"
fi
caps="$2"
elements="$3"
case "$caps$elements" in *[!0-9,]*) echo "active_set_cap.sh: CAPS and ELEMENTS are comma-separated whole numbers" >&2; exit 2 ;; esac
. tools/build.sh
bin="$(lab_program contact_scaling)"
for perturb in 0 1e-8; do
    for cap in ${caps//,/ }; do
        "$bin" --elements "$elements" --duration full --cap "$cap" --perturb "$perturb"
    done
done
