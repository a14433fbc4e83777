#!/usr/bin/env python3
"""PyElastica's own S-start scene, for the side-by-side comparison with slither.

The scene is PyElastica's recorded S-start reference run "sstart_forward_n50":
W = 300, G = 15, sigma = 0.04 L, couple centres 0.2/0.3/0.4 L from the head, v_m = 0.25 m/s,
kinetic friction forward : backward : sideways = 0.22 : 0.28 : 0.40, penalty ground (1 % of the
radius under self-weight, half-critical damping), rod damping 0.02, run for T = L / v_m.

Usage:  pyelastica_s_start.py [--dt 2e-5] [--elements 50] [--out result.json]
                              [--muscles curvature|torque] [--free] [--spin W]
                              [--damping legacy|uniform|none] [--duration S] [--no-warmup]
                              [--ground-stiffness X] [--static-friction]

Muscles (--muscles):
  "curvature" (default): the paper's internal moment M = B kappa + m. Before each step the
      rod's rest curvature is set from the couples, rest_kappa = m / B at the time the step
      evaluates its internal forces (the step's midpoint, PositionVerlet), so the couple enters
      PyElastica's internal moment together with its kappa x m term.
  "torque": the former form, kept for the record: -m on the tail-side element and +m on the
      head-side one, each in its own material frame. Once the two frames differ the pair leaves
      a net torque, and the kappa x m term of the moment balance is missing: a free rod gains
      angular momentum (see --free).

--free: no gravity, no ground, no damping (the free rod of the fixtures in tests/fixtures/);
  the run prints the total angular momentum, translational sum m_i x_i x v_i plus the elements'
  spin Q^T (J omega), which starts at 0 and is conserved by an internal moment.
--spin W: an initial spin W (rad/s) of the straight rod about its own axis (free rod only).

Forward speed: "v_s_over_v_m" is slither's definition, the centroid's displacement along the
initial ground-projected tail-to-head direction over the run time, over v_m. The
instantaneous-head form (the centroid velocity projected on the current head direction,
averaged) is printed beside it as "v_head_instantaneous_over_v_m".

Rod damping: "legacy" (default) is AnalyticalLinearDamper(damping_constant=0.02), PyElastica's
original protocol (velocities damped at 0.02 /s, angular velocities at 0.02 m_e / J_e per
second); it reproduces the recorded reference. "uniform" (uniform_damping_constant=0.02, both at
0.02 /s) leaves the twist and bending rates undamped and this scene blows up (NaN) with it.
"none": no rod damping.

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
def _muscle_moments(out, s, t, centres, scales, gamma_a3, ramp_time, v_m, sigma):
    """The muscle couples at time t at the interior nodes (arc lengths s from the head).

    out[0, k]: in-plane couple, about d1 (up): scales[0] at a (+), scales[2] at c (-).
    out[1, k]: out-of-plane couple, about d2 (horizontal): scales[1] at b (+, presses the
    middle down).
    """
    ramp = min(max(t / ramp_time, 0.0), 1.0) if ramp_time > 0.0 else 1.0
    shift = v_m * t
    inv2s2 = 1.0 / (2.0 * sigma * sigma)
    for k in range(s.shape[0]):
        ga = math.exp(-((s[k] - centres[0] - shift) ** 2) * inv2s2)
        gb = math.exp(-((s[k] - centres[1] - shift) ** 2) * inv2s2)
        gc = math.exp(-((s[k] - centres[2] - shift) ** 2) * inv2s2)
        out[0, k] = gamma_a3 * ramp * (scales[0] * ga - scales[2] * gc)
        out[1, k] = gamma_a3 * ramp * scales[1] * gb


@numba.njit(cache=True)
def _add_element_torques(torques, m):
    """The element-torque form: -m on element k (tail side of interior node k + 1), +m on
    element k + 1, each in its own material frame."""
    for k in range(m.shape[1]):
        torques[0, k] -= m[0, k]
        torques[0, k + 1] += m[0, k]
        torques[1, k] -= m[1, k]
        torques[1, k + 1] += m[1, k]


class Gait:
    """The three travelling Gaussian couples (all SI); `scales` as slither's `gait.scales`."""

    def __init__(self, n_elem, gamma_a3=None, centres=CENTRES, scales=(1.0, OUT_RATIO, 1.0),
                 sigma=SIGMA, v_m=V_M, ramp=RAMP):
        dx = L / n_elem
        # Interior node k + 1 (node 0 is the tail, node n the head) sits at s = L - (k + 1) dx
        # from the head.
        self.s = L - dx * np.arange(1, n_elem)
        self.gamma_a3 = GAMMA_A3 if gamma_a3 is None else gamma_a3
        self.centres = np.array(centres, dtype=np.float64)
        self.scales = np.array(scales, dtype=np.float64)
        self.sigma = sigma
        self.v_m = v_m
        self.ramp_time = ramp * L / v_m
        self.m = np.zeros((2, n_elem - 1))

    def moments(self, t):
        _muscle_moments(self.m, self.s, float(t), self.centres, self.scales, self.gamma_a3,
                        self.ramp_time, self.v_m, self.sigma)
        return self.m


