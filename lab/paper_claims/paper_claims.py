#!/usr/bin/env python3
"""The paper's claims, measured: the numbers of the guide's chapter "The paper, claim by claim".

Usage: lab/paper_claims/paper_claims.py OUT

OUT holds what lab/paper_claims/paper_claims.sh ran: s_start/ (the bundled S-start), friction/ and
flailing/ (one friction-dominated and one flailing cell of the 20 x 20 map), sidewinding/ (the
bundled sidewinding), map/ (the verified 20 x 20 map with self-contact, redrawn from its
committed phase.csv) and growth/ (the growth line with self-contact, redrawn from its committed
growth.csv). Every line is `key value`: the chapter quotes the values by their keys, and
tests/claims_drift.rs checks that each quoted number is this record's value, rounded.
"""
import csv
import json
import math
import sys
from collections import Counter, defaultdict

import numpy as np

out = sys.argv[1]


def say(key, value, fmt="{:.4g}"):
    if isinstance(value, str):
        print(f"{key} {value}")
    else:
        print(f"{key} {fmt.format(value)}")


def rank(x):
    """Ranks with ties averaged (for Spearman's rho)."""
    x = np.asarray(x, float)
    order = np.argsort(x, kind="mergesort")
    r = np.empty(len(x))
    r[order] = np.arange(len(x), dtype=float)
    for v in np.unique(x):
        m = x == v
        if m.sum() > 1:
            r[m] = r[m].mean()
    return r


def spearman(x, y):
    if len(x) < 3:
        return float("nan")
    rx, ry = rank(x), rank(y)
    if rx.std() == 0 or ry.std() == 0:
        return float("nan")
    return float(np.corrcoef(rx, ry)[0, 1])


def lambda_shape(z, t_lo, t_hi):
    """Median over the frames in [t_lo, t_hi] of the largest |lambda| and of the share of the
    windows where |lambda| is above half that frame's largest (how spread the density is)."""
    t, lam = z["t"], z["lambda"]
    peaks, spread = [], []
    for k in range(len(t)):
        if not (t_lo <= t[k] <= t_hi):
            continue
        a = np.abs(lam[k])
        p = a.max()
        if p <= 0:
            continue
        peaks.append(p)
        spread.append(float((a >= 0.5 * p).mean()))
    return float(np.median(peaks)), float(np.median(spread))


# ---- Fig. 2: the bundled S-start's kymographs ----------------------------------------------
print("## Fig. 2: the bundled S-start (problems/s_start.toml)")
s = json.load(open(f"{out}/s_start/summary.json"))
z = np.load(f"{out}/s_start/trajectory.npz")
a = float(z["diameter"][0])
v_m = float(z["gait_speed"][0])
sgrid = z["s"]
L = float(sgrid[-1])
T = L / v_m
centers, sigma = (0.20, 0.35, 0.50), 0.0525          # problems/s_start.toml, fractions of L
say("s_start.regime", s["regime"])
say("s_start.v_s_over_v_m", s["v_s_over_v_m"])
say("s_start.heading_deg", s["displacement_angle_deg"])
# While the whole triplet is on the body (t/T in [0.05, 0.45]: after the ramp, before c nears
# the tail): the lowest node between the centres of a and c, against the centre of b.
offsets, low, arc_a, arc_c, cv, inside, patch_off, spd = [], [], [], [], [], [], [], []
for k, t in enumerate(z["t"]):
    if not (0.05 * T <= t <= 0.45 * T):
        continue
    sa, sb, sc = [(c * L + v_m * t) for c in centers]
    e = z["elevation"][k]
    mid = (sgrid >= sa) & (sgrid <= sc)
    i = np.flatnonzero(mid)[np.argmin(e[mid])]
    offsets.append(abs(sgrid[i] - sb) / L)
    # the middle contact patch: nodes between a and c on the ground (elevation below a/20)
    on = mid & (e < 0.05 * a)
    if on.any():
        patch = sgrid[on]
        inside.append(patch.min() - 0.5 * L / (len(sgrid) - 1) <= sb <= patch.max() + 0.5 * L / (len(sgrid) - 1))
        patch_off.append(abs(0.5 * (patch.min() + patch.max()) - sb) / L)
    low.append(e[i] / a)
    arc_a.append(e[(sgrid >= sa - 2 * sigma * L) & (sgrid < sb)].max() / a)
    arc_c.append(e[(sgrid > sb) & (sgrid <= sc + 2 * sigma * L)].max() / a)
    # speed of the nodes outside the middle (a to c): how uniform (coefficient of variation)
    sp = np.linalg.norm(z["v"][k], axis=1)
    out_mid = ~mid
    cv.append(sp[out_mid].std() / sp[out_mid].mean())
    spd.append(np.median(sp[out_mid]) / v_m)
