#!/usr/bin/env bash
# Two S-starts in two Python threads against one alone (scripts/python_threads.py), kept as a
# dated record under docs/results/python-threads/ by scripts/record.sh. PYTHON names the
# interpreter with slither_gait installed (default python3).
#
#   PYTHON=.venv/bin/python scripts/python_threads.sh [REPEATS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
exec scripts/record.sh python-threads "${PYTHON:-python3}" scripts/python_threads.py "$@"
