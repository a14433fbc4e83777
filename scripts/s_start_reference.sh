#!/usr/bin/env bash
# The bundled S-start's v_s/v_m at given meshes and fixed implicit Euler steps (reference
# values for --accuracy and the work-precision chart), kept as a dated record
# docs/results/s-start-reference/<date>.md; with --heavy the heavy S-start's
# (problems/s_start_heavy.toml, record s-start-heavy-reference).
#
#   scripts/s_start_reference.sh ELEMENTS:DT [ELEMENTS:DT ...]    # e.g. 400:1.25e-4 200:6.25e-5
#   scripts/s_start_reference.sh --heavy 50:5e-4 100:5e-4
#
# SLITHER names a built binary to use instead of building one (`cargo build --release`).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
scene=s_start
if [ "${1:-}" = "--heavy" ]; then
    scene=s_start_heavy
fi
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec scripts/record.sh "${scene//_/-}-reference" "$0" "$@"
fi
[ "${1:-}" = "--heavy" ] && shift
if [ $# -lt 1 ]; then
    echo "usage: scripts/s_start_reference.sh [--heavy] ELEMENTS:DT [ELEMENTS:DT ...]" >&2
    exit 2
fi
if [ -n "${SLITHER:-}" ]; then
    slither="$SLITHER"
else
    cargo build --release --quiet
    slither="${CARGO_TARGET_DIR:-target}/release/slither"
fi
dir="out/${scene}_reference"
mkdir -p "$dir"
for model in "$@"; do
    elements="${model%%:*}"
    dt="${model#*:}"
    file="$dir/${scene}_${elements}_${dt}.toml"
    sed -e "s/^elements = 50$/elements = $elements/" -e "s/^dt = 2e-3$/dt = $dt/" \
        "problems/$scene.toml" > "$file"
    grep -q "^elements = $elements$" "$file" && grep -q "^dt = $dt$" "$file" || {
        echo "s_start_reference.sh: could not set elements and dt in $file" >&2
        exit 1
    }
    "$slither" run "$file" --no-plots --quiet --out "$dir/out_${elements}_${dt}"
    jq -r --arg n "$elements" --arg dt "$dt" \
        '"\($n) elements, dt \($dt) s: v_s/v_m \(.v_s_over_v_m), wall time \(.wall_time_s) s"' \
        "$dir/out_${elements}_${dt}/summary.json"
done
