#!/usr/bin/env bash
# The phase grid of problems/phase_pyelastica_straight.toml (PyElastica's "closer to a straight
# S-start" scene, W 30, 100, 300, 1000, 3000 x G 5, 10, 20, 40) side by side: slither at the
# phase file's base (200 elements, implicit Euler 1e-3 s) and PyElastica 1.0 with the muscles
# as a rest curvature at 50 and 200 elements, each PyElastica run labelled by slither's own
# regime rules from its frames (tests/pyelastica_phase.rs). Two stages, each a dated record:
#
#   lab/pyelastica_phase/pyelastica_phase.sh pe      # record pyelastica-phase-pe (PyElastica's 40 runs)
#   lab/pyelastica_phase/pyelastica_phase.sh label   # record pyelastica-phase (slither's 20 cells, the table)
#
# PyElastica's step per cell: its largest stable step on this mesh at W 300 (1e-4 s at 50
# elements, 3.5e-5 s at 200), times sqrt(W / 300) below W 300 (B, and so the bending and
# stretching wave speeds, scale with 1 / W), rounded down to a whole fraction of the 0.02 s
# frame interval; a run that is not stable is rerun once at half the step.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
stage="${1:-}"
case "$stage" in
    pe|label)
        if [ -z "${SLITHER_RECORDING:-}" ]; then
            name=pyelastica-phase
            [ "$stage" = pe ] && name=pyelastica-phase-pe
            exec tools/record.sh "$name" "$0" "$stage"
        fi ;;
    *) echo "usage: lab/pyelastica_phase/pyelastica_phase.sh pe|label" >&2; exit 2 ;;
esac
out="out/pyelastica_phase"
mkdir -p "$out"
venv="compare/.venv"
if [ "$stage" = pe ]; then
    [ -x "$venv/bin/python" ] || { echo "compare/.venv is missing: run compare/run.sh once" >&2; exit 2; }
    for n in ${PHASE_ELEMENTS:-50 200}; do
        for w in 30.0 100.0 300.0 1000.0 3000.0; do
            for g in 5.0 10.0 20.0 40.0; do
                dt="$("$venv/bin/python" -c "
import math
limit = {50: 1e-4, 200: 3.5e-5}[$n] * min(1.0, math.sqrt($w / 300.0))
print(0.02 / math.ceil(0.02 / limit))")"
                for try in 1 2; do
                    "$venv/bin/python" compare/pyelastica_s_start.py --scene straight --W "$w" \
                        --G "$g" --elements "$n" --dt "$dt" --frames-out "$out/pe_${n}_${w}_${g}.json" \
                        --out "$out/pe_${n}_${w}_${g}.summary.json" > /dev/null
                    stable="$("$venv/bin/python" -c "import json; print(json.load(open('$out/pe_${n}_${w}_${g}.summary.json'))['stable'])")"
                    v="$("$venv/bin/python" -c "import json; j=json.load(open('$out/pe_${n}_${w}_${g}.summary.json')); print(f\"{j['v_s_over_v_m']:.4f} {j['max_height_over_a']:.3g} {j['wall_per_sim_second']:.2f}\")")"
                    echo "PyElastica $n elements, W $w, G $g, dt $dt: stable $stable, v_s/v_m, max height / a, wall s per simulated s: $v"
                    [ "$stable" = True ] && break
                    dt="$("$venv/bin/python" -c "print($dt / 2)")"
                done
            done
        done
    done
    exit 0
fi
PE_PHASE_DIR="$out" cargo test --release --test pyelastica_phase -- --ignored --nocapture
