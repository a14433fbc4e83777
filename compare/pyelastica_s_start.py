#!/usr/bin/env python3
"""PyElastica's own S-start scene, for the back-to-back timing against slither.

The scene is PyElastica's recorded S-start reference run "sstart_forward_n50":
W = 300, G = 15, sigma = 0.04 L, couple centres 0.2/0.3/0.4 L from the head, v_m = 0.25 m/s,
kinetic friction forward : backward : sideways = 0.22 : 0.28 : 0.40, penalty ground (1 % of the
radius under self-weight, half-critical damping), rod damping 0.02, run for T = L / v_m.

Usage:  pyelastica_s_start.py [--dt 2e-5] [--elements 50] [--out result.json]
                              [--damping legacy|uniform] [--duration S] [--no-warmup]

Rod damping: "legacy" (default) is AnalyticalLinearDamper(damping_constant=0.02), PyElastica's
original protocol (velocities damped at 0.02 /s, angular velocities at 0.02 m_e / J_e per
second); it reproduces the recorded reference. "uniform" (uniform_damping_constant=0.02, both at
0.02 /s) leaves the twist and bending rates undamped and this scene blows up (NaN) with it.

Only the time stepping is timed: the scene is built, then (unless --no-warmup) a throw-away
copy of it runs a few hundred steps first so numba's first-call compilation is not counted.
Writes a JSON with the wall time, dt, steps, v_s/v_m and max height / a.
"""

import argparse
import importlib.metadata
import json
import math
import time

import numba
import numpy as np

import elastica as ea


# ---------------------------------------------------------------- parameters (all SI)
L = 1.0  # body length
A_DIAM = 0.02  # diameter a
RADIUS = 0.5 * A_DIAM
RHO = 1000.0
GRAV = 9.81
W = 300.0  # scaled weight rho g a^2 L^3 / B
TAU = 15.0  # scaled torque Gamma a^3 L / B
SIGMA = 0.04 * L
CENTRES = (0.2 * L, 0.3 * L, 0.4 * L)  # a, b, c, measured from the head
OUT_RATIO = 1.0  # out-of-plane couple at b relative to the in-plane ones
V_M = 0.25  # muscle pulse speed (m/s), T = L / v_m
RAMP = 0.05  # linear ramp over RAMP * T
MU_SIDE = 0.40
MU_FBS = (0.55 * MU_SIDE, 0.70 * MU_SIDE, MU_SIDE)  # 0.22 : 0.28 : 0.40
SS_FACTOR = 10.0  # stretch and shear stiffness over the physical value
DAMPING = 0.02
PENETRATION = 0.01  # ground spring: sinks this fraction of the radius under self-weight

AREA = math.pi * RADIUS**2
INERTIA = math.pi * RADIUS**4 / 4.0
B = RHO * GRAV * A_DIAM**2 * L**3 / W  # 0.01308 N m^2
E_MOD = B / INERTIA
G_MOD = E_MOD / 3.0  # Poisson ratio 0.5
GAMMA_A3 = TAU * B / L  # couple magnitude Gamma a^3 = 0.1962 N m
T_PULSE = L / V_M


@numba.njit(cache=True)
def _add_muscle_couples(torques, s, t):
    """Add the three travelling Gaussian couples at time t to the element torques."""
    ramp = min(max(t / (RAMP * T_PULSE), 0.0), 1.0)
    shift = V_M * t
    inv2s2 = 1.0 / (2.0 * SIGMA * SIGMA)
    for j in range(s.shape[0]):
        ga = math.exp(-((s[j] - CENTRES[0] - shift) ** 2) * inv2s2)
        gb = math.exp(-((s[j] - CENTRES[1] - shift) ** 2) * inv2s2)
        gc = math.exp(-((s[j] - CENTRES[2] - shift) ** 2) * inv2s2)
        m_in = GAMMA_A3 * ramp * (ga - gc)  # about d1 (up): a (+), c (-)
        m_out = OUT_RATIO * GAMMA_A3 * ramp * gb  # about d2 (horizontal): b
        # internal moment at node j + 1: -m on element j (tail side), +m on element j + 1
        torques[0, j] -= m_in
        torques[0, j + 1] += m_in
        torques[1, j] -= m_out
        torques[1, j + 1] += m_out