say("fig2.frames", len(offsets), "{:d}")
say("fig2.elevation_min_offset_from_b_over_L_median", float(np.median(offsets)))
say("fig2.elevation_min_offset_from_b_over_L_max", float(np.max(offsets)))
say("fig2.elevation_min_over_a_median", float(np.median(low)))
say("fig2.frames_with_middle_patch", len(inside), "{:d}")
say("fig2.frames_b_inside_middle_patch", int(sum(inside)), "{:d}")
say("fig2.middle_patch_centre_offset_from_b_over_L_median", float(np.median(patch_off)))
say("fig2.arc_a_lift_over_a_median", float(np.median(arc_a)))
say("fig2.arc_c_lift_over_a_median", float(np.median(arc_c)))
say("fig2.middle_static_fraction", s["middle_static_fraction"])
say("fig2.middle_slip_over_v_m", s["middle_slip_over_v_m"])
say("fig2.speed_cv_outside_middle_median", float(np.median(cv)))
say("fig2.speed_outside_middle_over_v_m_median", float(np.median(spd)))
say("fig2.max_elevation_over_a", s["max_elevation_over_a"])
say("fig2.arc_lift_max_over_a", s["arc_lift_max_over_a"])
say("fig2.two_arc_lift_over_a", s["two_arc_lift_over_a"])

# ---- the lambda pulse: S-start, friction-dominated, flailing ------------------------------
print()
print("## The lambda pulse: the S-start, a friction-dominated cell, a flailing cell")
for name in ("s_start", "friction", "flailing"):
    sm = json.load(open(f"{out}/{name}/summary.json"))
    zz = np.load(f"{out}/{name}/trajectory.npz")
    TT = float(zz["s"][-1]) / float(zz["gait_speed"][0])
    peak, spread = lambda_shape(zz, 0.05 * TT, 0.45 * TT)
    say(f"lambda.{name}.regime", sm["regime"])
    say(f"lambda.{name}.W", sm["dimensionless"]["scaled_weight"])
    say(f"lambda.{name}.v_s_over_v_m", sm["v_s_over_v_m"])
    say(f"lambda.{name}.pulse_r2", sm["lambda_pulse_r2"] if sm["lambda_pulse_r2"] is not None else float("nan"))
    sp = sm["lambda_pulse_speed_over_v_m"]
    say(f"lambda.{name}.pulse_speed_over_v_m", sp if sp is not None else float("nan"))
    say(f"lambda.{name}.peak_abs_lambda_median", peak)
    say(f"lambda.{name}.share_above_half_peak_median", spread)
    av = sm["lambda_amplitude_variation"]
    say(f"lambda.{name}.amplitude_variation", av if av is not None else float("nan"))

# ---- the verified 20 x 20 map with self-contact ------------------------------------------
rows = list(csv.DictReader(open(f"{out}/map/phase.csv")))
W = np.array([float(r["weight"]) for r in rows])
G = np.array([float(r["torque"]) for r in rows])
R = W / G
lab = np.array([r["regime"] for r in rows])
agree = np.array([float(r["label_agreement"]) for r in rows])
v = np.array([float(r["v_s_over_v_m"]) for r in rows])
wr_max = np.array([float(r["writhe_max"]) for r in rows])
wr_snap = np.abs(np.array([float(r["writhe_snapshot"]) for r in rows]))
certain = agree == 1
print()
print("## The verified 20 x 20 map (problems/phase_fine.toml, self-contact, every cell verified)")
say("map.cells", len(rows), "{:d}")
say("map.certain_cells", int(certain.sum()), "{:d}")
for k in "SMFNU":
    say(f"map.cells_{k}", int((lab == k).sum()), "{:d}")
    say(f"map.certain_cells_{k}", int(((lab == k) & certain).sum()), "{:d}")
# M ("moves, not an S-start"): which S criteria its cells miss (regime_detail).
detail = Counter(r["regime_detail"] for r in rows if r["regime"] == "M")
for d, n in sorted(detail.items()):
    say(f"map.M_missing.{d}", n, "{:d}")
say("map.M_missing_heading_only_or_with_others",
    sum(n for d, n in detail.items() if "heading" in d.split(";")), "{:d}")
say("map.M_missing_two_arcs", sum(n for d, n in detail.items() if "two_arcs" in d.split(";")), "{:d}")
say("map.M_missing_pulse", sum(n for d, n in detail.items()
                               if {"pulse_fit", "pulse_speed"} & set(d.split(";"))), "{:d}")

