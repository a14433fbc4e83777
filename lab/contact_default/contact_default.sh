#!/usr/bin/env bash
# HISTORY: this script cannot run any more. Its question was the retired active-set contact
# solver (retired in the contact-room rebuild; the measurement that justified it is the record
# docs/results/active-set-need/latest.md). It stays for its records; to rerun it, check out
# commit b95063e, the last with the active set.
# Which contact solve should be the default: the active set and the semi-smooth Newton on the
# scenes users run, one after the other in one window, with lab/programs/contact_scaling.rs: the
# 50-element S-start (implicit Euler at 2e-3 s, the studies' base) and its heavy variant, the
# bundled S-start (100 elements, BDF2 at 3.6e-3 s), the whole S-start with implicit Euler at
# 5e-4 s on 200 and 400 elements, the first 4 s of the bundled sidewinding (100 elements,
# 2e-3 s) and the 50-element S-start with adaptive BDF2 at the default tolerance (5e-6).
# Keeps the output as a dated record docs/results/contact-default/<date>.md.
#
#   lab/contact_default/contact_default.sh      # about 2 minutes
set -euo pipefail
echo "$(basename "$0"): the active-set contact solver was retired; this script is history (see its header)" >&2
exit 2
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh contact-default "$0" --inner
fi
. tools/build.sh
bin="$(lab_program contact_scaling)"
runs=(
    "--scene problems/s_start_coarse.toml --elements 50 --dt 2e-3 --duration full"
    "--scene problems/s_start_heavy.toml --elements 50 --dt 2e-3 --duration full"
    "--elements 100 --dt 3.6e-3 --integrator bdf2 --duration full"
    "--elements 200,400 --dt 5e-4 --duration full"
    "--scene problems/sidewinding.toml --elements 100 --dt 2e-3 --duration 4"
    "--scene problems/s_start_coarse.toml --elements 50 --dt 2e-3 --adaptive 5e-6 --duration full"
)
for r in "${runs[@]}"; do
    for contact in active-set semi-smooth; do
        echo
        echo "## $contact: $r"
        # shellcheck disable=SC2086
        "$bin" --contact "$contact" $r 2>&1
    done
done
