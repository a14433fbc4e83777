#!/usr/bin/env bash
# The contact Newton's scaling benchmark: the bundled S-start's first 0.5 s with
# implicit Euler at dt 5e-4 s at 50, 100, 200 and 400 elements (pass other arguments through to
# lab/programs/contact_scaling.rs, e.g. --elements 200,400,800 --duration 1.5, or --duration full
# for the whole scene with v_s/v_m), kept as a dated record under docs/results/contact-scaling/
# by tools/record.sh. Per element count: Newton iterations, factorisations and conic fallbacks
# per step, step halvings, microseconds per step per element, wall seconds per simulated second
# and the time split.
#
#   lab/contact_scaling/contact_scaling.sh [--record NAME] [ARGS...]
#
# --record NAME keeps the record under docs/results/NAME/ instead (for a configuration the guide
# cites on its own, e.g. contact-scaling-whole for --elements 200,400 --duration full).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
name=contact-scaling
if [ "${1:-}" = "--record" ]; then
    name="${2:?--record needs a NAME}"
    shift 2
fi
. tools/build.sh
scaling="$(lab_program contact_scaling)"
exec tools/record.sh "$name" "$scaling" "$@"
