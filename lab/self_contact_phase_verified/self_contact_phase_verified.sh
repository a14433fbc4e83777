#!/usr/bin/env bash
# The 20 x 20 map of problems/phase_fine.toml with self-contact (the default) and per-cell
# verification: every cell re-run on twice the elements and four times perturbed
# (`verify = { finer = true, perturbations = 4 }`, set from the command line), its label
# agreement and its v_s/v_m range in phase.csv. Compared with the same map without
# verification (docs/phase_fine_self_contact/phase.csv, the same physics): label counts,
# transitions and the uncertain cells (agreement below 1). The study resumes: rerun into the
# same OUT (default out/phase_fine_verified) after an interruption. Its phase.csv and phase.png
# are copied to docs/phase_fine_self_contact_verified/; kept as a dated record
# docs/results/self-contact-phase-verified/<date>.md.
#
#   lab/self_contact_phase_verified/self_contact_phase_verified.sh [OUT]   # about 28 min on 2 cores
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh self-contact-phase-verified "$0" --inner "${1:-out/phase_fine_verified}"
fi
out="$2"
. tools/build.sh
use_slither
bin="$SLITHER"
"$bin" phase problems/phase_fine.toml --out "$out" --quiet \
    --set "phase.verify={ finer = true, perturbations = 4 }"
mkdir -p docs/phase_fine_self_contact_verified
cp "$out/phase.csv" "$out/phase.png" docs/phase_fine_self_contact_verified/
python3 lab/phase_report/phase_summary.py "$out"
python3 lab/self_contact_phase_verified/phase_compare.py docs/phase_fine_self_contact/phase.csv "$out/phase.csv" \
    "without verification" "with verification"
