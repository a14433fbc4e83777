#!/usr/bin/env bash
# Two S-starts in two Python threads against one alone (lab/python_threads/python_threads.py), kept as a
# dated record under docs/results/python-threads/ by tools/record.sh. PYTHON names the
# interpreter with slither_gait installed (default python3).
#
#   PYTHON=.venv/bin/python lab/python_threads/python_threads.sh [REPEATS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
exec tools/record.sh python-threads "${PYTHON:-python3}" lab/python_threads/python_threads.py "$@"
