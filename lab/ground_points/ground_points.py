#!/usr/bin/env python3
"""Ground contact at the nodes against between the nodes (`[solver] ground_points`), on the
bundled S-start (implicit Euler): the mesh scan (30 to 200 elements), the scatter about a
fitted trend a + b n^-p over the 10 meshes of 30 to 75 elements, the couple-shift ensembles
(8 shifts of the three couples by k/8 of an element, k = 0..7, at 50, 100 and 200 elements,
at 5e-4 and 2.5e-4 s), and the converged value of each model (400 elements at two steps;
800 elements with --fine). A shift of the couples changes the scene itself (by per cents at
0.01 L), so each ensemble member's error is taken against the 400-element run at its own
shift (implicit Euler at 2.5e-4 s); the error against the unshifted run is printed beside it. Prints tables; writes out/ground_points/*.csv and the chart
docs/images/ground_points_scatter.png.

    lab/ground_points/ground_points.sh [--fine] [--jobs N]
"""
import argparse
import concurrent.futures as cf
import csv
import json
import math
import os
import subprocess
import sys
import time

MESHES = [30, 35, 40, 45, 50, 55, 60, 64, 70, 75, 80, 90, 100, 110, 120, 128, 140, 150, 175, 200]
COARSE = MESHES[:10]
CENTERS = [0.20, 0.35, 0.50]
ENSEMBLE = [50, 100, 200]
# Every shift of the ensembles (k/8 of an element at each ensemble mesh), once.
SHIFTS = sorted({round(k / (8 * n), 9) for n in ENSEMBLE for k in range(8)})


