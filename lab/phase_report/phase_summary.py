#!/usr/bin/env python3
"""Summarise a `slither phase` output directory for the README: regime counts, the fitted
boundaries (slope against the paper's 1), Fig. 3a (Wr_max against W/G at fixed G) and
Fig. 3b (v_s/v_m against Wr_max). Usage: lab/phase_report/phase_summary.py OUT_DIR"""
import csv, json, math, sys
from collections import Counter, defaultdict

out = sys.argv[1]
rows = [r for r in csv.DictReader(open(f"{out}/phase.csv"))]
ok = [r for r in rows if r["status"] == "ok"]
print(f"cells {len(rows)}, finished {len(ok)}, failed {len(rows) - len(ok)}")
print("regimes", dict(Counter(r["regime"] for r in rows)))
print("sum of cell wall times (s)", round(sum(float(r["wall_time_s"]) for r in rows), 1))
# Each boundary: how its points were placed (`method`: "bisection" when at least one point
# was bisected with `[phase] refine = true`, else "midpoints"; a boundaries.json from before
# the field existed prints "-") and its points (bisected ones, failed bisections, the largest
# half-width in decades along the axis each was located on).
def placement(b):
    pts = b.get("points")
    if pts is None:
        return f"method {b.get('method', '-')}, {len(b['cells'])} pairs"
    bis = sum(p["method"] == "bisection" for p in pts)
    bad = sum(p.get("failed") is not None for p in pts)
    hw = max((p["half_width"] for p in pts), default=float("nan"))
    return (f"method {b.get('method', '-')}, {len(pts)} points ({bis} bisected, {bad} failed, "
            f"half-width up to {hw:.3f} decades)")
bj = json.load(open(f"{out}/boundaries.json"))
if isinstance(bj, dict):
    # A verified study: the lines (fitted through unanimous cells only) and what was left out.
    print(f"verified: {len(bj['uncertain'])} uncertain cells; excluded from the fits: "
          f"{bj['excluded_cells']} cells, {bj['excluded_pairs']} neighbour pairs")
    bj = bj["boundaries"]
for b in bj:
    if b["slope"] is None:
        print(f"  {b['pair']}: no fit; {placement(b)}")
        continue
    r10 = "-" if b["ratio_at_g10"] is None else f"{b['ratio_at_g10']:.3g}"
    print(f"  {b['pair']}: slope {b['slope']:.3f} (off 1 by {b['slope'] - 1:+.3f}), W/G at G=10 "
          f"{r10}, residual {b['residual']:.3f} decades; {placement(b)}")
# Fig. 3a: at each G, Wr_max against W/G (Spearman rank correlation, and values).
def spearman(x, y):
    def rank(v):
        o = sorted(range(len(v)), key=lambda i: v[i]); r = [0] * len(v)
        for k, i in enumerate(o): r[i] = k
        return r
    rx, ry = rank(x), rank(y); n = len(x)
    if n < 3: return float("nan")
    mx, my = sum(rx) / n, sum(ry) / n
    sxy = sum((a - mx) * (b - my) for a, b in zip(rx, ry))
    sxx = sum((a - mx) ** 2 for a in rx); syy = sum((b - my) ** 2 for b in ry)
    return sxy / math.sqrt(sxx * syy) if sxx > 0 and syy > 0 else float("nan")
byg = defaultdict(list)
for r in ok:
    byg[float(r["torque"])].append((float(r["W_over_G"]), float(r["writhe_max"]), float(r["v_s_over_v_m"]), r["regime"]))
print("Fig 3a: G, Spearman(W/G, Wr_max), Wr_max at smallest/median/largest W/G")
neg = 0
for g in sorted(byg):
    v = sorted(byg[g])
    rho = spearman([a for a, *_ in v], [b for _, b, *_ in v])
    neg += rho < 0
    m = v[len(v) // 2]
    print(f"  G {g:.3g}: rho {rho:+.2f}; W/G {v[0][0]:.3g}: {v[0][1]:.3f}, {m[0]:.3g}: {m[1]:.3f}, {v[-1][0]:.3g}: {v[-1][1]:.3f}")
print(f"  rows with falling writhe (rho < 0): {neg} of {len(byg)}")
# Fig. 3b: v_s/v_m against Wr_max, binned.
pts = sorted((float(r["writhe_max"]), float(r["v_s_over_v_m"]), r["regime"]) for r in ok)
edges = [0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.5, 100]
print("Fig 3b: Wr_max bin: cells, max v_s/v_m (regime), median v_s/v_m")
for a, b in zip(edges, edges[1:]):
    sel = [p for p in pts if a <= p[0] < b]
    if not sel: continue
    best = max(sel, key=lambda p: p[1]); med = sorted(p[1] for p in sel)[len(sel) // 2]
    print(f"  [{a}, {b}): {len(sel)}, max {best[1]:.3f} ({best[2]}, Wr {best[0]:.2f}), median {med:.3f}")
best = max(pts, key=lambda p: p[1])
print(f"fastest: v_s/v_m {best[1]:.3f} at Wr_max {best[0]:.3f} ({best[2]})")
