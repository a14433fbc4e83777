#!/usr/bin/env python3
"""Where the Newton iterations of the S-start go, contact at the nodes against contact on the
curve: from the debug logs (`SLITHER_DEBUG=1`) and summaries written by iterations.sh, every
run's iterations per step, split into the attempts that converged and the semi-smooth attempts
that failed (and were retried or fell back to the conic program), and the curve's ratios to the
nodes'. Prints Markdown (for tools/record.sh).

    python3 lab/ground_points/iterations.py DIR
"""
import json
import os
import sys


def attempts(log):
    """(iterations in all semi-smooth attempts, in the failed ones, number of failed ones)."""
    total = failed = count = current = 0
    with open(log) as f:
        for line in f:
            if "semi-smooth statuses it " in line:
                if line.split("statuses it ", 1)[1].startswith("1:"):
                    current = 0
                current += 1
                total += 1
            elif "semi-smooth Newton failed" in line:
                failed += current
                count += 1
                current = 0
    return total, failed, count


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    d = sys.argv[1]
    runs = {}
    for name in sorted(os.listdir(d)):
        if not name.endswith(".log"):
            continue
        n, points, dt = name[:-4].split("_")
        s = json.load(open(os.path.join(d, name[:-4], "summary.json")))
        total, failed, count = attempts(os.path.join(d, name))
        st = s["stats"]
        runs.setdefault((int(n), points), []).append(
            dict(dt=dt, steps=s["steps"], it=s["newton_iterations_mean"], total=total,
                 failed=failed, count=count, fallbacks=st["semismooth_fallbacks"],
                 halvings=st["step_halvings"], v=s["v_s_over_v_m"], wall=s["wall_time_s"]))
    print("| elements | contact | step (s) | it/step | it/step in converged attempts | failed attempts (iterations) | conic fallbacks | halvings | v_s/v_m |")
    print("|---|---|---|---|---|---|---|---|---|")
    for (n, points), rs in sorted(runs.items()):
        for r in sorted(rs, key=lambda r: float(r["dt"])):
            clean = (r["total"] - r["failed"]) / r["steps"]
            print(f"| {n} | {points} | {r['dt']} | {r['it']:.2f} | {clean:.2f} | {r['count']} ({r['failed']}) | {r['fallbacks']} | {r['halvings']} | {r['v']:.5f} |")
    print()
    print("Means over the steps, and the curve's ratio to the nodes':")
    print()
    print("| elements | nodes it/step | curve it/step | ratio | nodes, converged attempts | curve, converged attempts | ratio | failed attempts per run, nodes / curve |")
    print("|---|---|---|---|---|---|---|---|")
    for n in sorted({k[0] for k in runs}):
        a, b = runs.get((n, "nodes"), []), runs.get((n, "curve"), [])
        if not a or not b:
            continue
        mean = lambda rs, f: sum(f(r) for r in rs) / len(rs)
        ia, ib = mean(a, lambda r: r["it"]), mean(b, lambda r: r["it"])
        ca = mean(a, lambda r: (r["total"] - r["failed"]) / r["steps"])
        cb = mean(b, lambda r: (r["total"] - r["failed"]) / r["steps"])
        fa, fb = mean(a, lambda r: r["count"]), mean(b, lambda r: r["count"])
        print(f"| {n} | {ia:.2f} | {ib:.2f} | {ib / ia:.3f} | {ca:.2f} | {cb:.2f} | {cb / ca:.3f} | {fa:.1f} / {fb:.1f} |")


if __name__ == "__main__":
    main()
