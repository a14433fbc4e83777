#!/usr/bin/env bash
# The S-start's work-precision chart (error of v_s/v_m against the converged value, mesh and
# step, over wall time; `slither chart work-precision`), kept as a dated record
# docs/results/work-precision/<date>.md, its figures copied to docs/images/. Several minutes:
# implicit Euler at four steps, BDF2 at the bundled file's fixed 3.6e-3 s and adaptive BDF2
# at two tolerances on 50, 100 and 200 elements, the reference on 200 elements and the
# --accuracy 0.01 selection.
#
#   lab/work_precision/work_precision.sh [PROBLEM.toml]     # default problems/s_start.toml
#
# MESHES and BDF2_DT override the meshes (default 50,100,200) and the fixed BDF2 steps
# (default 3.6e-3), comma-separated.
#
# SLITHER names a built binary to use instead of building one (tools/build.sh). The
# reference is cached in out/work_precision/<scene>/reference.json (delete it to recompute).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh work-precision "$0" "$@"
fi
problem="${1:-problems/s_start.toml}"
. tools/build.sh
use_slither
slither="$SLITHER"
scene="$(basename "$problem" .toml)"
out="out/work_precision/$scene"
mkdir -p "$out" docs/images
"$slither" chart work-precision "$problem" --out "$out" \
    --meshes "${MESHES:-50,100,200}" --bdf2-dt "${BDF2_DT:-3.6e-3}"
cp "$out/gait_precision.png" "docs/images/work_precision_$scene.png"
cp "$out/gait_precision_centreline.png" "docs/images/work_precision_${scene}_centreline.png"
cp "$out/gait_precision.csv" "docs/images/work_precision_$scene.csv"
echo "figures: docs/images/work_precision_$scene.png, docs/images/work_precision_${scene}_centreline.png"