# Fig. 3a: writhe against W/G. The paper plots Wr at one snapshot (writhe_snapshot, when
# couple b passes mid-body); the largest |writhe| (writhe_max) is given beside it.
print()
print("## Fig. 3a: writhe against W/G")
for label, wr in (("snapshot", wr_snap), ("max", wr_max)):
    say(f"fig3a.{label}.spearman_all_cells", spearman(R, wr))
    m = lab != "U"
    say(f"fig3a.{label}.spearman_without_U", spearman(R[m], wr[m]))
    falling, rhos = 0, []
    for g in sorted(set(G)):
        r = G == g
        rho = spearman(R[r], wr[r])
        rhos.append((g, rho))
        falling += rho < 0
    say(f"fig3a.{label}.rows_falling", falling, "{:d}")
    low_g = [rho for g, rho in rhos if g < 14]
    high_g = [rho for g, rho in rhos if g > 40]
    say(f"fig3a.{label}.rho_max_G_below_14", max(low_g))
    say(f"fig3a.{label}.rho_min_G_above_40", min(high_g))
    say(f"fig3a.{label}.rho_max_G_above_40", max(high_g))
# Wr against W/G alone: cells at equal W/G (within a tenth of a decade) but different G.
bins = defaultdict(list)
for i in range(len(rows)):
    bins[round(math.log10(R[i]) * 10)].append(i)
ratios = [np.ptp(wr_max[ix]) for ix in bins.values() if len(ix) >= 3]
say("fig3a.max.range_at_equal_W_over_G_median", float(np.median(ratios)))

# Fig. 3b: speed against writhe.
print()
print("## Fig. 3b: speed against writhe")
moving = (lab == "S") | (lab == "M")
i_best = np.flatnonzero(moving)[np.argmax(v[moving])]
say("fig3b.fastest_coherent.v_s_over_v_m", v[i_best])
say("fig3b.fastest_coherent.regime", lab[i_best])
say("fig3b.fastest_coherent.writhe_max", wr_max[i_best])
say("fig3b.fastest_coherent.writhe_snapshot_abs", wr_snap[i_best])
i_s = np.flatnonzero(lab == "S")[np.argmax(v[lab == "S"])]
say("fig3b.fastest_S.v_s_over_v_m", v[i_s])
say("fig3b.fastest_S.writhe_max", wr_max[i_s])
say("fig3b.S.writhe_max_median", float(np.median(wr_max[lab == "S"])))
say("fig3b.U.writhe_max_median", float(np.median(wr_max[lab == "U"])))
say("fig3b.U.writhe_max_q10", float(np.quantile(wr_max[lab == "U"], 0.1)))
i_u = np.flatnonzero(lab == "U")[np.argmax(v[lab == "U"])]
say("fig3b.fastest_U.v_s_over_v_m", v[i_u])
say("fig3b.fastest_U.writhe_max", wr_max[i_u])
say("fig3b.U.v_s_over_v_m_median", float(np.median(v[lab == "U"])))
say("fig3b.U.backward_share", float((v[lab == "U"] <= -0.01).mean()))
flat = wr_max < 0.05
say("fig3b.below_0.05.cells", int(flat.sum()), "{:d}")
say("fig3b.below_0.05.v_s_over_v_m_max", float(v[flat].max()))
edges = [0, 0.05, 0.2, 0.4, 0.7, 1.0, 1.5, 100]
for lo, hi in zip(edges[:-1], edges[1:]):
    m = (wr_max >= lo) & (wr_max < hi)
    c = Counter(lab[m])
    say(f"fig3b.bin_{lo}_{hi}.cells", int(m.sum()), "{:d}")
    say(f"fig3b.bin_{lo}_{hi}.v_s_over_v_m_median", float(np.median(v[m])))
    say(f"fig3b.bin_{lo}_{hi}.labels", " ".join(f"{k}:{c[k]}" for k in "SMFNU"))

# Fig. 3c: speed against W/G; where the snake moves backward.
print()
print("## Fig. 3c: speed against W/G")
back = v <= -0.01
say("fig3c.backward_cells", int(back.sum()), "{:d}")
say("fig3c.backward_cells_F", int((back & (lab == "F")).sum()), "{:d}")
say("fig3c.backward_cells_U", int((back & (lab == "U")).sum()), "{:d}")
say("fig3c.backward_G_min", float(G[back].min()))
say("fig3c.backward_W_over_G_min", float(R[back].min()))
say("fig3c.backward_W_over_G_max", float(R[back].max()))
say("fig3c.backward_v_s_over_v_m_min", float(v[back].min()))
say("fig3c.S_W_over_G_min", float(R[lab == "S"].min()))
say("fig3c.S_W_over_G_max", float(R[lab == "S"].max()))
say("fig3c.S_G_min", float(G[lab == "S"].min()))
say("fig3c.S_G_max", float(G[lab == "S"].max()))
say("fig3c.S_certain_G_values", " ".join(f"{g:.3g}" for g in sorted(set(G[(lab == 'S') & certain]))))

