#!/usr/bin/env python3
"""PyElastica's trajectory of a free, muscle-driven rod, written as a test fixture.

The rod of compare/pyelastica_s_start.py (L 1 m, a 0.02 m, W 300's B = 0.01308 N m^2,
C = 2B/3, stretch and shear 10x physical) with no gravity, no ground and no damping, driven by
muscles as a time-dependent rest curvature (pyelastica_s_start.CurvatureMuscles). Two cases:

  s-start  the S-start's three couples: G 15, sigma 0.04 L, centres 0.2/0.3/0.4 L,
           v_m 0.25 m/s, ramp over 0.05 T (T = 4 s).
  spin     twist matters: an in-plane couple (scale 1) and an out-of-plane couple (scale 0.5)
           at the same place (0.3 L), no third couple, on a rod spinning about its own axis at
           2 rad/s from the start. The couples act in the material frame, so the plane they
           bend the body in turns with the material frame: the shape depends on the twist
           degree of freedom (its initial rate, its inertia and its transport along the bent
           body).
  twisted  the S-start's three couples on a pre-twisted rod: natural twist 2 pi rad/m (one
           right-handed turn over the body), the rod starting at rest in it, its material
           frame unturned at the head. The couples travel through material frames turned
           36 degrees from one centre to the next, so the body bends in a helical wave.

Output (JSON, positions rounded to 1e-7 m): the frames every 0.05 s over 1 s of the 101 node
positions, in slither's axes and order: head first, z up (PyElastica's y), y = -(PyElastica's
z), so the initial rod lies along +x with its head at x = L and its centreline at z = a/2, as
slither's straight start. Also recorded: the command, the versions, the step, the change of the
total angular momentum over the run (an internal moment conserves it), and the rms node
distance to the same run at half the step (the step's own error).

Usage:  free_rod_fixture.py {s-start|spin|twisted} OUT.json [--dt 1e-5] [--elements 100]
                            [--store-every K]   (every K-th node only: a finer run stored at
                                                 a coarser mesh's nodes)
"""

import argparse
import importlib.metadata
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pyelastica_s_start as pe  # noqa: E402

CASES = {
    "s-start": dict(centres=(0.2, 0.3, 0.4), scales=(1.0, 1.0, 1.0), spin=0.0),
    "spin": dict(centres=(0.3, 0.3, 0.3), scales=(1.0, 0.5, 0.0), spin=2.0),
    "twisted": dict(centres=(0.2, 0.3, 0.4), scales=(1.0, 1.0, 1.0), spin=0.0,
                    twist=2.0 * math.pi),
}
DURATION = 1.0
FRAME_INTERVAL = 0.05


def run(case, n_elem, dt, muscles="curvature"):
    c = CASES[case]
    frame_every = int(round(FRAME_INTERVAL / dt))
    gait = pe.Gait(n_elem, centres=c["centres"], scales=c["scales"])
    sim, rod, store, _, pre = pe.build(
        n_elem, dt, damping="none", record_every=frame_every, muscles=muscles,
        free=True, spin=c["spin"], gait=gait, frame_every=frame_every,
        twist=c.get("twist", 0.0),
    )
    pe.step(sim, int(round(DURATION / dt)), dt, pre)
    ang, scale = pe.angular_momentum(rod)
    frames = [(t, x) for t, x in zip(store["frames_t"], store["frames_x"])]
    return frames, ang - store["ang"][0], max(store["ang_scale"])


def to_slither(x, every=1):
    """(3, n+1) PyElastica positions, tail first, y up -> (n+1, 3) head first, z up (every
    `every`-th node)."""
    x = x[:, ::-1][:, ::every]
    return np.stack([x[0], -x[2], x[1]], axis=1)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=sorted(CASES))
    ap.add_argument("out")
    ap.add_argument("--dt", type=float, default=1e-5)
    ap.add_argument("--elements", type=int, default=100)
    ap.add_argument("--muscles", choices=["curvature", "torque"], default="curvature",
                    help="torque: the element-torque form, for the record (not a fixture)")
    ap.add_argument("--store-every", type=int, default=1,
                    help="store every k-th node only (a finer run at a coarser fixture's nodes)")
    args = ap.parse_args()
    k = args.store_every
    if k < 1 or args.elements % k:
        ap.error("--store-every must divide --elements")

    frames, ang, scale = run(args.case, args.elements, args.dt, args.muscles)
    half, _, _ = run(args.case, args.elements, 0.5 * args.dt, args.muscles)
    step_error = [
        float(np.sqrt(np.mean(np.sum((to_slither(a[1]) - to_slither(b[1])) ** 2, axis=1))))
        / pe.A_DIAM
        for a, b in zip(frames, half)
    ]
    c = CASES[args.case]
    out = {
        "what": "PyElastica's free, muscle-driven rod (compare/free_rod_fixture.py, case "
                f"'{args.case}'): no gravity, no ground, no damping; muscles as a "
                "time-dependent rest curvature (unless 'muscles' says otherwise). Node "
                "positions in slither's axes and order (head first, z up), "
                f"every {k}th node of {args.elements} elements' (stored_nodes of them), "
                "metres, rounded to 1e-7 m; frame k at t = k * 0.05 s.",
        "command": "compare/.venv/bin/python compare/free_rod_fixture.py "
                   + " ".join(sys.argv[1:]),
        "pyelastica": importlib.metadata.version("pyelastica"),
        "numpy": np.__version__,
        "numba": importlib.metadata.version("numba"),
        "integrator": "PositionVerlet",
        "dt": args.dt,
        "elements": args.elements,
        "stored_nodes": args.elements // k + 1,
        "rod": {"length": pe.L, "diameter": pe.A_DIAM, "density": pe.RHO,
                "bending_stiffness": pe.B, "twist_stiffness": pe.G_MOD * 2 * pe.INERTIA,
                "stretch_stiffness": pe.SS_FACTOR * pe.E_MOD * pe.AREA,
                "shear_stiffness": pe.SS_FACTOR * pe.G_MOD * pe.AREA},
        "gait": {"Gamma_a3": pe.GAMMA_A3, "sigma": pe.SIGMA, "v_m": pe.V_M,
                 "ramp_time": pe.RAMP * pe.T_PULSE, "centres": list(c["centres"]),
                 "scales": list(c["scales"])},
        "muscles": args.muscles,
        "spin": c["spin"],
        "natural_twist": c.get("twist", 0.0),
        "angular_momentum_change_final": ang.tolist(),
        "angular_momentum_change_final_norm": float(np.linalg.norm(ang)),
        "motion_scale_sum_m_r_v_max": scale,
        "rms_distance_to_half_step_over_a": [round(e, 8) for e in step_error],
        "t": [round(t, 9) for t, _ in frames],
        "x": [[[round(float(v), 7) for v in p] for p in to_slither(x, k)] for _, x in frames],
    }
    with open(args.out, "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")
    print(f"{args.out}: {len(frames)} frames, |change of the angular momentum| at 1 s "
          f"{np.linalg.norm(ang):.3e} (motion scale {scale:.3e}), rms distance to dt/2 at "
          f"1 s {step_error[-1]:.2e} a, {os.path.getsize(args.out)} bytes")
    assert math.isclose(frames[-1][0], DURATION, abs_tol=1e-9), frames[-1][0]


if __name__ == "__main__":
    main()
