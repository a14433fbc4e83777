#!/usr/bin/env python3
"""Ground contact at the nodes against between the nodes (`[solver] ground_points`), on the
bundled S-start (implicit Euler): the mesh scan (30 to 200 elements), the scatter about a
fitted trend a + b n^-p over the 10 meshes of 30 to 75 elements (p within [0.25, 4], and the
least-squares p within [0.05, 20]), the couple-shift ensembles
(8 shifts of the three couples by k/8 of an element, k = 0..7, at 50, 100 and 200 elements,
at 5e-4 and 2.5e-4 s), and the converged value of each model (400 elements at two steps;
800 elements with --fine). A shift of the couples changes the scene itself (by per cents at
0.01 L), so each ensemble member's error is taken against the 400-element run at its own
shift (implicit Euler at 2.5e-4 s); the error against the unshifted run is printed beside it. Prints tables; writes out/ground_points/*.csv and the chart
docs/images/ground_points_scatter.png.

    lab/ground_points/ground_points.sh [--fine] [--jobs N] [--points nodes,curve]

--points chooses the contact models (default both). A run that fails is a row marked failed
(listed with its error; its tables say so), not the end of the script. Every finished run is
appended to out/ground_points/journal.jsonl under its command and the binary's hash, and a
later call with the same binary reads it back instead of running it again: an interrupted
measurement resumes, and the record says how many runs were read back. A run that left no
summary (killed, or its folder locked by another run) or was interrupted is not journaled: it
runs again.

--read-back MODEL=BUILD reads that model's runs from the journal rows of an earlier binary
(BUILD: the first 16 hex digits of its sha256, as the journal keys them), for a model whose
code did not change since: the cheapest of its runs is made again with this binary first, and
the script stops unless it gives the same `v_s/v_m` to 1e-12. Only completed runs are read
back; a run that failed then is made again.
"""
import argparse
import concurrent.futures as cf
import csv
import json
import math
import os
import subprocess
import sys
import hashlib
import threading
import time

JOURNAL_PATH = "out/ground_points/journal.jsonl"
JOURNAL = {}  # key (build and command) -> row, read from JOURNAL_PATH
BUILD = ""  # sha256 of the binary, first 16 hex digits
LOCK = threading.Lock()

MESHES = [30, 35, 40, 45, 50, 55, 60, 64, 70, 75, 80, 90, 100, 110, 120, 128, 140, 150, 175, 200]
COARSE = MESHES[:10]
CENTERS = [0.20, 0.35, 0.50]
ENSEMBLE = [50, 100, 200]
# Every shift of the ensembles (k/8 of an element at each ensemble mesh), once.
SHIFTS = sorted({round(k / (8 * n), 9) for n in ENSEMBLE for k in range(8)})


READ_BACK = {}  # model -> the build whose journal rows stand for it (--read-back)


