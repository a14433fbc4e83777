#!/usr/bin/env python3
"""Scripted search for a sidewinding gait: variants of problems/sidewinding.toml run with
`slither run`, each measured by the `periodic` block of its summary.json (the sidewinding
criteria: broadside >= 60 deg, |turn| <= 5 deg, >= 0.1 L per cycle, stationary share of the
contact time >= 0.8, in each of >= 4 cycles after the first).

    lab/sidewinding_search/sidewinding_search.py SLITHER random N SEED CSV   # N points drawn in the box
    lab/sidewinding_search/sidewinding_search.py SLITHER local N SEED CSV    # (1 + 1) steps from the seeds

Every run: 100 elements, dt = 2e-3 s, six launch periods, one thread. `random` draws period,
v_m, the lift scales[1], the spacing, sigma, the stress and the bend scales scales[0],
scales[2] uniformly in the box below; `local` keeps scales[0] = 0.53 and scales[2] = 1.0 (the
values the optimizer cannot vary) and perturbs the six others of the best point so far by a few
per cent (the margin: the smallest relative excess over the four thresholds). Rows go to CSV
(appended); a summary goes to stdout. The numbers are deterministic (the simulator is).
"""
import json
import os
import random
import subprocess
import sys
import tempfile
import time

BASE = dict(elements=100, stress=23500.0, sigma=0.044, speed=0.25, spacing=0.1, ka=0.53,
            kb=1.2, kc=1.0, period=1.8)
TOML = """[rod]
length = 1.0
diameter = 0.02
elements = {elements}
density = 1000.0
bending_stiffness = 0.01308
twist_stiffness = 0.00872
stretch_stiffness = 5232.0

[ground]
mu_forward = 0.44
mu_backward = 0.56
mu_sideways = 0.80

[gait]
kind = "sidewinding"
stress = {stress}
sigma = {sigma}
speed = {speed}
centers = [0.0, {c1}, {c2}]
scales = [{ka}, {kb}, {kc}]
period = {period}
ramp = 0.05

[time]
dt = 2e-3
duration = {duration}

[output]
interval = 0.06
"""
OUT = ["share_min", "share_mean", "turn_max", "broad_min", "disp_min", "patches", "lat",
       "sidewinding", "wall_s"]


def margin(r):
    """Smallest relative excess over the four sidewinding thresholds (negative: one fails)."""
    if r.get("cycles", 0) < 5:
        return -9.0
    return min((r["share_min"] - 0.8) / 0.8, (r["disp_min"] - 0.1) / 0.1,
               (5.0 - r["turn_max"]) / 5.0, (r["broad_min"] - 60.0) / 60.0)


def run(slither, point, csv):
    p = dict(BASE)
    p.update(point)
    p["c1"] = round(p["spacing"], 6)
    p["c2"] = round(2 * p["spacing"], 6)
    p["duration"] = round(6 * p["period"], 6)
    with tempfile.TemporaryDirectory() as d:
        f = os.path.join(d, "p.toml")
        with open(f, "w") as fh:
            fh.write(TOML.format(**p))
        t0 = time.time()
        subprocess.run([slither, "run", f, "--out", d + "/o", "--quiet", "--no-plots"],
                       capture_output=True, env=dict(os.environ, RAYON_NUM_THREADS="1"))
        r = {k: p[k] for k in BASE}
        try:
            with open(d + "/o/summary.json") as fh:
                q = json.load(fh)["periodic"]
        except (OSError, KeyError, ValueError):
            q = None
    r["wall_s"] = round(time.time() - t0, 1)
    if q and q["cycles"]:
        cyc = q["cycles"]
        r.update(cycles=len(cyc), share_min=q["stationary_contact_share_min"],
                 share_mean=sum(c["stationary_contact_share"] for c in cyc) / len(cyc),
                 turn_max=q["turn_deg_max_abs"], broad_min=q["broadside_deg_min"],
                 disp_min=q["displacement_over_length_min"],
                 patches=sum(c["contact_patches_mean"] for c in cyc) / len(cyc),
                 lat=q["lateral_speed_over_v_m"], sidewinding=int(bool(q["sidewinding"])))
    cols = list(BASE) + ["cycles"] + OUT + ["margin"]
    r["margin"] = margin(r)
    new = not os.path.exists(csv)
    with open(csv, "a") as fh:
        if new:
            fh.write(",".join(cols) + "\n")
        fh.write(",".join(f"{r[k]:.4g}" if isinstance(r.get(k), float) else str(r.get(k, ""))
                          for k in cols) + "\n")
    return r


