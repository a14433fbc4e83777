#!/usr/bin/env python3
"""Contacts (normal force > 1e-3 N) every 10 ms in 1.80-2.05 s, and contact changes between 1 ms
frames per window, for IE and BDF2 at 1.25e-4 and 3.125e-5 s (200 elements)."""
import numpy as np
runs = [("IE 1.25e-4", "runs/slap_implicit_200_1.25e-4"), ("IE 3.125e-5", "runs/slap_implicit_200_3.125e-5"),
        ("BDF2 1.25e-4", "runs/slap_bdf2_200_1.25e-4"), ("BDF2 3.125e-5", "runs/slap_bdf2_200_3.125e-5")]
d = [(n, np.load(r + "/trajectory.npz")) for n, r in runs]
c = lambda e, j: e["normal_force"][j] > 1e-3
print("t      " + "  ".join("%13s" % n for n, _ in d) + "   (contacts; centroid x mm)")
for j in range(1800, 2051, 10):
    print("%.3f " % d[0][1]["t"][j] + "  ".join("%4d %8.2f" % (c(e, j).sum(), 1e3 * e["x"][j, :, 0].mean()) for _, e in d))
print()
for a, b in [(1, 1700), (1700, 1820), (1820, 2051)]:
    print("contact changes %.2f-%.2f s: " % (a / 1e3, b / 1e3) + "  ".join("%s %d" % (n, sum(np.sum(c(e, j) != c(e, j - 1)) for j in range(a, b))) for n, e in d))