# Fig. 3d: the phase space. Where each regime lies, the fitted boundaries, and whether W/G
# alone sets the label: the share of cells that carry their bin's most common label, in bins
# of a tenth of a decade of W/G, of W or of G (1 when that quantity alone sets the regime).
print()
print("## Fig. 3d: the phase space")
for k in "SMFNU":
    m = lab == k
    say(f"fig3d.{k}.W_median", float(np.median(W[m])))
    say(f"fig3d.{k}.G_median", float(np.median(G[m])))
    say(f"fig3d.{k}.W_over_G_median", float(np.median(R[m])))
for name, x in (("W_over_G", R), ("W", W), ("G", G)):
    b = defaultdict(list)
    for i in range(len(rows)):
        b[round(math.log10(x[i]) * 10)].append(lab[i])
    pure = sum(Counter(ls).most_common(1)[0][1] for ls in b.values()) / len(rows)
    say(f"fig3d.label_purity_by_{name}", pure)
bj = json.load(open(f"{out}/map/boundaries.json"))
for bnd in bj["boundaries"]:
    if bnd["slope"] is not None and len(bnd["points"]) >= 4:
        say(f"fig3d.boundary_{bnd['pair']}.slope", bnd["slope"], "{:.3f}")
        say(f"fig3d.boundary_{bnd['pair']}.points", len(bnd["points"]), "{:d}")

# Biology: the growth line with self-contact.
print()
print("## Growth: juveniles to adults (problems/growth.toml, self-contact)")
gj = json.load(open(f"{out}/growth/growth.json"))
labels = [(p["diameter"] * 100, p["regime"], p["confident"], p["w_over_g"]) for p in gj["points"]]
say("growth.sizes", len(labels), "{:d}")
say("growth.S_sizes_cm", " ".join(f"{d:.3g}" for d, l, c, r in labels if l == "S" and c))
say("growth.certain_sizes", sum(c for d, l, c, r in labels), "{:d}")
say("growth.sizes_above_2.5cm", sum(d > 2.5 for d, l, c, r in labels), "{:d}")
say("growth.certain_above_2.5cm", sum(c for d, l, c, r in labels if d > 2.5), "{:d}")
big = [p for p in gj["points"] if p["diameter"] > 0.025]
say("growth.above_2.5cm_U", sum(p["regime"] == "U" for p in big), "{:d}")
say("growth.above_2.5cm_backward_in_a_run", sum(min(p["v_s_over_v_m_range"]) <= -0.01 for p in big), "{:d}")
say("growth.at_1cm_regime", labels[0][1])
say("growth.at_1cm_v_s_over_v_m", gj["points"][0]["v_s_over_v_m"])
say("growth.W_over_G_at_1cm", labels[0][3], "{:.3g}")
say("growth.W_over_G_at_10cm", labels[-1][3], "{:.3g}")
print("growth.verdict", gj.get("verdict", "-"))

# Sidewinding.
print()
print("## Sidewinding (problems/sidewinding.toml)")
sw = json.load(open(f"{out}/sidewinding/summary.json"))
p = sw["periodic"]
say("sidewinding.sidewinding", str(p["sidewinding"]).lower())
say("sidewinding.cycles", len(p["cycles"]), "{:d}")
say("sidewinding.broadside_deg_min", p["broadside_deg_min"])
say("sidewinding.turn_deg_max_abs", p["turn_deg_max_abs"])
say("sidewinding.displacement_over_length_min", p["displacement_over_length_min"])
say("sidewinding.stationary_contact_share_min", p["stationary_contact_share_min"])
say("sidewinding.lateral_speed_over_v_m", p["lateral_speed_over_v_m"])
zs = np.load(f"{out}/sidewinding/trajectory.npz")
P = float(zs["gait_period"][0])
# Lobes of |lambda| above a fifth of the run's largest, in each frame after the first cycle.
lam_all = np.abs(zs["lambda"])
top = lam_all.max()
lobes = []
for k, t in enumerate(zs["t"]):
    if t < P:
        continue
    on = lam_all[k] >= 0.2 * top
    lobes.append(int(on[0]) + int(np.sum(on[1:] & ~on[:-1])))
lobes = np.array(lobes)
say("sidewinding.lambda_frames", len(lobes), "{:d}")
say("sidewinding.lambda_lobes_median", float(np.median(lobes)), "{:.1f}")
say("sidewinding.lambda_lobes_max", int(lobes.max()), "{:d}")
say("sidewinding.lambda_frames_with_2_or_more_lobes", int((lobes >= 2).sum()), "{:d}")
