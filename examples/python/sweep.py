"""A sweep of the travelling speed v_m of the bundled S-start, from Python.

Run from the repository root after `pip install ./python`:

    python examples/python/sweep.py [--quick]

Prints v_s and the regime for each v_m, writes out/sweep_v_m.csv and, when matplotlib is
installed, out/sweep_v_m.png. `--quick` simulates a fifth of the pulse (seconds instead of
tens of seconds). Runs go two at a time in Python threads: slither releases the GIL.
"""
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

import slither_gait as sg

base = sg.load_problem("problems/s_start.toml")
if "--quick" in sys.argv:
    base = base.with_(**{"time.duration": 0.7})
speeds = np.linspace(0.22, 0.34, 5)  # v_m (m/s)


def simulate(v_m):
    return sg.run(base.with_(**{"gait.speed": float(v_m)}), progress=False)


with ThreadPoolExecutor(max_workers=2) as pool:
    results = list(pool.map(simulate, speeds))

v_s = np.array([r.summary["v_s"] for r in results])
for v_m, r in zip(speeds, results):
    print(f"v_m = {v_m:.3f} m/s: v_s = {r.summary['v_s']:.4f} m/s "
          f"(v_s/v_m = {r.summary['v_s_over_v_m']:.3f}), regime {r.regime}")

out = Path("out")
out.mkdir(exist_ok=True)
np.savetxt(out / "sweep_v_m.csv", np.column_stack([speeds, v_s]), delimiter=",",
           header="v_m,v_s", comments="")
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib is not installed: no plot (pip install matplotlib)")
else:
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.5))
    a.plot(speeds, v_s, "o-")
    a.set(xlabel="v_m (m/s)", ylabel="v_s (m/s)", title="forward speed")
    slowest = results[0]
    a_t = slowest.t  # kymograph of the link density of the slowest pulse
    b.pcolormesh(np.arange(slowest.lambda_.shape[1]), a_t, slowest.lambda_, shading="auto")
    b.set(xlabel="window (head to tail)", ylabel="t (s)", title=f"lambda, v_m = {speeds[0]:.2f}")
    fig.tight_layout()
    fig.savefig(out / "sweep_v_m.png", dpi=120)
    print(f"wrote {out / 'sweep_v_m.png'}")
print(f"wrote {out / 'sweep_v_m.csv'}")