def run(binary, out, n, dt, points, shift=0.0):
    sets = [f"rod.elements={n}", 'solver.integrator="implicit"', f"time.dt={dt}",
            f'solver.ground_points="{points}"']
    if shift:
        c = ", ".join(f"{x + shift:.6f}" for x in CENTERS)
        sets.append(f"gait.centers=[{c}]")
    cmd = [binary, "run", "problems/s_start.toml", "--out", out, "--no-plots", "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    try:  # never read an earlier run's summary
        os.remove(os.path.join(out, "summary.json"))
    except FileNotFoundError:
        pass
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - t0
    try:
        d = json.load(open(os.path.join(out, "summary.json")))
    except OSError:
        sys.exit(f"ground_points: {' '.join(cmd)} wrote no summary (exit {p.returncode}): {p.stderr}")
    if d.get("status") == "failed":
        sys.exit(f"ground_points: {' '.join(cmd)} failed: {d.get('error')}")
    st = d["stats"]
    return dict(points=points, n=n, dt=dt, shift=shift, v=d["v_s_over_v_m"],
                iters=d["newton_iterations_mean"], wall=wall,
                fallbacks=st["semismooth_fallbacks"], halvings=d["step_halvings"],
                penetration=d["max_penetration"])


def fit_trend(ns, vs):
    """Least squares v = a + b n^-p over p in [0.25, 4] (grid then refine): residuals' std."""
    best = None
    for k in range(0, 376):
        p = 0.25 + 0.01 * k
        x = [n ** -p for n in ns]
        mx, mv = sum(x) / len(x), sum(vs) / len(vs)
        sxx = sum((a - mx) ** 2 for a in x)
        b = sum((a - mx) * (v - mv) for a, v in zip(x, vs)) / sxx
        a = mv - b * mx
        res = [v - (a + b * xi) for v, xi in zip(vs, x)]
        ss = sum(r * r for r in res)
        if best is None or ss < best[0]:
            best = (ss, a, b, p, res)
    ss, a, b, p, res = best
    sd = math.sqrt(ss / (len(ns) - 3))
    return a, b, p, sd


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--fine", action="store_true", help="also 800 elements (about 10 min each)")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    binary = os.environ.get("SLITHER")
    if not binary:
        subprocess.run(["cargo", "build", "--release", "--quiet"], check=True)
        binary = os.path.join(os.environ.get("CARGO_TARGET_DIR", "target"), "release", "slither")
    root = "out/ground_points"
    os.makedirs(root, exist_ok=True)
    jobs = []
    for points in ["nodes", "curve"]:
        for n in MESHES:
            jobs.append((n, 5e-4, points, 0.0))
        for n in ENSEMBLE:
            for dt in [5e-4, 2.5e-4]:
                for k in range(8):
                    if k == 0 and dt == 5e-4:
                        continue  # the mesh scan has it
                    jobs.append((n, dt, points, round(k / (8 * n), 9)))
        for dt in [5e-4, 2.5e-4]:
            jobs.append((400, dt, points, 0.0))
        for shift in SHIFTS:
            if shift:
                jobs.append((400, 2.5e-4, points, shift))
        if args.fine:
            jobs.append((800, 5e-4, points, 0.0))
    # Longest first, so the two workers end together.
    jobs.sort(key=lambda j: -j[0] / j[1])
    rows = []
    with cf.ThreadPoolExecutor(args.jobs) as ex:
        futs = {ex.submit(run, binary, f"{root}/{p}-{n}-{dt:g}-{s:.6f}", n, dt, p, s): (n, dt, p, s)
                for (n, dt, p, s) in jobs}
        for i, f in enumerate(cf.as_completed(futs)):
            rows.append(f.result())
            print(f"  [{i + 1}/{len(jobs)}] {rows[-1]['points']} {rows[-1]['n']} el dt {rows[-1]['dt']:g} "
                  f"shift {rows[-1]['shift']:.5f}: {rows[-1]['v']:.5f}", file=sys.stderr, flush=True)
    with open(f"{root}/runs.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in sorted(rows, key=lambda r: (r["points"], r["n"], r["dt"], r["shift"])):
            w.writerow(r)

    def get(points, n, dt, shift=0.0):
        for r in rows:
            if r["points"] == points and r["n"] == n and r["dt"] == dt and abs(r["shift"] - shift) < 1e-9:
                return r
        raise KeyError((points, n, dt, shift))

    print("## Converged values (implicit Euler, unshifted couples)\n")
    print("| model | 400 el, 5e-4 s | 400 el, 2.5e-4 s |" + (" 800 el, 5e-4 s |" if args.fine else ""))
    print("|---|---|---|" + ("---|" if args.fine else ""))
    conv = {}
    for points in ["nodes", "curve"]:
        a, b = get(points, 400, 5e-4)["v"], get(points, 400, 2.5e-4)["v"]
        line = f"| {points} | {a:.5f} | {b:.5f} |"
        conv[points] = b
        if args.fine:
            c = get(points, 800, 5e-4)["v"]
            line += f" {c:.5f} |"
            conv[points] = c
        print(line)
    ref = conv
    print(f"\nErrors below are against each model's finest value: nodes {ref['nodes']:.5f}, "
          f"curve {ref['curve']:.5f}.\n")

    print("## Mesh scan (implicit Euler at 5e-4 s, unshifted couples)\n")
    print("| elements | nodes v_s/v_m | error | iterations/step | curve v_s/v_m | error | iterations/step | fallbacks |")
    print("|---|---|---|---|---|---|---|---|")
    for n in MESHES:
        a, b = get("nodes", n, 5e-4), get("curve", n, 5e-4)
        print(f"| {n} | {a['v']:.5f} | {100 * (a['v'] / ref['nodes'] - 1):+.2f} % | {a['iters']:.2f} | "
              f"{b['v']:.5f} | {100 * (b['v'] / ref['curve'] - 1):+.2f} % | {b['iters']:.2f} | {b['fallbacks']} |")
    print("\n## Scatter about a fitted trend a + b n^-p, 30 to 75 elements (10 meshes)\n")
    print("| model | a | b | p | standard deviation of the residuals | plain standard deviation |")
    print("|---|---|---|---|---|---|")
    for points in ["nodes", "curve"]:
        vs = [get(points, n, 5e-4)["v"] for n in COARSE]
        a, b, p, sd = fit_trend(COARSE, vs)
        mv = sum(vs) / len(vs)
        plain = math.sqrt(sum((v - mv) ** 2 for v in vs) / (len(vs) - 1))
        print(f"| {points} | {a:.5f} | {b:.4g} | {p:.2f} | {100 * sd / ref[points]:.2f} % | {100 * plain / ref[points]:.2f} % |")

    print("\n## The scene at each shift (400 elements, implicit Euler at 2.5e-4 s)\n")
    print("| shift (fraction of L) | nodes v_s/v_m | change from unshifted | curve v_s/v_m | change from unshifted |")
    print("|---|---|---|---|---|")
    for sh in SHIFTS:
        a, b = get("nodes", 400, 2.5e-4, sh)["v"], get("curve", 400, 2.5e-4, sh)["v"]
        print(f"| {sh:.6f} | {a:.5f} | {100 * (a / get('nodes', 400, 2.5e-4)['v'] - 1):+.2f} % | "
              f"{b:.5f} | {100 * (b / get('curve', 400, 2.5e-4)['v'] - 1):+.2f} % |")

    print("\n## Couple-shift ensembles (8 shifts of k/8 element)\n")
    print("Error of each member against the 400-element run at its own shift; the mean error "
          "against the unshifted 400-element run (the earlier record's measure) beside it.\n")
    print("| model | elements | step | mean error | standard deviation | range of errors | mean error against unshifted |")
    print("|---|---|---|---|---|---|---|")
    for points in ["nodes", "curve"]:
        for n in ENSEMBLE:
            for dt in [5e-4, 2.5e-4]:
                errs, plain = [], []
                for k in range(8):
                    sh = round(k / (8 * n), 9)
                    v = get(points, n, dt, sh)["v"]
                    errs.append(100 * (v / get(points, 400, 2.5e-4, sh)["v"] - 1))
                    plain.append(100 * (v / get(points, 400, 2.5e-4)["v"] - 1))
                m = sum(errs) / 8
                sd = math.sqrt(sum((e - m) ** 2 for e in errs) / 7)
                print(f"| {points} | {n} | {dt:g} s | {m:+.2f} % | {sd:.2f} % | "
                      f"{min(errs):+.2f} to {max(errs):+.2f} % | {sum(plain) / 8:+.2f} % |")

    print("\n## Cost (mesh scan, one process each, two at a time)\n")
    print("| elements | nodes: iterations/step, wall s | curve: iterations/step, wall s, fallbacks, halvings | iteration ratio |")
    print("|---|---|---|---|")
    for n in [50, 100, 200]:
        a, b = get("nodes", n, 5e-4), get("curve", n, 5e-4)
        print(f"| {n} | {a['iters']:.2f}, {a['wall']:.1f} | {b['iters']:.2f}, {b['wall']:.1f}, {b['fallbacks']}, "
              f"{b['halvings']} | {b['iters'] / a['iters']:.2f} |")
    pen = max(r["penetration"] for r in rows if r["points"] == "curve")
    pen_nodes = max(r["penetration"] for r in rows if r["points"] == "nodes")
    print(f"\nLargest node below a/2 over all runs: nodes {pen_nodes:.3g} m, curve {pen:.3g} m "
          "(curve: a node between the step's frozen contact points).")

    chart_csv = f"{root}/chart.csv"
    with open(chart_csv, "w") as fh:
        fh.write("label,x,y\n")
        for points, label in [("nodes", "contact at the nodes"), ("curve", "contact on the curve")]:
            for n in MESHES:
                fh.write(f"{label},{n},{100 * (get(points, n, 5e-4)['v'] / ref[points] - 1):.4f}\n")
        fh.write(f"zero,{MESHES[0]},0\nzero,{MESHES[-1]},0\n")
    subprocess.run(["cargo", "run", "--release", "--quiet", "--example", "series_chart", "--", chart_csv,
                    "docs/images/ground_points_scatter.png",
                    "S-start, implicit Euler at 5e-4 s: error against the finest mesh", "elements",
                    "error of v_s/v_m (%)", "--log-x"], check=True)

if __name__ == "__main__":
    main()
