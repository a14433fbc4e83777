#!/usr/bin/env bash
# HISTORY: this script cannot run any more. Its question was the retired active-set contact
# solver (retired in the contact-room rebuild; the measurement that justified it is the record
# docs/results/active-set-need/latest.md). It stays for its records; to rerun it, check out
# commit b95063e, the last with the active set.
# Whether a bundled scene still needs the active-set contact solver (the default before the
# semi-smooth Newton): every bundled dynamic scene with a ground, run once with each solver
# (`SLITHER_CONTACT=active-set` and `semi-smooth`), self-contact off in both (the active set
# has none; no bundled scene but the coil comes close, so its answers are those of the files
# as bundled). Per scene and solver: status, wall s of the time stepping, Newton iterations
# per step, conic fallbacks, step halvings and the headline number (v_s/v_m). Kept as a dated
# record docs/results/active-set-need/<date>.md.
#
#   lab/active_set_need/active_set_need.sh
set -euo pipefail
echo "$(basename "$0"): the active-set contact solver was retired; this script is history (see its header)" >&2
exit 2
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh active-set-need "$0" --inner
fi
. tools/build.sh
use_slither
bin="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
scenes="s_start s_start_heavy sidewinding serpenoid slide incline"
for s in $scenes; do
    cp "problems/$s.toml" "$tmp/$s.toml"
    printf '\n[self_contact]\nenabled = false\n' >>"$tmp/$s.toml"
    for solver in active-set semi-smooth; do
        SLITHER_CONTACT="$solver" "$bin" run "$tmp/$s.toml" --out "$tmp/$s-$solver" --no-plots --quiet || true
    done
done
python3 - "$tmp" "$scenes" <<'EOF'
import json, sys
tmp, scenes = sys.argv[1], sys.argv[2].split()
print("| scene | solver | status | wall s | Newton it. per step | conic fallbacks | halvings | v_s/v_m |")
print("|---|---|---|---|---|---|---|---|")
for s in scenes:
    for solver in ("active-set", "semi-smooth"):
        try:
            d = json.load(open(f"{tmp}/{s}-{solver}/summary.json"))
        except OSError:
            print(f"| {s} | {solver} | no summary | | | | | |")
            continue
        st = d["stats"]
        fb = st["active_set_fallbacks"] if solver == "active-set" else st["semismooth_fallbacks"]
        v = d.get("v_s_over_v_m")
        print(f"| {s} | {solver} | {d['status']} | {d['wall_time_s']:.2f} | "
              f"{st['newton_iterations'] / max(st['steps'], 1):.2f} | {fb} | {st['step_halvings']} | "
              f"{'-' if v is None else f'{v:.6f}'} |")
EOF