def main():
    slither, mode, n, seed, csv = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
    rng = random.Random(seed)
    rows = []
    t0 = time.time()
    if mode == "random":
        for _ in range(n):
            v = dict(period=round(rng.uniform(1.5, 2.4), 3), speed=round(rng.uniform(0.2, 0.32), 3),
                     kb=round(rng.uniform(0.9, 1.5), 3), spacing=round(rng.uniform(0.06, 0.12), 3),
                     sigma=round(rng.uniform(0.035, 0.055), 4), stress=round(rng.uniform(19000, 28000)),
                     ka=round(rng.uniform(0.4, 0.7), 3), kc=round(rng.uniform(0.85, 1.15), 3))
            rows.append((v, run(slither, v, csv)))
    elif mode == "local":
        keys = ["stress", "sigma", "speed", "spacing", "kb", "period"]
        rel = dict(stress=0.05, sigma=0.07, speed=0.05, spacing=0.07, kb=0.05, period=0.05)
        seeds = [dict(period=2.05, speed=0.265, kb=1.151, spacing=0.059, sigma=0.0395, stress=24707),
                 dict(period=1.95, speed=0.273, kb=1.04, spacing=0.06, sigma=0.0456, stress=23508),
                 dict(period=1.95, speed=0.276, kb=1.152, spacing=0.0558, sigma=0.0411, stress=23747)]
        for s in seeds:
            rows.append((s, run(slither, s, csv)))
        for _ in range(n):
            ranked = sorted(rows, key=lambda x: -x[1]["margin"])
            pick = min(int(rng.expovariate(1.0)), len(ranked) - 1) if rng.random() < 0.5 else 0
            parent = ranked[pick][0]
            child = {k: parent[k] * (1 + rng.gauss(0, rel[k])) for k in keys}
            child = {k: round(v, 4 if k in ("sigma", "spacing") else 3) for k, v in child.items()}
            child["stress"] = round(child["stress"])
            rows.append((child, run(slither, child, csv)))
    else:
        sys.exit(f"unknown mode {mode!r}: random or local")
    done = [r for _, r in rows if r.get("cycles", 0) >= 5]
    passing = [r for r in done if r["sidewinding"]]
    print(f"{mode} search, seed {seed}: {len(rows)} runs ({len(done)} with 5 measured cycles), "
          f"{len(passing)} pass every sidewinding criterion; {time.time() - t0:.0f} s")
    print(f"stationary share >= 0.8 in every cycle: {sum(r['share_min'] >= 0.8 for r in done)}; "
          f"|turn| <= 5 deg: {sum(r['turn_max'] <= 5 for r in done)}; "
          f">= 0.1 L: {sum(r['disp_min'] >= 0.1 for r in done)}; "
          f"broadside >= 60 deg: {sum(r['broad_min'] >= 60 for r in done)}")
    keys = ["period", "speed", "kb", "spacing", "sigma", "stress", "ka", "kc"]
    print("\nBest ten by margin (smallest relative excess over the four thresholds):")
    print("| " + " | ".join(keys + OUT[:-2] + ["margin"]) + " |")
    print("|---" * (len(keys) + len(OUT) - 1) + "|")
    for r in sorted(done, key=lambda r: -r["margin"])[:10]:
        print("| " + " | ".join(f"{r[k]:.4g}" for k in keys + OUT[:-2] + ["margin"]) + " |")


if __name__ == "__main__":
    main()
