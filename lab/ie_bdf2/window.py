#!/usr/bin/env python3
"""Centroid x (mm) at chosen times for several runs, and the forward displacement gained in each
window: where along the run the step dependence is acquired."""
import numpy as np, sys
times = [0.36, 0.9, 1.44, 1.764, 2.016, 2.304, 2.88, 3.572]
print("run                           " + " ".join("%8.3f" % t for t in times))
for r in sys.argv[1:]:
    d = np.load(r + "/trajectory.npz"); t = d["t"]
    c = [1e3 * (d["x"][int(np.argmin(abs(t - tt))), :, 0].mean() - d["x"][0, :, 0].mean()) for tt in times]
    print("%-30s" % r.split("/")[-1] + " ".join("%8.2f" % x for x in c))
