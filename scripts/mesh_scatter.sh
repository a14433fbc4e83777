#!/usr/bin/env bash
# v_s/v_m of the bundled S-start against the element count, at fixed steps small enough that
# the step error is below the mesh-to-mesh scatter (BDF2 at 2e-3 s and implicit Euler at
# 5e-4 s), with the chart docs/images/s_start_mesh_scatter.png; kept as a dated record
# docs/results/s-start-mesh-scatter/<date>.md. The converged interval 0.31965 to 0.32053 is
# the 400-element runs at four steps (record s-start-reference and the guide's S-start table).
#
#   scripts/mesh_scatter.sh
#
# SLITHER_EXAMPLES names a folder of built examples to use instead of building them.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec scripts/record.sh s-start-mesh-scatter "$0" "$@"
fi
if [ -n "${SLITHER_EXAMPLES:-}" ]; then
    scan="$SLITHER_EXAMPLES/convergence_scan"
else
    cargo build --release --quiet --example convergence_scan
    scan="${CARGO_TARGET_DIR:-target}/release/examples/convergence_scan"
fi
mkdir -p out/mesh_scatter docs/images
meshes=30,35,40,45,50,55,60,64,70,75,80,90,100,110,120,128,140,150,175,200
reference=0.31965,0.32053
"$scan" problems/s_start.toml 0 "$meshes" 2e-3 --bdf2 --reference "$reference" \
    --csv out/mesh_scatter/bdf2_2e-3.csv --chart docs/images/s_start_mesh_scatter.png
"$scan" problems/s_start.toml 0 "$meshes" 5e-4 --reference "$reference" \
    --csv out/mesh_scatter/implicit_5e-4.csv --chart out/mesh_scatter/implicit_5e-4.png
