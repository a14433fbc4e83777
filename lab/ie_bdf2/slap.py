#!/usr/bin/env python3
"""The window 1.70-2.05 s at 1 ms frames: centroid x of BDF2 and of IE at 3.125e-5 s against IE at
1.25e-4 s (mm), contacts, head height, landings and lift-offs per frame."""
import numpy as np
ie = np.load("runs/slap_implicit_200_1.25e-4/trajectory.npz")
bd = np.load("runs/slap_bdf2_200_1.25e-4/trajectory.npz")
if2 = np.load("runs/slap_implicit_200_3.125e-5/trajectory.npz")
t = ie["t"]; thr = 1e-3
def cx(d, j): return 1e3 * d["x"][j, :, 0].mean()
def contacts(d, j): return d["normal_force"][j] > thr
print(" t      bdf2-ie  ie/4-ie  | contacts ie bdf2 | head z/a ie bdf2 | lifted-span ie / bdf2 | land+lift per frame ie bdf2 | sum N ie bdf2")
for j in range(1700, len(t), 10):
    ci, cb = contacts(ie, j), contacts(bd, j)
    ev_i = np.sum(contacts(ie, j) != contacts(ie, j - 1)); ev_b = np.sum(contacts(bd, j) != contacts(bd, j - 1))
    def span(c):
        w = np.where(~c)[0]
        return "%d-%d" % (w.min(), w.max()) if len(w) else "-"
    print("%.3f %8.3f %8.3f | %4d %4d | %6.2f %6.2f | %9s / %9s | %3d %3d | %.2f %.2f" % (
        t[j], cx(bd, j) - cx(ie, j), cx(if2, j) - cx(ie, j), ci.sum(), cb.sum(),
        (ie["x"][j, 0, 2] - 0.01) / 0.02, (bd["x"][j, 0, 2] - 0.01) / 0.02, span(ci), span(cb), ev_i, ev_b,
        ie["normal_force"][j].sum(), bd["normal_force"][j].sum()))
# event counts over windows (frame-to-frame contact changes, 1 ms frames)
for a, b in [(0, 1700), (1700, 2050)]:
    for name, d in [("ie 1.25e-4", ie), ("bdf2 1.25e-4", bd), ("ie 3.125e-5", if2)]:
        n = sum(np.sum(contacts(d, j) != contacts(d, j - 1)) for j in range(max(a, 1), min(b, len(d["t"]))))
        print("contact changes between frames, t %.2f-%.2f s, %s: %d" % (d["t"][a], d["t"][min(b, len(d['t'])) - 1], name, n))
