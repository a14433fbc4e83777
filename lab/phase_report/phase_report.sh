#!/usr/bin/env bash
# The counts, boundary slopes and Fig. 3 numbers of a finished `slither phase` directory
# (lab/phase_report/phase_summary.py), kept as a dated record docs/results/phase-NAME/<date>.md, NAME
# the directory's name.
#
#   lab/phase_report/phase_report.sh OUT_DIR
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
[ $# -eq 1 ] || { echo "usage: lab/phase_report/phase_report.sh OUT_DIR" >&2; exit 2; }
name="phase-$(basename "$1" | tr -c 'A-Za-z0-9_\n-' '-')"
exec tools/record.sh "$name" python3 lab/phase_report/phase_summary.py "$1"