class SStartMuscles(ea.NoForces):
    """Three Gaussian couples travelling head to tail at v_m, each an internal moment.

    Interior node j (between elements j-1 and j; node 0 is the tail, node n the head) sits at
    arc length s = L - j dx from the head. The couple m there enters like a rest curvature:
    PyElastica's bending torque on element i is M[i] - M[i-1] over the Voronoi moments
    M = B (kappa - kappa0), so adding -m on the tail-side element and +m on the head-side one
    gives B kappa = m at rest. Components are in the material frame: d1 is up (a couple about
    d1 turns the body in the ground plane), d2 = d3 x d1 is horizontal, d3 runs tail to head.
    A positive couple about d2 at b gives kappa_2 > 0: the body is concave up about b, the
    middle presses down and the parts toward a and c rise, as the reference README describes.
    With a (+) and c (-) about d1 the body drifts toward -z (the reference's lateral sign).
    """

    def __init__(self, n_elem):
        super().__init__()
        dx = L / n_elem
        self.s = L - dx * np.arange(1, n_elem)  # arc length from the head, interior nodes

    def apply_torques(self, system, time=np.float64(0.0)):
        _add_muscle_couples(system.external_torques, self.s, float(time))


class Recorder(ea.CallBackBaseClass):
    """Every `every` steps: centre of mass, ground-projected tail-to-head direction, heights."""

    def __init__(self, every, store):
        super().__init__()
        self.every = every
        self.store = store

    def make_callback(self, system, time, current_step):
        if current_step % self.every:
            return
        x = system.position_collection
        com = system.compute_position_center_of_mass()
        chord = x[:, -1] - x[:, 0]
        chord[1] = 0.0  # PyElastica's y axis is up: project on the ground
        self.store["t"].append(float(time))
        self.store["com"].append(com.copy())
        self.store["dir"].append(chord / (np.linalg.norm(chord) + 1e-300))
        h = x[1] - RADIUS
        self.store["hmax"].append(float(h.max()))
        self.store["hmin"].append(float(h.min()))


class Scene(
    ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping, ea.Contact, ea.CallBacks
):
    pass


def build(n_elem, dt, damping, record_every=None):
    sim = Scene()
    rod = ea.CosseratRod.straight_rod(
        n_elem,
        np.array([0.0, RADIUS, 0.0]),  # tail resting on the ground
        np.array([1.0, 0.0, 0.0]),  # tail to head along +x
        np.array([0.0, 1.0, 0.0]),  # d1 up
        L,
        RADIUS,
        RHO,
        youngs_modulus=E_MOD,
        shear_modulus=G_MOD,
    )
    # near-inextensible: stretch and shear stiffness SS_FACTOR x physical (no shear factor)
    rod.shear_matrix[0, 0, :] = SS_FACTOR * G_MOD * AREA
    rod.shear_matrix[1, 1, :] = SS_FACTOR * G_MOD * AREA
    rod.shear_matrix[2, 2, :] = SS_FACTOR * E_MOD * AREA
    sim.append(rod)

    ground = ea.Plane(plane_origin=np.zeros(3), plane_normal=np.array([0.0, 1.0, 0.0]))
    sim.append(ground)

    sim.add_forcing_to(rod).using(
        ea.GravityForces, acc_gravity=np.array([0.0, -GRAV, 0.0])
    )
    sim.add_forcing_to(rod).using(SStartMuscles, n_elem=n_elem)

    mass = RHO * AREA * L
    m_elem = mass / n_elem
    k = m_elem * GRAV / (PENETRATION * RADIUS)  # per element
    nu = 0.5 * 2.0 * math.sqrt(k * m_elem)  # half of critical
    sim.detect_contact_between(rod, ground).using(
        ea.RodPlaneContactWithAnisotropicFriction,
        k=k,
        nu=nu,
        slip_velocity_tol=1e-4,
        static_mu_array=np.zeros(3),  # kinetic friction only
        kinetic_mu_array=np.array(MU_FBS),
    )

    if damping == "uniform":
        sim.dampen(rod).using(
            ea.AnalyticalLinearDamper, uniform_damping_constant=DAMPING, time_step=dt
        )
    else:  # PyElastica's pre-0.4 protocol (rotations damped by m_e / J times the constant)
        sim.dampen(rod).using(ea.AnalyticalLinearDamper, damping_constant=DAMPING, time_step=dt)

    store = {"t": [], "com": [], "dir": [], "hmax": [], "hmin": []}
    if record_every:
        sim.collect_diagnostics(rod).using(Recorder, every=record_every, store=store)
    sim.finalize()
    return sim, rod, store, (k, nu)


