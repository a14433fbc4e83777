#!/usr/bin/env bash
# The protocol study: is W/G alone the control parameter when the cells are dynamically
# similar? Runs the two verified 8 x 6 phase studies of docs/protocol/ (W through B at fixed
# v_m, today's default; W through g, every cell dynamically similar), copies their rows, lines
# and maps to docs/protocol/<protocol>/, and keeps lab/protocol/protocol_verdict.py's comparison as
# the record docs/results/protocol/. Resumable: rerun to finish an interrupted study.
#
#   lab/protocol/protocol.sh [OUT_DIR]        # default out/protocol
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-out/protocol}"
. tools/build.sh
use_slither
for p in stiffness gravity; do
    "$SLITHER" phase "docs/protocol/$p.toml" --out "$out/$p" --quiet
    mkdir -p "docs/protocol/$p"
    cp "$out/$p"/{phase.csv,phase.json,boundaries.json,phase.png} "docs/protocol/$p/"
done
exec tools/record.sh protocol python3 lab/protocol/protocol_verdict.py \
    "stiffness=docs/protocol/stiffness" "gravity=docs/protocol/gravity"