class CurvatureMuscles:
    """Muscles as a time-dependent rest curvature: before each step, rest_kappa[0:2] = m / B.

    PyElastica's internal couple at an interior node is B (kappa - rest_kappa) (material
    frame, per unit length); with rest_kappa = m / B it is B kappa - m, the paper's internal
    moment with the muscle couple inside it, so the kappa x m term of the moment balance comes
    with it. The sign matches the element-torque form below (which adds -m to the tail-side
    element and +m to the head-side one, i.e. subtracts m from the internal couple): at rest
    both give B kappa = m, so a positive couple about d2 at b curves the body concave up (the
    middle presses down, the parts toward a and c rise; the run prints this check).
    """

    def __init__(self, gait, rod):
        self.gait = gait
        self.rod = rod
        self.inv_b = 1.0 / rod.bend_matrix[0, 0, :]  # B at each Voronoi node (uniform rod)

    def set(self, t):
        m = self.gait.moments(t)
        self.rod.rest_kappa[0, :] = m[0] * self.inv_b
        self.rod.rest_kappa[1, :] = m[1] * self.inv_b


class TorqueMuscles(ea.NoForces):
    """The element-torque form, kept for the record (--muscles torque): not an internal moment
    once the body curves (module doc)."""

    def __init__(self, gait):
        super().__init__()
        self.gait = gait

    def apply_torques(self, system, time=np.float64(0.0)):
        _add_element_torques(system.external_torques, self.gait.moments(float(time)))


def angular_momentum(rod):
    """Total angular momentum about the origin: sum m_i x_i x v_i over the nodes plus
    sum_j Q_j^T (J_j omega_j) over the elements (omega and J in the material frame, the rows
    of Q the directors)."""
    x = rod.position_collection
    v = rod.velocity_collection
    lin = np.sum(rod.mass[None, :] * np.cross(x.T, v.T).T, axis=1)
    jw = np.einsum("ijk,jk->ik", rod.mass_second_moment_of_inertia, rod.omega_collection)
    spin = np.einsum("ijk,ik->j", rod.director_collection, jw)
    # the scale of the motion: sum m |x - x_cm| |v|
    xc = x - (np.sum(rod.mass * x, axis=1) / rod.mass.sum())[:, None]
    scale = float(np.sum(rod.mass * np.linalg.norm(xc, axis=0) * np.linalg.norm(v, axis=0)))
    return lin + spin, scale


class Recorder(ea.CallBackBaseClass):
    """Every `every` steps: centre of mass, ground-projected tail-to-head direction, heights,
    angular momentum; every `frame_every` steps (if set) the node positions."""

    def __init__(self, every, store, frame_every=None):
        super().__init__()
        self.every = every
        self.frame_every = frame_every
        self.store = store

    def make_callback(self, system, time, current_step):
        if self.frame_every and current_step % self.frame_every == 0:
            self.store["frames_t"].append(float(time))
            self.store["frames_x"].append(system.position_collection.copy())
            self.store["frames_v"].append(system.velocity_collection.copy())
            self.store["frames_d2"].append(system.director_collection[1].copy())
        if current_step % self.every:
            return
        record(system, time, self.store)


def record(rod, time, store):
    x = rod.position_collection
    com = rod.compute_position_center_of_mass()
    chord = x[:, -1] - x[:, 0]
    chord[1] = 0.0  # PyElastica's y axis is up: project on the ground
    store["t"].append(float(time))
    store["com"].append(com.copy())
    store["dir"].append(chord / (np.linalg.norm(chord) + 1e-300))
    h = x[1] - RADIUS
    store["hmax"].append(float(h.max()))
    store["hmin"].append(float(h.min()))
    ang, scale = angular_momentum(rod)
    store["ang"].append(ang.copy())
    store["ang_scale"].append(scale)
    if store.get("keep_x") or abs(time - store.get("x_at", -1.0)) < 0.5e-3:
        store["x"].append(x.copy())
        store["x_t"].append(float(time))


