#!/usr/bin/env bash
# v_s/v_m of the bundled S-start against the element count (30 to 500), at fixed steps whose
# step error is below the scatter from one mesh to the next (BDF2 at 2e-3 s and implicit
# Euler at 5e-4 s; implicit Euler alone from 250 elements on), with the chart
# docs/images/s_start_mesh_scatter.png (30 to 200 elements), and with the couples moved by
# fractions of an element; kept as a dated record
# docs/results/s-start-mesh-scatter/<date>.md. The converged interval 0.31965 to 0.32053 is
# the 400-element runs at four steps (record s-start-reference and the guide's S-start table).
#
#   lab/mesh_scatter/mesh_scatter.sh
#
# SLITHER_EXAMPLES names a folder of built examples to use instead of building them.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh s-start-mesh-scatter "$0" "$@"
fi
. tools/build.sh
scan="$(lab_program convergence_scan)"
mkdir -p out/mesh_scatter docs/images
meshes=30,35,40,45,50,55,60,64,70,75,80,90,100,110,120,128,140,150,175,200
reference=0.31965,0.32053
"$scan" problems/s_start.toml 0 "$meshes" bdf2:2e-3,implicit:5e-4 --reference "$reference" \
    --csv out/mesh_scatter/coarse.csv --chart docs/images/s_start_mesh_scatter.png
# The fine meshes (implicit Euler only: 250 to 500 elements take 0.5 to 6 minutes each).
"$scan" problems/s_start.toml 0 250,300,350,450,500 implicit:5e-4 --reference "$reference" \
    --csv out/mesh_scatter/fine.csv
# The couples' sensitivity: all three centres moved toward the tail by 0.005, 0.01 and
# 0.015 L (a quarter, a half and three quarters of an element at 50 elements).
for shift in 0.005 0.01 0.015; do
    file="out/mesh_scatter/s_start_shift_$shift.toml"
    centers=$(awk -v d="$shift" 'BEGIN { printf "%.4f, %.4f, %.4f", 0.20 + d, 0.35 + d, 0.50 + d }')
    sed -e "s/^centers = \[0.20, 0.35, 0.50\]/centers = [$centers]/" problems/s_start.toml > "$file"
    grep -q "^centers = \[$centers\]" "$file" || {
        echo "mesh_scatter.sh: could not move the centres in $file" >&2
        exit 1
    }
    echo "centres moved by $shift L: [$centers]"
    "$scan" "$file" 0 50,100,200,400 implicit:5e-4 --reference "$reference" \
        --csv "out/mesh_scatter/shift_$shift.csv"
done
