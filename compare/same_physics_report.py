#!/usr/bin/env python3
"""Report of lab/pyelastica_same_physics/pyelastica_same_physics.sh: the S-start on PyElastica's scene, both codes
on the same muscle physics, over the mesh.

Usage:  same_physics_report.py OUT_DIR FIGURE_STEM

Reads OUT_DIR/pe_<elements>_<dt>.json (compare/pyelastica_s_start.py) and
OUT_DIR/sl_<elements>_<dt>/summary.json (slither run). v_s/v_m is slither's definition on both
sides: the centroid's displacement along the initial tail-to-head direction over T, over v_m.

Each code's limit:
1. per mesh, the value at a vanishing step: PyElastica (Verlet, second order, its steps at
   and below its stability limit) takes its finest step, with the change from the step before
   as that value's time uncertainty (a mesh run at one step only takes the next coarser
   mesh's); slither (implicit Euler, first order) takes the
   Richardson value 2 v(dt/2) - v(dt) of its two finest steps, with |v(dt/2) - v(dt)| as the
   uncertainty;
2. over the mesh, Richardson on the three finest meshes (N/4, N/2, N) with the observed order
   p = log2(d1 / d2) (d1, d2 the successive changes): v_N + d2 / (2^p - 1). Its uncertainty:
   the spread of that value and of the extrapolations with p = 1 and p = 2, plus the finest
   mesh's time uncertainty. When the changes do not shrink (d2 >= d1) no order is observed and
   the limit is not established: the script says so and gives the range from v_N to the p = 1
   extrapolation.
The two limits are called a common value only if they differ by less than the sum of their
uncertainties.

Cost at equal accuracy: each code's cheapest run (wall time of the whole 4 s scene) within 1 %
and within 2 % of its own limit, and of the other code's; the ratio PyElastica / slither.
Writes FIGURE_STEM.png (the work-precision chart: both codes, against their own limit and
against the other's) and FIGURE_STEM.csv (every run).
"""

import glob
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

T = 4.0  # the scene's duration (s)


def load(out):
    pe, sl = {}, {}
    for f in glob.glob(os.path.join(out, "pe_*.json")):
        n, dt = re.match(r"pe_(\d+)_(.+)\.json", os.path.basename(f)).groups()
        j = json.load(open(f))
        pe[(int(n), dt)] = {"v": j["v_s_over_v_m"], "head": j["v_head_instantaneous_over_v_m"],
                            "rate": j["wall_per_sim_second"], "stable": j["stable"],
                            "height": j["max_height_over_a"], "code": j["code"]}
    for f in glob.glob(os.path.join(out, "sl_*", "summary.json")):
        n, dt = re.match(r"sl_(\d+)_(.+)", os.path.basename(os.path.dirname(f))).groups()
        j = json.load(open(f))
        sl[(int(n), dt)] = {"v": j["v_s_over_v_m"], "rate": j["wall_time_s"] / j["t_final"],
                            "stable": j.get("error") is None, "steps": j["steps"]}
    return pe, sl


def per_mesh(runs, order):
    """Per mesh: (value at a vanishing step, its uncertainty, finest step's value)."""
    out = {}
    for n in sorted({k[0] for k in runs}):
        ks = sorted((k for k in runs if k[0] == n and runs[k]["stable"]),
                    key=lambda k: float(k[1]))
        if len(ks) < 2:
            # one step only: its time uncertainty taken as the next coarser mesh's
            if ks:
                prev = [out[m][1] for m in sorted(out) if m < n]
                out[n] = (runs[ks[0]]["v"], prev[-1] if prev else float("nan"),
                          runs[ks[0]]["v"])
            continue
        fine, coarse = runs[ks[0]]["v"], runs[ks[1]]["v"]
        ratio = float(ks[1][1]) / float(ks[0][1])
        if order == 1:
            value = fine + (fine - coarse) / (ratio - 1.0)
        else:
            value = fine
        out[n] = (value, abs(fine - coarse), fine)
    return out


def limit(mesh):
    """Richardson over the three finest meshes: (limit, uncertainty, order, note). The limit is
    the middle of the interval spanned by the extrapolations with the observed order and with
    orders 1 and 2; the uncertainty its half-width plus the finest mesh's time uncertainty."""
    ns = sorted(mesh)[-3:]
    if len(ns) < 3:
        return float("nan"), float("nan"), float("nan"), "fewer than three meshes"
    v = [mesh[n][0] for n in ns]
    d1, d2 = v[1] - v[0], v[2] - v[1]
    ext = {p: v[2] + d2 / (2.0 ** p - 1.0) for p in (1.0, 2.0)}
    if d1 == 0 or d2 / d1 <= 0 or abs(d2) >= abs(d1):
        lo, hi = sorted((v[2], ext[1.0]))
        return 0.5 * (lo + hi), 0.5 * (hi - lo) + mesh[ns[2]][1], float("nan"), (
            f"meshes {ns}: no order observed (changes {d1:+.5f}, {d2:+.5f}): not established; "
            f"the interval from the finest mesh to the order-1 extrapolation, {lo:.5f} to {hi:.5f}")
    p = math.log2(d1 / d2)
    ext[p] = v[2] + d2 / (2.0 ** p - 1.0)
    lo, hi = min(ext.values()), max(ext.values())
    u = 0.5 * (hi - lo) + mesh[ns[2]][1]
    return 0.5 * (lo + hi), u, p, (
        f"meshes {ns}: changes {d1:+.5f}, {d2:+.5f}, observed order {p:.2f} (extrapolation "
        f"{ext[p]:.5f}); order 1 gives {ext[1.0]:.5f}, order 2 {ext[2.0]:.5f}; the limit is the "
        f"middle of {lo:.5f} to {hi:.5f}, +- half that interval plus the finest mesh's step "
        f"uncertainty {mesh[ns[2]][1]:.5f}")


