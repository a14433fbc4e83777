#!/usr/bin/env python3
"""Max node distance (m) between two runs' trajectories at every recorded frame."""
import numpy as np, sys
a = np.load(sys.argv[1] + "/trajectory.npz"); b = np.load(sys.argv[2] + "/trajectory.npz")
n = min(len(a["t"]), len(b["t"]))
every = int(sys.argv[3]) if len(sys.argv) > 3 else 5
for k in range(0, n, every):
    d = np.abs(a["x"][k] - b["x"][k]).max()
    ca = a["x"][k].mean(0); cb = b["x"][k].mean(0)
    print("%.4f  maxdist %.3e  centroid dx %.3e dy %.3e" % (a["t"][k], d, cb[0]-ca[0], cb[1]-ca[1]))
