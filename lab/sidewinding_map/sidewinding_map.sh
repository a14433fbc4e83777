#!/usr/bin/env bash
# Where the bundled sidewinding gait sidewinds on the (W, G) map: every cell of
# docs/sidewinding_map/map.toml (3 x 3 around W = 300, G = 15) is run with `slither phase
# --cell` at the scene's mesh and at twice its elements (the check of the cell's verdict), two
# at a time, and lab/sidewinding_map/sidewinding_map.py tabulates each cell's sidewinding verdict and the
# criteria it is decided by, with its sidewinding margin (not a phase.csv column: `slither
# phase docs/sidewinding_map/map.toml` gives the rest at 100 elements directly). Kept as the
# record docs/results/sidewinding-map/.
#
#   lab/sidewinding_map/sidewinding_map.sh [OUT_DIR]      # default out/sidewinding_map
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ] && [ -z "${SLITHER_NO_RECORD:-}" ]; then
    exec tools/record.sh sidewinding-map "$0" "$@"
fi
out="${1:-out/sidewinding_map}"
. tools/build.sh
use_slither
slither="$SLITHER"
mkdir -p "$out"
# The finer copy: the same phase file over the scene at twice the elements.
awk '/^elements = / { print "elements = " $3 * 2; next } { print }' problems/sidewinding.toml \
    > "$out/sidewinding_x2.toml"
grep -q "^elements = " "$out/sidewinding_x2.toml"
sed -e "s#^base = .*#base = \"sidewinding_x2.toml\"#" docs/sidewinding_map/map.toml \
    > "$out/map_x2.toml"
jobs=()
for w in 100 300 900; do
    for g in 10 15 22.5; do
        jobs+=("docs/sidewinding_map/map.toml $w,$g $out/w${w}_g${g}")
        jobs+=("$out/map_x2.toml $w,$g $out/w${w}_g${g}_x2")
    done
done
printf '%s\n' "${jobs[@]}" | xargs -P 2 -L 1 sh -c \
    'RAYON_NUM_THREADS=1 "$0" phase "$1" --cell "$2" --out "$3" --quiet > "$3.log" 2>&1 || echo "failed: $1 $2 (see $3.log)"' "$slither"
python3 lab/sidewinding_map/sidewinding_map.py "$out"
