#!/usr/bin/env python3
"""Print a phase study's growth line (its growth.json) as a Markdown table and its verdict.

    python3 lab/growth/growth_table.py OUT_DIR/growth.json
"""
import json
import sys


def main(path):
    with open(path) as f:
        g = json.load(f)
    law = g["growth"]
    print(
        f"Muscle stress {law['stress'] / 1e3:g} kPa (a / {law['reference_diameter'] * 100:g} cm)"
        f"^{law['exponent']:g}; Young's modulus {g['young_modulus'] / 1e6:.3f} MPa; "
        f"base diameter {g['base_diameter'] * 100:g} cm"
    )
    print()
    print("| a (cm) | L (m) | Gamma (kPa) | W | G | W/G | label | agreement | v_s/v_m | range |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for p in g["points"]:
        lo, hi = p["v_s_over_v_m_range"]
        label = p["regime"] + ("" if p["confident"] else "?")
        print(
            f"| {p['diameter'] * 100:.3g} | {p['length']:.3g} | {p['stress'] / 1e3:.3g} "
            f"| {p['weight']:.4g} | {p['torque']:.4g} | {p['w_over_g']:.3g} | {label} "
            f"| {p['label_agreement']:.2f} | {p['v_s_over_v_m']:.4f} | {lo:.4f} .. {hi:.4f} |"
        )
    print()
    print(f"Verdict: {g['verdict']}.")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: lab/growth/growth_table.py GROWTH_JSON")
    main(sys.argv[1])