class Scene(
    ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping, ea.Contact, ea.CallBacks
):
    pass


def build(n_elem, dt, damping="legacy", record_every=None, muscles="curvature", free=False,
          spin=0.0, gait=None, ground_stiffness=1.0, static_friction=False, frame_every=None,
          twist=0.0):
    """The scene. `free`: no gravity, no ground, no damping. `twist` (rad/m): a natural twist,
    the rod starting at rest in it (material frame turned right-handedly about the tangent at
    `twist` per metre, unturned at the head). Returns (sim, rod, store, info, pre_step),
    pre_step(t) to call with the time of the step's force evaluation."""
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
    if twist:
        # element j (tail first) centred at s_j from the head: d1, d2 turned about d3 by
        # -twist s_j, so that along the rod (tail to head, d3) they turn by +twist per metre
        dx = L / n_elem
        s_head = L - dx * (np.arange(n_elem) + 0.5)
        q = rod.director_collection
        for j in range(n_elem):
            c, sn = math.cos(-twist * s_head[j]), math.sin(-twist * s_head[j])
            d1, d2 = q[0, :, j].copy(), q[1, :, j].copy()
            q[0, :, j] = c * d1 + sn * d2
            q[1, :, j] = -sn * d1 + c * d2
        rod.rest_kappa[2, :] = twist
    sim.append(rod)
    gait = gait or Gait(n_elem)

    info = {}
    if not free:
        ground = ea.Plane(plane_origin=np.zeros(3), plane_normal=np.array([0.0, 1.0, 0.0]))
        sim.append(ground)
        sim.add_forcing_to(rod).using(
            ea.GravityForces, acc_gravity=np.array([0.0, -GRAV, 0.0])
        )
        mass = RHO * AREA * L
        m_elem = mass / n_elem
        k = ground_stiffness * m_elem * GRAV / (PENETRATION * RADIUS)  # per element
        nu = 0.5 * 2.0 * math.sqrt(k * m_elem)  # half of critical
        kinetic = np.array(MU_FBS)
        sim.detect_contact_between(rod, ground).using(
            ea.RodPlaneContactWithAnisotropicFriction,
            k=k,
            nu=nu,
            slip_velocity_tol=1e-4,
            static_mu_array=kinetic.copy() if static_friction else np.zeros(3),
            kinetic_mu_array=kinetic,
        )
        info = {"contact_k": k, "contact_nu": nu}
        if damping == "uniform":
            sim.dampen(rod).using(
                ea.AnalyticalLinearDamper, uniform_damping_constant=DAMPING, time_step=dt
            )
        elif damping == "legacy":  # PyElastica's pre-0.4 protocol (rotations by m_e / J)
            sim.dampen(rod).using(
                ea.AnalyticalLinearDamper, damping_constant=DAMPING, time_step=dt
            )
    if muscles == "torque":
        sim.add_forcing_to(rod).using(TorqueMuscles, gait=gait)

    store = {k: [] for k in ("t", "com", "dir", "hmax", "hmin", "ang", "ang_scale", "x", "x_t",
                             "frames_t", "frames_x", "frames_v", "frames_d2")}
    store["keep_x"] = False
    store["x_at"] = 0.5  # keep the positions near this time (the shape check)
    if record_every:
        sim.collect_diagnostics(rod).using(
            Recorder, every=record_every, store=store, frame_every=frame_every
        )
    sim.finalize()
    if spin:
        rod.omega_collection[2, :] = spin  # about d3 (tail to head), material frame
    # the initial state (finalize may have called the recorder at step 0 before the spin was
    # set: record it again)
    for key in store:
        if isinstance(store[key], list):
            store[key].clear()
    record(rod, 0.0, store)
    if frame_every:
        store["frames_t"].append(0.0)
        store["frames_x"].append(rod.position_collection.copy())
        store["frames_v"].append(rod.velocity_collection.copy())
        store["frames_d2"].append(rod.director_collection[1].copy())
    if muscles == "curvature":
        pre_step = CurvatureMuscles(gait, rod).set
    else:
        pre_step = None
    return sim, rod, store, info, pre_step