def run(binary, out, n, dt, points, shift=0.0, fresh=False):
    """One run, or its row from the journal when this binary ran the same command before (or
    the build `--read-back` names for this model; `fresh`: always run)."""
    sets = [f"rod.elements={n}", 'solver.integrator="implicit"', f"time.dt={dt}",
            f'solver.ground_points="{points}"']
    if shift:
        c = ", ".join(f"{x + shift:.6f}" for x in CENTERS)
        sets.append(f"gait.centers=[{c}]")
    cmd = [binary, "run", "problems/s_start.toml", "--out", out, "--no-plots", "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    key = BUILD + " " + " ".join(cmd[1:])
    if points in READ_BACK and not fresh:
        old = READ_BACK[points] + " " + " ".join(cmd[1:])
        if old in JOURNAL and JOURNAL[old]["status"] == "ok":
            return dict(JOURNAL[old], reused=True)
    if key in JOURNAL and not fresh:
        return dict(JOURNAL[key], reused=True)
    try:  # never read an earlier run's summary
        os.remove(os.path.join(out, "summary.json"))
    except FileNotFoundError:
        pass
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - t0
    row = dict(points=points, n=n, dt=dt, shift=shift, v=float("nan"), iters=float("nan"), wall=wall,
               fallbacks=0, halvings=0, penetration=0.0, status="failed", error="")
    try:
        d = json.load(open(os.path.join(out, "summary.json")))
    except OSError:
        row["error"] = f"no summary (exit {p.returncode}): {p.stderr.strip()[-300:]}"
        d = None
    if d is not None and d.get("status") == "interrupted":
        row["error"] = "interrupted"
        d = None  # a partial run's answer is no answer, and it is not journaled
    elif d is not None and d.get("status") != "completed":
        row["error"] = d.get("error", "") or f"status {d.get('status')}"
    elif d is not None:
        st = d["stats"]
        row.update(v=d["v_s_over_v_m"], iters=d["newton_iterations_mean"],
                   fallbacks=st["semismooth_fallbacks"], halvings=d["step_halvings"],
                   node_steps=st.get("ground_point_fallbacks", 0),
                   penetration=d["max_penetration"], status="ok")
    if d is not None:  # a run without a summary (killed, or its folder locked) is not kept
        with LOCK:
            with open(JOURNAL_PATH, "a") as fh:
                fh.write(json.dumps(dict(key=key, row=row)) + "\n")
    return row


# The ranges of p the trend is fitted over: the range this script used until 2026-12-06, and a
# wide one (the least-squares p), so that a fit held at an edge of the first shows as such.
P_RANGES = [(0.25, 4.0), (0.05, 20.0)]


def fit_trend(ns, vs, lo, hi):
    """Least squares v = a + b n^-p over p on a grid of 0.01 in [lo, hi]: residuals' std."""
    best = None
    for k in range(0, round((hi - lo) / 0.01) + 1):
        p = lo + 0.01 * k
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
    ap.add_argument("--points", default="nodes,curve",
                    help="contact models, comma-separated (nodes, curve)")
    ap.add_argument("--read-back", action="append", default=[], metavar="MODEL=BUILD",
                    help="read MODEL's runs from the journal rows of build BUILD (checked)")
    args = ap.parse_args()
    models = args.points.split(",")
    for item in args.read_back:
        model, _, build = item.partition("=")
        if model not in ("nodes", "curve") or len(build) != 16:
            sys.exit(f"--read-back {item}: expected nodes=BUILD or curve=BUILD (16 hex digits)")
        READ_BACK[model] = build
    binary = os.environ.get("SLITHER")
    if not binary:
        subprocess.run(["cargo", "build", "--release", "--quiet"], check=True)
        binary = os.path.join(os.environ.get("CARGO_TARGET_DIR", "target"), "release", "slither")
    root = "out/ground_points"
    os.makedirs(root, exist_ok=True)
    global BUILD
    BUILD = hashlib.sha256(open(binary, "rb").read()).hexdigest()[:16]
    if os.path.exists(JOURNAL_PATH):
        for line in open(JOURNAL_PATH):
            e = json.loads(line)
            JOURNAL[e["key"]] = e["row"]
    jobs = []
    for points in models:
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
    for points, build in READ_BACK.items():
        # The model's cheapest run, made again: its code must not have changed since BUILD.
        n, dt, _, sh = min((j for j in jobs if j[2] == points), key=lambda j: j[0] / j[1])
        c = [r for k, r in JOURNAL.items() if k.startswith(build + " ") and r["points"] == points
             and r["n"] == n and r["dt"] == dt and abs(r["shift"] - sh) < 1e-9]
        now = run(binary, f"{root}/{points}-{n}-{dt:g}-{sh:.6f}", n, dt, points, sh, fresh=True)
        if not c or not abs(c[0]["v"] - now["v"]) <= 1e-12:
            sys.exit(f"--read-back {points}={build}: {n} el at {dt:g} s gives {now['v']!r} with this "
                     f"binary against {c[0]['v'] if c else 'no row'} then; run the model afresh")
        print(f"{points}: runs read back from build {build} ({n} el at {dt:g} s made again: "
              f"v_s/v_m {now['v']:.12f} both times)")
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
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()), extrasaction="ignore")
        w.writeheader()
        for r in sorted(rows, key=lambda r: (r["points"], r["n"], r["dt"], r["shift"])):
            w.writerow(r)

    def get(points, n, dt, shift=0.0):
        for r in rows:
            if r["points"] == points and r["n"] == n and r["dt"] == dt and abs(r["shift"] - shift) < 1e-9:
                return r
        raise KeyError((points, n, dt, shift))

    reused = sum(1 for r in rows if r.get("reused"))
    print(f"{len(rows)} runs, {reused} of them read back from {JOURNAL_PATH} (the same command, by this build or the one --read-back names).\n")
    failed = [r for r in rows if r["status"] != "ok"]
    if failed:
        print("## Failed runs\n")
        for r in failed:
            print(f"- {r['points']}, {r['n']} elements, {r['dt']:g} s, shift {r['shift']:.6f}: {r['error']}")
        print()
    fell = [r for r in rows if r["status"] == "ok" and r.get("node_steps", 0)]
    if fell:
        print("## Runs with steps taken again with contact at the nodes (stats.ground_point_fallbacks)\n")
        for r in fell:
            print(f"- {r['points']}, {r['n']} elements, {r['dt']:g} s, shift {r['shift']:.6f}: {r['node_steps']} steps")
        print()

    def pct(v, ref):
        return f"{100 * (v / ref - 1):+.2f} %" if math.isfinite(v) and math.isfinite(ref) else "failed"

    print("## Converged values (implicit Euler, unshifted couples)\n")
    print("| model | 400 el, 5e-4 s | 400 el, 2.5e-4 s |" + (" 800 el, 5e-4 s |" if args.fine else ""))
    print("|---|---|---|" + ("---|" if args.fine else ""))
    ref = {}
    for points in models:
        a, b = get(points, 400, 5e-4)["v"], get(points, 400, 2.5e-4)["v"]
        line = f"| {points} | {a:.5f} | {b:.5f} |"
        ref[points] = b
        if args.fine:
            c = get(points, 800, 5e-4)["v"]
            line += f" {c:.5f} |"
            ref[points] = c
        print(line)
    print("\nErrors below are against each model's finest value: "
          + ", ".join(f"{p} {ref[p]:.5f}" for p in models) + ".\n")

    print("## Mesh scan (implicit Euler at 5e-4 s, unshifted couples)\n")
    print("| model | elements | v_s/v_m | error | iterations/step | conic fallbacks | wall s |")
    print("|---|---|---|---|---|---|---|")
    for points in models:
        for n in MESHES:
            a = get(points, n, 5e-4)
            print(f"| {points} | {n} | {a['v']:.5f} | {pct(a['v'], ref[points])} | {a['iters']:.2f} | "
                  f"{a['fallbacks']} | {a['wall']:.1f} |")
    print("\n## Scatter about a fitted trend a + b n^-p, 30 to 75 elements (10 meshes)\n")
    print("| model | range of p | a | b | p | standard deviation of the residuals | plain standard deviation |")
    print("|---|---|---|---|---|---|---|")
    for points in models:
        vs = [get(points, n, 5e-4)["v"] for n in COARSE]
        if not all(math.isfinite(v) for v in vs):
            print(f"| {points} | | failed runs | | | | |")
            continue
        mv = sum(vs) / len(vs)
        plain = math.sqrt(sum((v - mv) ** 2 for v in vs) / (len(vs) - 1))
        for lo, hi in P_RANGES:
            a, b, p, sd = fit_trend(COARSE, vs, lo, hi)
            edge = " (edge)" if min(abs(p - lo), abs(p - hi)) < 0.005 else ""
            print(f"| {points} | {lo:g} to {hi:g} | {a:.5f} | {b:.4g} | {p:.2f}{edge} | "
                  f"{100 * sd / ref[points]:.2f} % | {100 * plain / ref[points]:.2f} % |")

    print("\n## The scene at each shift (400 elements, implicit Euler at 2.5e-4 s)\n")
    print("| model | shift (fraction of L) | v_s/v_m | change from unshifted |")
    print("|---|---|---|---|")
    for points in models:
        for sh in SHIFTS:
            a = get(points, 400, 2.5e-4, sh)["v"]
            print(f"| {points} | {sh:.6f} | {a:.5f} | {pct(a, get(points, 400, 2.5e-4)['v'])} |")

    print("\n## Couple-shift ensembles (8 shifts of k/8 element)\n")
    print("Error of each member against the 400-element run at its own shift; the mean error "
          "against the unshifted 400-element run (the earlier record's measure) beside it.\n")
    print("| model | elements | step | mean error | standard deviation | range of errors | mean error against unshifted |")
    print("|---|---|---|---|---|---|---|")
    for points in models:
        for n in ENSEMBLE:
            for dt in [5e-4, 2.5e-4]:
                errs, plain = [], []
                for k in range(8):
                    sh = round(k / (8 * n), 9)
                    v = get(points, n, dt, sh)["v"]
                    errs.append(100 * (v / get(points, 400, 2.5e-4, sh)["v"] - 1))
                    plain.append(100 * (v / get(points, 400, 2.5e-4)["v"] - 1))
                if not all(math.isfinite(e) for e in errs + plain):
                    print(f"| {points} | {n} | {dt:g} s | failed runs | | | |")
                    continue
                m = sum(errs) / 8
                sd = math.sqrt(sum((e - m) ** 2 for e in errs) / 7)
                print(f"| {points} | {n} | {dt:g} s | {m:+.2f} % | {sd:.2f} % | "
                      f"{min(errs):+.2f} to {max(errs):+.2f} % | {sum(plain) / 8:+.2f} % |")

    ok = [r for r in rows if r["status"] == "ok"]
    for points in models:
        pen = max((r["penetration"] for r in ok if r["points"] == points), default=float("nan"))
        print(f"\nLargest node below a/2 over all runs, {points}: {pen:.3g} m")

    chart_csv = f"{root}/chart.csv"
    labels = {"nodes": "contact at the nodes", "curve": "contact on the curve"}
    with open(chart_csv, "w") as fh:
        fh.write("label,x,y\n")
        for points in models:
            for n in MESHES:
                v = get(points, n, 5e-4)["v"]
                if math.isfinite(v) and math.isfinite(ref[points]):
                    fh.write(f"{labels[points]},{n},{100 * (v / ref[points] - 1):.4f}\n")
        fh.write(f"zero,{MESHES[0]},0\nzero,{MESHES[-1]},0\n")
    subprocess.run(["cargo", "run", "--release", "--quiet", "--example", "series_chart", "--", chart_csv,
                    "docs/images/ground_points_scatter.png",
                    "S-start, implicit Euler at 5e-4 s: error against the finest mesh", "elements",
                    "error of v_s/v_m (%)", "--log-x"], check=True)


if __name__ == "__main__":
    main()
