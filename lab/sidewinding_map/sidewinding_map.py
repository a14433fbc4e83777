#!/usr/bin/env python3
"""Tabulate lab/sidewinding_map/sidewinding_map.sh's cells: per (W, G), whether the gait sidewinds at the
scene's mesh and at twice its elements, with the per-cycle extremes it is decided by
(summary.json `periodic`). Usage: lab/sidewinding_map/sidewinding_map.py OUT_DIR"""
import json
import os
import sys

out = sys.argv[1]


def cell(name):
    path = os.path.join(out, name, "summary.json")
    if not os.path.exists(path):
        return None
    s = json.load(open(path))
    return s.get("periodic"), s.get("regime"), s.get("v_s_over_v_m")


print("| W | G | sidewinds (100 el. / 200 el.) | margin | displacement min (L) | broadside min (deg) "
      "| turn max (deg) | stationary share min | regime |")
print("|---|---|---|---|---|---|---|---|---|")
yes = both = 0
for w in ("100", "300", "900"):
    for g in ("10", "15", "22.5"):
        a, b = cell(f"w{w}_g{g}"), cell(f"w{w}_g{g}_x2")
        if a is None or a[0] is None:
            print(f"| {w} | {g} | failed | | | | | | |")
            continue
        p = a[0]
        sa = "yes" if p["sidewinding"] else "no"
        sb = "-" if b is None or b[0] is None else ("yes" if b[0]["sidewinding"] else "no")
        yes += p["sidewinding"]
        both += p["sidewinding"] and sb == "yes"
        print(f"| {w} | {g} | {sa} / {sb} | {p['sidewinding_margin']:+.3f} "
              f"| {p['displacement_over_length_min']:.3f} | {p['broadside_deg_min']:.1f} "
              f"| {p['turn_deg_max_abs']:.1f} | {p['stationary_contact_share_min']:.3f} | {a[1]} |")
print()
print(f"sidewinding at the scene's mesh: {yes} of 9 cells; confirmed at twice the elements: {both}")