def step(sim, n_steps, dt, pre_step=None):
    """n_steps of PositionVerlet; pre_step(t + dt/2) before each (its forces are evaluated
    after the first half drift, at the step's midpoint)."""
    stepper = ea.PositionVerlet()
    t = np.float64(0.0)
    dt = np.float64(dt)
    for _ in range(n_steps):
        if pre_step is not None:
            pre_step(t + 0.5 * dt)
        t = stepper.step(sim, t, dt)
    return t


def shape_check(store, centres=CENTRES, n_elem=None, when=0.5):
    """Sign check by the shape at `when` s: the height (along the initial up axis, y) of the
    node under b minus the mean height of the nodes under a and c, over a. Negative: the middle
    presses down and the parts toward a and c rise."""
    t = np.array(store["x_t"])
    i = int(np.argmin(abs(t - when)))
    x = store["x"][i]
    n = x.shape[1] - 1
    dx = L / n

    def node(s):  # the node at arc length s from the head
        return int(round((L - s) / dx))

    sh = V_M * t[i]
    ya, yb, yc = (x[1, node(c + sh)] for c in centres)
    return float(t[i]), (yb - 0.5 * (ya + yc)) / A_DIAM


SCENES = {
    # PyElastica's two reference scenes (problems/pyelastica_s_start.toml and
    # problems/pyelastica_straight.toml): G, sigma / L, centres / L, scale of the couple at b
    "s-start": (15.0, 0.04, (0.2, 0.3, 0.4), 1.0),
    "straight": (17.5, 0.06, (0.20, 0.35, 0.50), 0.4),
}


def set_scene(scene, w=None, g=None):
    """Rebind the scene's module constants: scene's couples, W (through B, with E, the shear
    modulus and the stretch and shear stiffness scaled alike) and G (through Gamma)."""
    global W, TAU, SIGMA, CENTRES, OUT_RATIO, B, E_MOD, G_MOD, GAMMA_A3
    g0, sigma, centres, out_ratio = SCENES[scene]
    W = 300.0 if w is None else w
    TAU = g0 if g is None else g
    SIGMA = sigma * L
    CENTRES = tuple(c * L for c in centres)
    OUT_RATIO = out_ratio
    B = RHO * GRAV * A_DIAM**2 * L**3 / W
    E_MOD = B / INERTIA
    G_MOD = E_MOD / 3.0
    GAMMA_A3 = TAU * B / L