def cheapest(runs, ref, tol, robust=False):
    """The cheapest stable run within `tol` of `ref`: (wall s for the scene, key). `robust`:
    only runs whose every smaller step on the same mesh is within `tol` too (no run that lands
    there by a cancellation of step and mesh errors)."""
    def within(k):
        return runs[k]["stable"] and abs(runs[k]["v"] / ref - 1.0) <= tol

    ok = [(r["rate"] * T, k) for k, r in runs.items() if within(k) and (
        not robust or all(within(j) for j in runs if j[0] == k[0] and float(j[1]) < float(k[1])))]
    return min(ok) if ok else None


def main():
    out, stem = sys.argv[1], sys.argv[2]
    pe, sl = load(out)
    print("## Runs (v_s/v_m: displacement along the initial heading over T v_m)")
    print()
    print("| code | elements | dt (s) | stable | v_s/v_m | instantaneous-head form | "
          "wall s per simulated s | wall s for the scene |")
    print("|---|---|---|---|---|---|---|---|")
    for code, runs in (("PyElastica", pe), ("slither (implicit Euler)", sl)):
        for k in sorted(runs, key=lambda k: (k[0], -float(k[1]))):
            r = runs[k]
            head = f"{r['head']:.5f}" if "head" in r else "-"
            v = f"{r['v']:.5f}" if r["stable"] else f"({r['v']:.3g})"
            print(f"| {code} | {k[0]} | {k[1]} | {r['stable']} | {v} | {head} | "
                  f"{r['rate']:.3f} | {r['rate'] * T:.2f} |")
    print()
    mesh = {"PyElastica": per_mesh(pe, 2), "slither": per_mesh(sl, 1)}
    lim = {}
    print("## Each code's value per mesh at a vanishing step, and its limit")
    print()
    meshes = sorted(set(mesh["slither"]) | set(mesh["PyElastica"]))
    print("| code | " + " | ".join(f"{n} el." for n in meshes) + " | limit |")
    print("|---|" + "---|" * (len(meshes) + 1))
    for code in ("PyElastica", "slither"):
        best, u, p, note = limit(mesh[code])
        lim[code] = (best, u)
        cells = " | ".join(
            f"{mesh[code][n][0]:.5f} (+-{mesh[code][n][1]:.5f})" if n in mesh[code] else "-"
            for n in meshes)
        print(f"| {code} | {cells} | {best:.5f} +- {u:.5f} |")
        print(f"\n{code}: {note}\n")
    (a, ua), (b, ub) = lim["PyElastica"], lim["slither"]
    diff = a - b
    common = abs(diff) <= ua + ub
    print(f"Limits: PyElastica {a:.5f} +- {ua:.5f}, slither {b:.5f} +- {ub:.5f}; difference "
          f"PyElastica - slither {diff:+.5f} ({100 * diff / b:+.2f} % of slither's), "
          f"combined uncertainty {ua + ub:.5f}: "
          + ("within it, a common value" if common else "larger: no common value"))
    print()
    print("## Cheapest run within 1 % and 2 % (wall s for the 4 s scene)")
    print()
    print("Robust: every smaller step on the same mesh is within the band too.")
    print()
    print("| accuracy | against | PyElastica | slither | slither, robust | PyElastica / slither "
          "(robust) |")
    print("|---|---|---|---|---|---|")
    for tol in (0.01, 0.02):
        for against in ("own limit", "PyElastica's limit", "slither's limit"):
            if against == "own limit":
                refp, refs = a, b
            else:
                refp = refs = a if against.startswith("PyElastica") else b
            cp, cs = cheapest(pe, refp, tol, True), cheapest(sl, refs, tol)
            csr = cheapest(sl, refs, tol, True)
            f = (lambda c: f"{c[0]:.2f} s ({c[1][0]} el., dt {c[1][1]})" if c else "none")
            ratio = (f"{cp[0] / cs[0]:.1f} ({cp[0] / csr[0]:.1f})" if cp and cs and csr
                     else "-")
            print(f"| {100 * tol:.0f} % | {against} | {f(cp)} | {f(cs)} | {f(csr)} | {ratio} |")
    print()
    for code, runs, ref, other_runs, oref in (("PyElastica", pe, a, sl, b),
                                               ("slither", sl, b, pe, a)):
        best = min((abs(r["v"] / ref - 1.0), r["rate"] * T, k)
                   for k, r in runs.items() if r["stable"])
        eq = cheapest(other_runs, oref, best[0], True)
        print(f"{code}'s run closest to its own limit: {best[2][0]} el., dt {best[2][1]}, "
              f"{100 * best[0]:.2f} % off, {best[1]:.2f} s for the scene"
              + (f"; the other code's cheapest run at least as close to its own limit: "
                 f"{eq[1][0]} el., dt {eq[1][1]}, {eq[0]:.2f} s (ratio "
                 f"{best[1] / eq[0] if code == 'PyElastica' else eq[0] / best[1]:.1f}, "
                 f"PyElastica / slither)" if eq else ""))
    print()
    print("A run's error against a limit is known only to that limit's uncertainty (above).")
    like = {}
    for f in glob.glob(os.path.join(out, "like_*.json")):
        n, dt = re.match(r"like_(\d+)_(.+)\.json", os.path.basename(f)).groups()
        j = json.load(open(f))
        like[(int(n), dt)] = {"v": j["v_s_over_v_m"], "rate": j["wall_per_sim_second"],
                              "stable": j["stable"]}
    if like:
        lm = per_mesh(like, 2)
        best, u, p, note = limit(lm)
        print()
        print("## PyElastica with slither's modelling choices (ground 100x stiffer, no rod "
              "damping, static = kinetic friction)")
        print()
        print("| elements | " + " | ".join(str(n) for n in sorted(lm)) + " | limit |")
        print("|---|" + "---|" * (len(lm) + 1))
        print("| v_s/v_m | " + " | ".join(f"{lm[n][0]:.5f} (+-{lm[n][1]:.5f})" for n in sorted(lm))
              + f" | {best:.5f} +- {u:.5f} |")
        print(f"\n{note}")
        print(f"\nAgainst slither's limit {b:.5f} +- {ub:.5f}: difference {best - b:+.5f} "
              f"({100 * (best - b) / b:+.2f} %), combined uncertainty {u + ub:.5f}: "
              + ("within it" if abs(best - b) <= u + ub else "larger"))

    with open(stem + ".csv", "w") as fcsv:
        fcsv.write("code,elements,dt_s,stable,v_s_over_v_m,wall_s_per_simulated_s,"
                   "error_vs_own_limit,error_vs_other_limit\n")
        for code, runs, own, other in (("PyElastica 1.0.0", pe, a, b), ("slither", sl, b, a)):
            for k in sorted(runs, key=lambda k: (k[0], -float(k[1]))):
                r = runs[k]
                fcsv.write(f"{code},{k[0]},{k[1]},{r['stable']},{r['v']:.6f},{r['rate']:.4f},"
                           f"{r['v'] / own - 1:.6f},{r['v'] / other - 1:.6f}\n")
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True)
    colours = {"PyElastica": "tab:orange", "slither": "tab:blue"}
    for ax, which in zip(axes, ("own", "other")):
        for code, runs in (("PyElastica", pe), ("slither", sl)):
            ref = lim[code][0] if which == "own" else lim["slither" if code == "PyElastica"
                                                          else "PyElastica"][0]
            for n in sorted({k[0] for k in runs}):
                ks = sorted((k for k in runs if k[0] == n and runs[k]["stable"]),
                            key=lambda k: -float(k[1]))
                xs = [runs[k]["rate"] * T for k in ks]
                ys = [max(abs(runs[k]["v"] / ref - 1.0) * 100, 1e-3) for k in ks]
                ax.plot(xs, ys, "-o" if code == "slither" else "-^", color=colours[code],
                        alpha=0.35 + 0.65 * math.log2(n / 25) / 5, ms=5,
                        label=f"{code} {n} el.")
                ax.annotate(f"{n}", (xs[-1], ys[-1]), fontsize=7, color=colours[code])
        for tol in (1, 2):
            ax.axhline(tol, color="grey", lw=0.6, ls="--")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time for the 4 s scene (s)")
        ax.set_title("against its own limit" if which == "own"
                     else "against the other code's limit")
        ax.grid(True, which="both", lw=0.3)
    axes[0].set_ylabel("|error of v_s/v_m| (%)")
    axes[0].legend(fontsize=7, ncol=2)
    fig.suptitle("S-start on PyElastica's scene, same muscle physics: PyElastica 1.0 "
                 f"(limit {a:.4f} +- {ua:.4f}) and slither ({b:.4f} +- {ub:.4f})")
    fig.tight_layout()
    fig.savefig(stem + ".png", dpi=110)
    print(f"\nwrote {stem}.png and {stem}.csv")


if __name__ == "__main__":
    main()
