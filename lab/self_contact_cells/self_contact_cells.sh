#!/usr/bin/env bash
# The twelve cells of problems/phase_fine.toml in which the body passed through itself before
# self-contact existed (W 29.8, 127.4 and 545.6, each at G 14.4, 23.4, 37.9 and 100), each
# re-run with `slither phase --cell` twice: with self-contact off ([self_contact] enabled =
# false: the physics of the builds before it, unchanged to the bit) and on (the default).
# Per cell: the regime, v_s/v_m, the closest centreline distance between parts more than 2a
# apart along the body over a (summary.json self_contact.closest_over_a: every step and
# frame), the frames closer than a (trajectory.npz closest_distance), and with self-contact
# the steps with active pairs, the most pairs at once and the largest pair force. Kept as a
# dated record docs/results/self-contact-cells/<date>.md.
#
#   lab/self_contact_cells/self_contact_cells.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    exec tools/record.sh self-contact-cells "$0" --inner
fi
. tools/build.sh
use_slither
bin="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
python3 -c "import numpy" 2>/dev/null || { echo "self_contact_cells.sh: needs python3 with numpy" >&2; exit 2; }

weights="29.76351441631318 127.42749857031336 545.559478116852"
torques="14.38449888287663 23.357214690901223 37.926901907322495 100"
for on in false true; do
    d="$tmp/$on"
    mkdir -p "$d"
    cp problems/phase_fine.toml "$d/"
    cp problems/phase_fine_base.toml "$d/"
    printf '\n[self_contact]\nenabled = %s\n' "$on" >>"$d/phase_fine_base.toml"
    for w in $weights; do
        for g in $torques; do
            "$bin" phase "$d/phase_fine.toml" --cell "$w,$g" --out "$d/cell-$w-$g" >/dev/null
        done
    done
done

python3 - "$tmp" "$weights" "$torques" <<'EOF'
import json, sys
import numpy as np
tmp, weights, torques = sys.argv[1], sys.argv[2].split(), sys.argv[3].split()
print("| W | G | off: regime | off: closest / a | off: frames < a | on: regime | on: closest / a | on: frames < a | on: steps with pairs | on: most pairs | on: largest pair force (N) | on: wall s (off) | v_s/v_m off, on |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
worst = float("inf")
for w in weights:
    for g in torques:
        row = [f"{float(w):.1f}", f"{float(g):.1f}"]
        walls = {}
        vs = {}
        for on in ("false", "true"):
            d = f"{tmp}/{on}/cell-{w}-{g}"
            s = json.load(open(f"{d}/summary.json"))
            a = float(np.load(f"{d}/trajectory.npz")["diameter"][0])
            cd = np.load(f"{d}/trajectory.npz")["closest_distance"] / a
            c = s["self_contact"]["closest_over_a"]
            row += [str(s.get("regime")), f"{c:.4f}", f"{int((cd < 1).sum())} of {len(cd)}"]
            walls[on] = s["wall_time_s"]
            vs[on] = s["v_s_over_v_m"]
            if on == "true":
                sc = s["self_contact"]
                row += [str(sc["active_steps"]), str(sc["max_pairs"]), f"{sc['max_force']:.2f}"]
                worst = min(worst, c)
        row.append(f"{walls['true']:.2f} ({walls['false']:.2f})")
        row.append(f"{vs['false']:.4f}, {vs['true']:.4f}")
        print("| " + " | ".join(row) + " |")
print()
print(f"closest pair over the twelve cells with self-contact: {worst:.5f} a (required: at least {1 - 1e-3} a)")
EOF
