#!/usr/bin/env python3
"""BDF2's event rule at node 31 around t = 0.3863 s (100 elements, 1.25e-4 s), reconstructed from
the per-step frames of the base run and of the run with v_m * (1 + 1e-6): the normal coordinate
takes an implicit Euler step when the BDF2 predictor lies below a/2 - 1e-9 a."""
import numpy as np
h = 1.25e-4; floor = 0.01; eps = 1e-9 * 0.02
for r in ["runs/loc_bdf2_100_1.25e-4", "runs/locpvm_bdf2_100_1.25e-4"]:
    d = np.load(r + "/trajectory.npz"); t = d["t"]; print(r)
    for tt in (0.386125, 0.386250, 0.386375, 0.3865):
        n = int(np.argmin(abs(t - tt))); i = 31
        z, z1, v, v1 = d["x"][n, i, 2], d["x"][n - 1, i, 2], d["v"][n, i, 2], d["v"][n - 1, i, 2]
        qhat = (4 * z - z1) / 3 - (h / 2.25) * (-2 * v + 0.5 * v1)
        print("  step from t=%.6f: z-a/2 %.3e, v_z %.4f, BDF2 predictor - a/2 %.3e -> %s; z-a/2 after %.3e" % (
            t[n], z - floor, v, qhat - floor, "Euler" if qhat < floor - eps else "BDF2", d["x"][n + 1, i, 2] - floor))