def write_frames(path, store):
    """The recorded frames in slither's axes and order (head first, z up; slither's d1 is
    PyElastica's d2): t, node positions and velocities, edge directors d1."""
    def axes(v):  # (3, k) PyElastica, tail first -> (k, 3) slither, head first
        v = v[:, ::-1]
        return np.stack([v[0], -v[2], v[1]], axis=1).round(9).tolist()

    with open(path, "w") as f:
        json.dump({"t": store["frames_t"],
                   "x": [axes(x) for x in store["frames_x"]],
                   "v": [axes(v) for v in store["frames_v"]],
                   "d1": [axes(d) for d in store["frames_d2"]],
                   "diameter": A_DIAM}, f, separators=(",", ":"))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", choices=sorted(SCENES), default="s-start")
    ap.add_argument("--W", type=float, default=None, help="scaled weight (default 300)")
    ap.add_argument("--G", type=float, default=None, help="scaled torque (default the scene's)")
    ap.add_argument("--frames-out", default=None,
                    help="write frames (slither's axes) every --frame-interval s to this JSON")
    ap.add_argument("--frame-interval", type=float, default=0.02)
    ap.add_argument("--dt", type=float, default=2e-5)
    ap.add_argument("--elements", type=int, default=50)
    ap.add_argument("--out", default=None)
    ap.add_argument("--muscles", choices=["curvature", "torque"], default="curvature")
    ap.add_argument("--free", action="store_true")
    ap.add_argument("--spin", type=float, default=0.0)
    ap.add_argument("--damping", choices=["legacy", "uniform", "none"], default="legacy")
    ap.add_argument("--ground-stiffness", type=float, default=1.0,
                    help="ground spring stiffness over the scene's (damping kept half-critical)")
    ap.add_argument("--static-friction", action="store_true",
                    help="static friction coefficients equal to the kinetic ones (else 0)")
    ap.add_argument("--duration", type=float, default=T_PULSE)
    ap.add_argument("--no-warmup", action="store_true")
    args = ap.parse_args()
    if args.spin and not args.free:
        ap.error("--spin needs --free")
    set_scene(args.scene, args.W, args.G)
    frame_every = None
    if args.frames_out:
        frame_every = int(round(args.frame_interval / args.dt))
        if abs(frame_every * args.dt - args.frame_interval) > 1e-9 * args.frame_interval:
            ap.error("--frame-interval must be a whole number of steps")

    n_steps = int(round(args.duration / args.dt))
    record_every = max(1, int(round(1e-3 / args.dt)))
    kw = dict(damping=args.damping, muscles=args.muscles, free=args.free, spin=args.spin,
              ground_stiffness=args.ground_stiffness, static_friction=args.static_friction,
              gait=Gait(args.elements, gamma_a3=GAMMA_A3, centres=CENTRES,
                        scales=(1.0, OUT_RATIO, 1.0), sigma=SIGMA))

    compile_s = 0.0
    if not args.no_warmup:
        w0 = time.perf_counter()
        warm, _, _, _, pre = build(args.elements, args.dt, record_every=record_every, **kw)
        step(warm, 2 * record_every, args.dt, pre)
        compile_s = time.perf_counter() - w0

    sim, rod, rec, info, pre = build(args.elements, args.dt, record_every=record_every,
                                     frame_every=frame_every, **kw)
    w0 = time.perf_counter()
    t_end = step(sim, n_steps, args.dt, pre)
    wall = time.perf_counter() - w0

    t = np.array(rec["t"])
    com = np.array(rec["com"])
    d = np.array(rec["dir"])
    # instantaneous-head form: centre-of-mass velocity along the instantaneous ground-projected
    # tail-to-head direction, averaged over the run (midpoint directions on recorded intervals)
    dmid = 0.5 * (d[1:] + d[:-1])
    dmid /= np.linalg.norm(dmid, axis=1)[:, None]
    dcom = np.diff(com, axis=0)
    v_head = float(np.sum(np.einsum("ij,ij->i", dcom, dmid)) / (t[-1] - t[0]))
    # slither's v_s: displacement along the initial tail-to-head direction over the run time
    disp = com[-1] - com[0]
    head0 = d[0]
    v_s = float(disp @ head0) / float(t_end)
    # Stable: finite, and the body never rises above 50 diameters (the S-start lifts its arcs
    # by about 7 a; an explicit step above the stability limit flings the rod thousands of
    # diameters up while its positions stay finite).
    finite = bool(np.all(np.isfinite(rod.position_collection)))
    stable = finite and (args.free or max(rec["hmax"]) < 50 * A_DIAM)
    ang = np.array(rec["ang"])
    result = {
        "code": "PyElastica " + importlib.metadata.version("pyelastica"),
        "muscles": args.muscles,
        "free": args.free,
        "spin": args.spin,
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
        "v_head_instantaneous_over_v_m": v_head / V_M,
        "com_disp": disp.tolist(),
        "com_disp_along_initial_head_m": float(disp @ head0),
        "com_disp_direction_deg": math.degrees(math.atan2(-disp[2], disp[0])),
        "angular_momentum_initial": ang[0].tolist(),
        "angular_momentum_final": ang[-1].tolist(),
        "angular_momentum_change_final_norm": float(np.linalg.norm(ang[-1] - ang[0])),
        "angular_momentum_change_max_norm": float(np.linalg.norm(ang - ang[0], axis=1).max()),
        "motion_scale_sum_m_r_v_max": float(max(rec["ang_scale"])),
        "max_height_over_a": max(rec["hmax"]) / A_DIAM,
        "min_height_m": min(rec["hmin"]),
        "final_head_dir": d[-1].tolist(),
        "settings": {
            "B": B, "E": E_MOD, "G": G_MOD, "Gamma_a3": GAMMA_A3, **info,
            "damping": "none" if args.free else args.damping, "damping_constant": DAMPING,
            "ground_stiffness_factor": args.ground_stiffness,
            "slip_velocity_tol": 1e-4,
            "static_mu": list(MU_FBS) if args.static_friction else [0.0, 0.0, 0.0],
            "kinetic_mu_fbs": list(MU_FBS), "record_every_steps": record_every,
        },
    }
    if args.frames_out:
        write_frames(args.frames_out, rec)
    result["scene"] = {"name": args.scene, "W": W, "G": TAU, "sigma_over_L": SIGMA / L,
                       "centres_over_L": [c / L for c in CENTRES], "scale_b": OUT_RATIO}
    if t_end >= 0.5:
        when, below = shape_check(rec, centres=CENTRES)
        result["shape_check"] = {
            "t": when,
            "b_minus_mean_of_a_c_over_a": below,
            "middle_presses_down": bool(below < 0.0),
        }
    text = json.dumps(result, indent=1)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
