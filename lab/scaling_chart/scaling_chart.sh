#!/usr/bin/env bash
# The cost of the S-start against the element count, slither beside PyElastica, in one window:
# 1. compare/stable_steps.sh: PyElastica 1.0 on its own S-start scene at its largest stable
#    step for 50, 100, 200, 400 and 800 elements (each checked: the next larger step flings the
#    rod), timed over the whole 4 s;
# 2. lab/programs/contact_scaling.rs on the same scene (problems/pyelastica_s_start.toml), its
#    first 0.5 s with implicit Euler at dt 5e-4 and 1e-3 s at the same element counts, with
#    the per-step counts (Newton iterations, factorisations, fallbacks, halvings);
# 3. the chart docs/images/contact_scaling.png (log-log, wall seconds per simulated second).
# Kept as a dated record under docs/results/contact-scaling-chart/ (tools/record.sh).
# Needs compare/.venv (compare/run.sh creates it). About 25 minutes on a 2-core machine.
#
#   lab/scaling_chart/scaling_chart.sh [ELEMENTS:STABLE:UNSTABLE ...]   # PyElastica's step pairs
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ -z "${SLITHER_RECORDING:-}" ]; then
    exec tools/record.sh contact-scaling-chart "$(pwd)/lab/scaling_chart/scaling_chart.sh" "$@"
fi
triples=("$@")
[ ${#triples[@]} -gt 0 ] || triples=(50:1e-4:1.2e-4 100:7e-5:8e-5 200:3.5e-5:4e-5 400:1.8e-5:2e-5 800:9e-6:1e-5)
elements="$(printf '%s\n' "${triples[@]}" | cut -d: -f1 | paste -sd,)"
. tools/build.sh
scaling="$(lab_program contact_scaling)"
pe_csv="docs/results/contact-scaling-chart/pyelastica_steps.csv"
mkdir -p "$(dirname "$pe_csv")"
echo "## PyElastica 1.0 at its largest stable step (whole scene)"
compare/stable_steps.sh "$pe_csv" "${triples[@]}"
echo
echo "## slither, the same scene, first 0.5 s"
"$scaling" \
    --scene problems/pyelastica_s_start.toml --elements "$elements" --duration 0.5 \
    --dt 5e-4,1e-3 --chart docs/images/contact_scaling.png --pyelastica "$pe_csv"
