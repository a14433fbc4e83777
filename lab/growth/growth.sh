#!/usr/bin/env bash
# The growth line of problems/growth.toml (anacondas of 1 to 10 cm on the regime map, every
# size verified): runs the study into docs/growth (or resumes it: finished rows are reused),
# then prints its sizes as a table (lab/growth/growth_table.py), kept as a dated record under
# docs/results/growth/ by tools/record.sh.
#
#   lab/growth/growth.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
. tools/build.sh
use_slither
exec tools/record.sh growth bash -c \
    '"$SLITHER" phase problems/growth.toml --out docs/growth --quiet && python3 lab/growth/growth_table.py docs/growth/growth.json'
