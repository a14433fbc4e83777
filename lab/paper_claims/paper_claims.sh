#!/usr/bin/env bash
# The numbers of the guide's chapter "The paper, claim by claim" (docs/book/src/claims.md), as
# one dated record, docs/results/paper-claims/<date>.md. About a minute on 2 cores.
#
#   lab/paper_claims/paper_claims.sh [OUT]          (default OUT: out/paper_claims)
#
# It runs the bundled S-start (Fig. 2, the lambda pulse), one friction-dominated and one
# flailing cell of the 20 x 20 map (the lambda pulse outside the S-start) and the bundled
# sidewinding; it redraws the verified 20 x 20 map with self-contact from its committed table
# (docs/phase_fine_self_contact_verified/phase.csv: every cell is reused, none simulated),
# which writes the paper's Fig. 3 charts, and reads the growth line with self-contact from
# docs/growth_self_contact/growth.json (record self-contact-growth); then
# lab/paper_claims/paper_claims.py prints the numbers, one `key value` per line.
# The charts the chapter shows are copied to docs/claims/.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh paper-claims "$0" --inner "${1:-out/paper_claims}"
fi
out="$2"
. tools/build.sh
use_slither
bin="$SLITHER"
rm -rf "$out"
mkdir -p "$out/map" "$out/growth" docs/claims
"$bin" run problems/s_start.toml --out "$out/s_start" --quiet
"$bin" run problems/sidewinding.toml --out "$out/sidewinding" --quiet --no-plots
# A friction-dominated cell (W 264, G 6.95: F in the verified map, its base run and its finer one) and a flailing one
# (W 88.6, G 23.4: U), each as `slither run` would run it.
"$bin" phase problems/phase_fine.toml --cell-index 9,8 --out "$out/friction" --quiet --no-plots
"$bin" phase problems/phase_fine.toml --cell-index 6,13 --out "$out/flailing" --quiet --no-plots
cp docs/phase_fine_self_contact_verified/phase.csv "$out/map/"
# Every cell of the committed table is reused only if it was made with this build's effective
# base problem (its hash); a table made with other settings (until 2026-12-06 the contact
# Newton's iteration caps of 100, now 300) would be simulated again, about half an hour on 2
# cores, so the script stops if any cell is not reused (and after 5 min at most): make the map
# again with lab/self_contact_phase_verified/self_contact_phase_verified.sh.
timeout 300 "$bin" phase problems/phase_fine.toml --out "$out/map" --quiet \
    --set "phase.verify={ finer = true, perturbations = 4 }" 2>&1 | tee "$out/map.log"
grep -q "(0 simulated, 400 reused" "$out/map.log" ||
    { echo "paper_claims.sh: the verified map was not all reused (see $out/map.log)" >&2; exit 1; }
cp docs/growth_self_contact/growth.json "$out/growth/"
cp "$out/map/writhe_vs_ratio.png" "$out/map/speed_vs_writhe.png" "$out/map/speed_vs_ratio.png" \
    docs/claims/
cp "$out/s_start/kymograph_elevation.png" "$out/s_start/kymograph_slip.png" \
    "$out/s_start/kymograph_lambda.png" docs/claims/
python3 lab/paper_claims/paper_claims.py "$out"
