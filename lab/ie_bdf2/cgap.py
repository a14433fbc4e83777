#!/usr/bin/env python3
"""Centroid x difference (mm) of several runs against the first, at every k-th recorded frame."""
import numpy as np, sys
k = int(sys.argv[1]); runs = sys.argv[2:]
d = [np.load(r + "/trajectory.npz") for r in runs]
print("t     " + "  ".join("%10s" % r.split("/")[-1][-18:] for r in runs[1:]))
ref = d[0]["x"][:, :, 0].mean(1)
for j in range(0, len(d[0]["t"]), k):
    print("%.3f " % d[0]["t"][j] + "  ".join("%10.4f" % (1e3 * (e["x"][j, :, 0].mean() - ref[j])) for e in d[1:]))