def step(sim, n_steps, dt):
    stepper = ea.PositionVerlet()
    t = np.float64(0.0)
    dt = np.float64(dt)
    for _ in range(n_steps):
        t = stepper.step(sim, t, dt)
    return t


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dt", type=float, default=2e-5)
    ap.add_argument("--elements", type=int, default=50)
    ap.add_argument("--out", default=None)
    ap.add_argument("--damping", choices=["legacy", "uniform"], default="legacy")
    ap.add_argument("--duration", type=float, default=T_PULSE)
    ap.add_argument("--no-warmup", action="store_true")
    args = ap.parse_args()

    n_steps = int(round(args.duration / args.dt))
    record_every = max(1, int(round(1e-3 / args.dt)))

    compile_s = 0.0
    if not args.no_warmup:
        w0 = time.perf_counter()
        warm, _, _, _ = build(args.elements, args.dt, args.damping, record_every)
        step(warm, 2 * record_every, args.dt)
        compile_s = time.perf_counter() - w0

    sim, rod, rec, (k, nu) = build(args.elements, args.dt, args.damping, record_every)
    w0 = time.perf_counter()
    t_end = step(sim, n_steps, args.dt)
    wall = time.perf_counter() - w0

    t = np.array(rec["t"])
    com = np.array(rec["com"])
    d = np.array(rec["dir"])
    # v_s: centre-of-mass velocity along the instantaneous ground-projected tail-to-head
    # direction, averaged over the run (midpoint directions on the recorded intervals)
    dmid = 0.5 * (d[1:] + d[:-1])
    dmid /= np.linalg.norm(dmid, axis=1)[:, None]
    dcom = np.diff(com, axis=0)
    v_s = float(np.sum(np.einsum("ij,ij->i", dcom, dmid)) / (t[-1] - t[0]))
    # Stable: finite, and the body never rises above 50 diameters (the S-start lifts its arcs
    # by about 7 a; an explicit step above the stability limit flings the rod thousands of
    # diameters up while its positions stay finite).
    stable = bool(np.all(np.isfinite(rod.position_collection))) and max(rec["hmax"]) < 50 * A_DIAM
    disp = com[-1] - com[0]
    head0 = d[0]
    result = {
        "code": "PyElastica " + importlib.metadata.version("pyelastica"),
        "dt": args.dt,
        "elements": args.elements,
        "steps": n_steps,
        "t_reached": float(t_end),
        "simulated_s": float(t_end),
        "wall_time_s": wall,
        "wall_per_sim_second": wall / float(t_end),
        "us_per_step": 1e6 * wall / n_steps,
        "warmup_and_compile_s": compile_s,
        "stable": stable,
        "v_s_over_v_m": v_s / V_M,
        "com_disp_over_T_along_initial_head_over_v_m": float(disp @ head0) / float(t_end) / V_M,
        "com_disp": disp.tolist(),
        "max_height_over_a": max(rec["hmax"]) / A_DIAM,
        "min_height_m": min(rec["hmin"]),
        "final_head_dir": d[-1].tolist(),
        "settings": {
            "B": B, "E": E_MOD, "G": G_MOD, "Gamma_a3": GAMMA_A3, "contact_k": k,
            "contact_nu": nu, "damping": args.damping, "damping_constant": DAMPING,
            "slip_velocity_tol": 1e-4, "static_mu": [0.0, 0.0, 0.0],
            "kinetic_mu_fbs": list(MU_FBS), "record_every_steps": record_every,
        },
    }
    text = json.dumps(result, indent=1)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
