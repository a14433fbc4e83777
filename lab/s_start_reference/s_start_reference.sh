#!/usr/bin/env bash
# The bundled S-start's v_s/v_m at given meshes and fixed implicit Euler steps (reference
# values for --accuracy and the work-precision chart), kept as a dated record
# docs/results/s-start-reference/<date>.md; with --heavy the heavy S-start's
# (problems/s_start_heavy.toml, record s-start-heavy-reference). With --ensemble K each model
# runs as an ensemble of K members (`slither run --ensemble K`: friction and initial shape
# perturbed, the step on a ladder from dt/2.5 to 2.5 dt) and prints the members' mean, spread
# and range (record s-start-ensembles, or s-start-heavy-ensembles).
#
#   lab/s_start_reference/s_start_reference.sh ELEMENTS:DT [ELEMENTS:DT ...]    # e.g. 400:1.25e-4 200:6.25e-5
#   lab/s_start_reference/s_start_reference.sh --heavy 50:5e-4 100:5e-4
#   lab/s_start_reference/s_start_reference.sh --ensemble 8 50:5e-4 100:5e-4
#
# SLITHER names a built binary to use instead of building one (tools/build.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
scene=s_start
kind=reference
members=""
args=("$@")
while [ $# -gt 0 ]; do
    case "$1" in
        --heavy) scene=s_start_heavy; shift ;;
        --ensemble)
            members="${2:-}"
            case "$members" in
                ''|*[!0-9]*) echo "s_start_reference.sh: --ensemble takes a member count, got '$members'" >&2; exit 2 ;;
            esac
            kind=ensembles
            shift 2 ;;
        *) break ;;
    esac
done
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh "${scene//_/-}-$kind" "$0" "${args[@]}"
fi
if [ $# -lt 1 ]; then
    echo "usage: lab/s_start_reference/s_start_reference.sh [--heavy] [--ensemble K] ELEMENTS:DT [ELEMENTS:DT ...]" >&2
    exit 2
fi
. tools/build.sh
use_slither
slither="$SLITHER"
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
    out="$dir/out_${elements}_${dt}${members:+_ensemble_$members}"
    "$slither" run "$file" --no-plots --quiet --out "$out" ${members:+--ensemble "$members"}
    jq -r --arg n "$elements" --arg dt "$dt" \
        '"\($n) elements, dt \($dt) s: v_s/v_m \(.v_s_over_v_m), wall time \(.wall_time_s) s" +
         (.ensemble.stats.v_s_over_v_m // null | if . then "; ensemble of \(.n): mean \(.mean), sd \(.sd), min \(.min), max \(.max)" else "" end)' \
        "$out/summary.json"
done
