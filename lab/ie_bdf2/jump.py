#!/usr/bin/env python3
"""Per-frame max node distance between two runs; print frames where it grows by > FACTOR, with
the node, its height, normal force and slip speed in both runs."""
import numpy as np, sys
a = np.load(sys.argv[1] + "/trajectory.npz"); b = np.load(sys.argv[2] + "/trajectory.npz")
fac = float(sys.argv[3]) if len(sys.argv) > 3 else 3.0
n = min(len(a["t"]), len(b["t"]))
prev = 1e-12
a_r = 0.01
for k in range(1, n):
    d = np.abs(a["x"][k] - b["x"][k]).max(axis=1)
    i = int(d.argmax()); m = d[i]
    if m > fac * prev and m > 1e-9:
        print("t %.6f  maxdist %.3e (was %.3e) node %d  z-a/2: %.3e / %.3e  N: %.4f / %.4f  slip: %.3e / %.3e" % (
            a["t"][k], m, prev, i, a["x"][k][i][2] - a_r, b["x"][k][i][2] - a_r,
            a["normal_force"][k][i], b["normal_force"][k][i], a["slip_speed"][k][i], b["slip_speed"][k][i]))
    prev = max(prev, m)
