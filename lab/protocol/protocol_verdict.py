#!/usr/bin/env python3
"""Is W/G alone the control parameter? Compare verified `slither phase` studies run on the same
grid under different protocols (`[phase] weight_via`, `similar`).

For each study directory: the regime counts, the cells whose runs disagree (uncertain), and two
slope estimates of the boundaries in the log-log (W, G) plane, from unanimous cells only (the
paper's claim is slope 1: lines of constant W/G):

- the interval of slopes s of every line log10 G = s log10 W + c that separates the unanimous
  N cells (no net motion, below) from the unanimous moving cells (any other label, above),
  found by scanning s; empty when no line separates them. This is the motion-onset boundary;
  its interval is its uncertainty (any slope inside it fits the labels equally well);
- every boundary line of `boundaries.json` fitted through at least two unanimous pairs, with
  a 5-95 % range from refitting 2000 times with each point moved uniformly within its
  half-width (its cells' spacing).

Usage: lab/protocol/protocol_verdict.py NAME=DIR [NAME=DIR ...]
"""
import csv
import json
import math
import random
import sys
from collections import Counter


def load(d):
    rows = list(csv.DictReader(open(f"{d}/phase.csv")))
    b = json.load(open(f"{d}/boundaries.json"))
    return rows, (b["boundaries"] if isinstance(b, dict) else b)


def separating_slopes(rows):
    """Interval of slopes s for which a line separates unanimous N (below) from unanimous
    moving cells (above) in (log W, log G)."""
    sure = [r for r in rows if r["status"] == "ok" and float(r.get("label_agreement") or 1) == 1.0]
    n = [(math.log10(float(r["weight"])), math.log10(float(r["torque"]))) for r in sure
         if r["regime"] == "N" and float(r["torque"]) > 0]
    mv = [(math.log10(float(r["weight"])), math.log10(float(r["torque"]))) for r in sure
          if r["regime"] != "N" and float(r["torque"]) > 0]
    if not n or not mv:
        return None, len(n), len(mv)
    ok = []
    for k in range(-3000, 3001):
        s = k / 1000.0
        hi_n = max(g - s * w for w, g in n)
        lo_m = min(g - s * w for w, g in mv)
        if hi_n < lo_m:
            ok.append(s)
    if not ok:
        return (), len(n), len(mv)
    return (min(ok), max(ok)), len(n), len(mv)


def onsets(rows):
    """Per weight column: the torque interval in which motion starts (the highest unanimous
    N cell below the lowest unanimous moving cell, when they are neighbours in the grid)."""
    torques = sorted({float(r["torque"]) for r in rows})
    out = []
    for w in sorted({float(r["weight"]) for r in rows}):
        col = {float(r["torque"]): r for r in rows if float(r["weight"]) == w}
        lab = []
        for g in torques:
            r = col.get(g)
            sure = r is not None and r["status"] == "ok" and float(r.get("label_agreement") or 1) == 1.0
            lab.append(None if not sure else ("N" if r["regime"] == "N" else "moving"))
        first = next((i for i, l in enumerate(lab) if l == "moving"), None)
        if first is None or first == 0 or lab[first - 1] != "N":
            out.append((w, None))
            continue
        out.append((w, (torques[first - 1], torques[first])))
    return out


def fit(points):
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx == 0:
        return None
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def slope_range(b, rng):
    pts = b.get("points") or []
    if len(pts) < 2:
        return None
    base = [(math.log10(p["w"]), math.log10(p["g"]), p["along"], p["half_width"]) for p in pts]
    s0 = fit([(x, y) for x, y, _, _ in base])
    if s0 is None:
        return None
    draws = []
    for _ in range(2000):
        moved = []
        for x, y, along, hw in base:
            d = rng.uniform(-hw, hw)
            moved.append((x + d, y) if along == "W" else (x, y + d))
        s = fit(moved)
        if s is not None:
            draws.append(s)
    draws.sort()
    return s0, draws[int(0.05 * len(draws))], draws[int(0.95 * len(draws)) - 1], len(pts)


def main():
    rng = random.Random(1)
    for arg in sys.argv[1:]:
        name, d = arg.split("=", 1)
        rows, bounds = load(d)
        ok = [r for r in rows if r["status"] == "ok"]
        unsure = [r for r in ok if float(r.get("label_agreement") or 1) < 1.0]
        print(f"## {name} ({d})")
        print(f"cells {len(rows)}, finished {len(ok)}, uncertain {len(unsure)}; "
              f"labels {dict(sorted(Counter(r['regime'] for r in ok).items()))}")
        sep, nn, nm = separating_slopes(rows)
        if sep is None:
            print(f"motion onset (N below, moving above; {nn} N and {nm} moving unanimous cells): "
                  f"not enough cells")
        elif sep == ():
            print(f"motion onset (N below, moving above; {nn} N and {nm} moving unanimous cells): "
                  f"no straight line separates them")
        else:
            inside = "includes" if sep[0] <= 1.0 <= sep[1] else "excludes"
            print(f"motion onset (N below, moving above; {nn} N and {nm} moving unanimous cells): "
                  f"separating slopes {sep[0]:.2f} to {sep[1]:.2f} ({inside} 1)")
        cols = onsets(rows)
        print("motion onset per W (G of the last N and the first moving cell): " + ", ".join(
            f"W {w:.3g}: " + ("-" if iv is None else f"{iv[0]:.3g}-{iv[1]:.3g}") for w, iv in cols))
        known = [(w, math.sqrt(iv[0] * iv[1])) for w, iv in cols if iv is not None]
        for (w0, g0), (w1, g1) in zip(known, known[1:]):
            print(f"  local slope W {w0:.3g} -> {w1:.3g}: "
                  f"{math.log10(g1 / g0) / math.log10(w1 / w0):.2f}")
        for b in bounds:
            r = slope_range(b, rng)
            if r is None:
                continue
            s0, lo, hi, n = r
            print(f"  {b['pair']}: slope {s0:.2f} (5-95 % {lo:.2f} to {hi:.2f}) through {n} points")
        print()


if __name__ == "__main__":
    main()
