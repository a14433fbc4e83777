//! The immutable [`Model`]: geometry, masses, stiffnesses, boundary conditions and settings,
//! compiled once from a validated [`Problem`].
//!
//! A clamped end is modelled by one extra *ghost* edge beyond the clamped end node, whose two
//! nodes and twist angle are fixed: the clamp holds the end node's position and the end's
//! material frame, and the bending/twist stencil at the end node carries the clamp moment.
//! The end node's Voronoi length is halved (only the half cell outside the clamp bends), which
//! places the clamp exactly at the rod's end (s = 0 or s = L): the discrete cantilever has its
//! whole length and converges at second order.

mod gait;

pub use gait::Gait;

use crate::problem::{Clamp, Mode, Problem, Shape};
use crate::rod::{dof, frames, vec3::f};
use std::f64::consts::PI;
use std::ops::Range;

/// Ground parameters: kinetic Coulomb coefficients of the anisotropic friction (MODEL 3).
/// The friction law of every ground contact ([`crate::contact::Contact::law`]).
#[derive(Clone, Copy, Debug)]
pub struct Ground {
    /// Kinetic coefficient against forward sliding.
    pub mu_f: f64,
    /// Against backward sliding.
    pub mu_b: f64,
    /// Against sideways sliding.
    pub mu_s: f64,
}

impl Ground {
    /// The friction law's coefficient for a slip (or a friction force, in the dissipation's
    /// convention) with forward component `forward`: `mu_f` when it is forward (`> 0`),
    /// `mu_b` otherwise. The one place that decides it (MODEL 3).
    #[inline]
    pub fn mu_along(&self, forward: f64) -> f64 {
        if forward > 0.0 {
            self.mu_f
        } else {
            self.mu_b
        }
    }

    /// A slip `s` in `(forward, side)` components scaled by the law, `(mu(s_f) s_f, mu_s
    /// s_s)`: the friction dissipation per unit normal force is its length.
    #[inline]
    pub fn scaled_slip(&self, s: [f64; 2]) -> [f64; 2] {
        [self.mu_along(s[0]) * s[0], self.mu_s * s[1]]
    }

    /// A friction force `G` in `(forward, side)` components scaled by the law, `(G_f /
    /// mu(G_f), G_s / mu_s)`: inside the friction set exactly when its length is at most the
    /// normal force.
    #[inline]
    pub fn scaled_force(&self, g: [f64; 2]) -> [f64; 2] {
        [g[0] / self.mu_along(g[0]), g[1] / self.mu_s]
    }
}

/// Everything that does not change during a run.
#[derive(Clone, Debug)]
pub struct Model {
    /// Number of nodes in the internal rod (real nodes plus a ghost node at a clamped end).
    pub nodes: usize,
    /// Internal indices of the real nodes (node `real.start` is the head, s = 0).
    pub real: Range<usize>,
    /// Number of generalised coordinates.
    pub ndof: usize,
    /// Rod length `L` (m).
    pub length: f64,
    /// Diameter `a` (m).
    pub diameter: f64,
    /// Density `rho` (kg/m^3).
    pub density: f64,
    /// Bending rigidity `B` (N m^2).
    pub bend: f64,
    /// Twist rigidity `C` (N m^2).
    pub twist: f64,
    /// Stretching rigidity `EA` (N).
    pub stretch: f64,
    /// Kelvin-Voigt damping time `tau` (s): viscous stresses `tau` times the elastic
    /// stiffness times the strain rate; 0: none.
    pub damping_time: f64,
    /// Rest length of each internal edge (m).
    pub rest_len: Vec<f64>,
    /// Voronoi length of each internal node (m; 0 at the two internal ends).
    pub voronoi: Vec<f64>,
    /// Mass (kg) or twist inertia (kg m^2) of each coordinate.
    pub mass: Vec<f64>,
    /// Coordinates held fixed (clamp).
    pub fixed: Vec<bool>,
    /// Gravity vector (m/s^2).
    pub gravity: [f64; 3],
    /// Natural curvature density `[about d1, about d2]` (1/m).
    pub natural_curvature: [f64; 2],
    /// Natural twist density (rad/m).
    pub natural_twist: f64,
    /// Integration mode.
    pub mode: Mode,
    /// Time step (s); static mode: unused.
    pub dt: f64,
    /// Duration (s); static mode: unused.
    pub duration: f64,
    /// Error-controlled steps (`[time] adaptive = true`), else `None` (fixed steps of `dt`).
    pub adaptive: Option<crate::problem::Adaptive>,
    /// Output interval (s).
    pub output_interval: f64,
    /// Static load increments.
    pub load_steps: usize,
    /// Newton tolerance (relative to `a` for positions, rad for angles).
    pub tolerance: f64,
    /// Newton iteration cap per step.
    pub max_iterations: usize,
    /// Step halvings allowed before the run stops.
    pub max_halvings: usize,
    /// All solver settings (`[solver]`), for the Newton and contact solvers.
    pub solver: crate::problem::SolverSpec,
    /// Initial coordinates.
    pub q0: Vec<f64>,
    /// Initial velocities.
    pub v0: Vec<f64>,
    /// Initial reference director `a1` of every internal edge.
    pub a1_0: Vec<[f64; 3]>,
    /// Clamp.
    pub clamp: Clamp,
    /// Ground contact and friction, if any.
    pub ground: Option<Ground>,
    /// Muscle activation.
    pub gait: Gait,
    /// Self-contact, if on.
    pub self_contact: Option<SelfContactParams>,
}

/// Self-contact parameters ([`crate::energy::self_contact`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SelfContactParams {
    /// Activation gap over `a`.
    pub activation: f64,
    /// Barrier stiffness `kappa g_hat` over `B / a^2`.
    pub stiffness: f64,
}

/// A node carries contact when its normal force exceeds this fraction of its share of the
/// weight, `m_total g / N` (a millionth: well above the conic solver's interior-point residue,
/// far below any supporting force). One test for every slip statistic, the kymographs and the
/// run loop.
pub const CONTACT_FRACTION: f64 = 1e-6;

/// Dimensionless groups of a model (MODEL.md section 6).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Dimensionless {
    /// Scaled weight `W = rho g a^2 L^3 / B`.
    pub scaled_weight: f64,
    /// Aspect ratio `L / a`.
    pub aspect_ratio: f64,
}

/// The initial coil (`[initial] shape = "coil"`): a helix of radius `rad` and pitch `pitch`
/// from the tail (bottom, at height `z`) up to the head, its nodes at equal angles `dphi`
/// apart, chosen so that every edge (a chord) has the rest length `l0`, written into the
/// positions `q0` and `xs` and the reference directors `a1_0` (with the twist angles that make
/// the coil's curvature lie about `d2`).
fn place_coil(
    rad: f64,
    pitch: f64,
    l0: f64,
    z: f64,
    q0: &mut [f64],
    xs: &mut [[f64; 3]],
    a1_0: &mut [[f64; 3]],
) {
    // A helix from the tail (bottom) up to the head, its nodes at equal angles `dphi`
    // apart, chosen so that every edge (a chord) has the rest length `l0`:
    // 2 R^2 (1 - cos dphi) + (p dphi / 2 pi)^2 = l0^2, by Newton's method from the
    // arc's angle (the chord of an arc of `l0` is shorter by about `(l0 k)^2 / 24`).
    let b = pitch / (2.0 * PI);
    let mut dphi = l0 / rad.hypot(b);
    for _ in 0..50 {
        let f = 2.0 * rad * rad * (1.0 - dphi.cos()) + (b * dphi).powi(2) - l0 * l0;
        let df = 2.0 * rad * rad * dphi.sin() + 2.0 * b * b * dphi;
        let step = f / df;
        dphi -= step;
        if step.abs() <= 1e-15 * dphi {
            break;
        }
    }
    for i in 0..xs.len() {
        let k = (xs.len() - 1 - i) as f64;
        let phi = k * dphi;
        let x = [rad * phi.cos(), rad * phi.sin(), z + b * phi];
        q0[dof::node(i)..dof::node(i) + 3].copy_from_slice(&x);
        xs[i] = x;
    }
    // Reference directors transported along the edges from the head's (no twist).
    let tangent = |j: usize| f::unit(f::sub(xs[j + 1], xs[j]));
    a1_0[0] = frames::initial_director(tangent(0));
    for j in 1..xs.len() - 1 {
        a1_0[j] = f::unit(f::transport(tangent(j - 1), tangent(j), a1_0[j - 1]));
    }
    // The material frame with d1 horizontal (d2 along the helix's binormal, near
    // vertical): twist angles from the transported directors, so that the coil's own
    // curvature lies about d2 all along (natural curvature [0, -k] and natural twist
    // t, with k and t the helix's curvature and torsion, make it stress-free).
    for j in 0..xs.len() - 1 {
        let t = tangent(j);
        let d1 = frames::initial_director(t);
        let a2 = f::cross(t, a1_0[j]);
        q0[dof::edge(j)] = f::dot(a2, d1).atan2(f::dot(a1_0[j], d1));
    }
}

/// The initial velocity (`[initial] velocity`, `angular_velocity`): uniform plus the rigid
/// rotation about the centroid of the real nodes (`xs` the node positions, `t` the tangent),
/// zero on fixed coordinates.
fn initial_velocity(
    p: &Problem,
    xs: &[[f64; 3]],
    real: &std::ops::Range<usize>,
    fixed: &[bool],
    t: [f64; 3],
) -> Vec<f64> {
    let centroid = {
        let mut c = [0.0; 3];
        for i in real.clone() {
            c = f::add(c, xs[i]);
        }
        f::scale(c, 1.0 / real.len() as f64)
    };
    let w = p.initial.angular_velocity;
    let mut v0 = vec![0.0; fixed.len()];
    for i in 0..xs.len() {
        let v = f::add(p.initial.velocity, f::cross(w, f::sub(xs[i], centroid)));
        for c in 0..3 {
            if !fixed[dof::node(i) + c] {
                v0[dof::node(i) + c] = v[c];
            }
        }
    }
    for j in 0..xs.len() - 1 {
        if !fixed[dof::edge(j)] {
            v0[dof::edge(j)] = f::dot(w, t);
        }
    }
    v0
}

impl Model {
    /// Compile a validated problem.
    pub fn new(p: &Problem) -> Self {
        let r = &p.rod;
        let n = r.elements;
        let l0 = r.length / n as f64;
        let (nodes, real) = match r.clamp {
            Clamp::None => (n + 1, 0..n + 1),
            Clamp::Head => (n + 2, 1..n + 2),
            Clamp::Tail => (n + 2, 0..n + 1),
        };
        let ndof = dof::count(nodes);
        let a = r.diameter;
        let area = PI * a * a / 4.0;
        let polar = PI * a.powi(4) / 32.0;
        let rest_len = vec![l0; nodes - 1];
        let mut voronoi = vec![0.0; nodes];
        for i in 1..nodes - 1 {
            voronoi[i] = 0.5 * (rest_len[i - 1] + rest_len[i]);
        }
        // The clamped end node's Voronoi cell lies half inside the clamp: only the half outside
        // bends (the ghost edge is the clamp, not rod material). This keeps the clamp at s = 0
        // or s = L exactly (second-order convergence of the cantilever).
        match r.clamp {
            Clamp::None => {}
            Clamp::Head => voronoi[1] = 0.5 * l0,
            Clamp::Tail => voronoi[nodes - 2] = 0.5 * l0,
        }
        let mut mass = vec![0.0; ndof];
        for (k, i) in real.clone().enumerate() {
            let lv = if k == 0 || k == n { 0.5 * l0 } else { l0 };
            for c in 0..3 {
                mass[dof::node(i) + c] = r.density * area * lv;
            }
        }
        for j in 0..nodes - 1 {
            mass[dof::edge(j)] = r.density * polar * rest_len[j];
        }
        let mut fixed = vec![false; ndof];
        let fix_node = |i: usize, fixed: &mut Vec<bool>| {
            for c in 0..3 {
                fixed[dof::node(i) + c] = true;
            }
        };
        match r.clamp {
            Clamp::None => {}
            Clamp::Head => {
                fix_node(0, &mut fixed);
                fix_node(1, &mut fixed);
                fixed[dof::edge(0)] = true;
            }
            Clamp::Tail => {
                fix_node(nodes - 1, &mut fixed);
                fix_node(nodes - 2, &mut fixed);
                fixed[dof::edge(nodes - 2)] = true;
            }
        }
        // Initial straight rod: head (s = 0) at x = L, tail at the origin, rotated by heading.
        let phi = p.initial.heading_deg.to_radians();
        let hdir = [phi.cos(), phi.sin(), 0.0];
        let z = 0.5 * a + p.initial.height;
        let first_s = if r.clamp == Clamp::Head { -l0 } else { 0.0 };
        let mut q0 = vec![0.0; ndof];
        let mut xs = Vec::with_capacity(nodes);
        for i in 0..nodes {
            let s = first_s + i as f64 * l0;
            let x = [(r.length - s) * hdir[0], (r.length - s) * hdir[1], z];
            q0[dof::node(i)..dof::node(i) + 3].copy_from_slice(&x);
            xs.push(x);
        }
        let t = f::scale(hdir, -1.0);
        let a1 = frames::initial_director(t);
        let mut a1_0 = vec![a1; nodes - 1];
        if p.initial.shape == Shape::Coil {
            let (rad, pitch) = (p.initial.coil_radius, p.initial.coil_pitch);
            place_coil(rad, pitch, l0, z, &mut q0, &mut xs, &mut a1_0);
        }
        let v0 = initial_velocity(p, &xs, &real, &fixed, t);
        let (dt, duration) = match p.time.mode {
            Mode::Dynamic => (p.time.dt.unwrap_or(1e-3), p.time.duration.unwrap_or(1.0)),
            Mode::Static => (p.time.dt.unwrap_or(1.0), p.time.duration.unwrap_or(0.0)),
        };
        let max_iterations = match p.time.mode {
            Mode::Dynamic => p.solver.max_iterations,
            Mode::Static => 10 * p.solver.max_iterations,
        };
        Model {
            nodes,
            real,
            ndof,
            length: r.length,
            diameter: a,
            density: r.density,
            bend: r.bending_stiffness,
            twist: r.twist_stiffness.unwrap_or(2.0 * r.bending_stiffness / 3.0),
            stretch: r
                .stretch_stiffness
                .unwrap_or(16.0 * r.bending_stiffness / (a * a)),
            damping_time: r.damping_time,
            rest_len,
            voronoi,
            mass,
            fixed,
            gravity: {
                let beta = p
                    .ground
                    .as_ref()
                    .map_or(0.0, |g| g.incline_deg.to_radians());
                [-p.gravity.g * beta.sin(), 0.0, -p.gravity.g * beta.cos()]
            },
            natural_curvature: r.natural_curvature,
            natural_twist: r.natural_twist,
            mode: p.time.mode,
            dt,
            duration,
            adaptive: crate::problem::Adaptive::of(p),
            output_interval: p.output.interval_for(duration).max(0.0),
            load_steps: p.time.load_steps,
            tolerance: p.solver.tolerance,
            max_iterations,
            max_halvings: p.solver.max_halvings,
            solver: p.solver.effective(),
            q0,
            v0,
            a1_0,
            clamp: r.clamp,
            ground: p.ground.as_ref().map(|g| Ground {
                mu_f: g.mu_forward,
                mu_b: g.mu_backward,
                mu_s: g.mu_sideways,
            }),
            gait: Gait::new(&p.gait, r.length, a),
            self_contact: p.self_contact.enabled.then_some(SelfContactParams {
                activation: p.self_contact.activation,
                stiffness: p.self_contact.stiffness,
            }),
        }
    }

    /// Line density `rho A` (kg/m).
    pub fn line_density(&self) -> f64 {
        self.density * PI * self.diameter * self.diameter / 4.0
    }

    /// Total mass of the real rod (kg).
    pub fn total_mass(&self) -> f64 {
        self.line_density() * self.length
    }

    /// Number of real elements.
    pub fn elements(&self) -> usize {
        self.real.len() - 1
    }

    /// Internal edge indices of the real edges.
    pub fn real_edges(&self) -> Range<usize> {
        self.real.start..self.real.end - 1
    }

    /// Arc length of internal node `i` from the head (m).
    pub fn arc_length(&self, i: usize) -> f64 {
        (i as f64 - self.real.start as f64) * self.length / self.elements() as f64
    }

    /// The normal force (N) above which a node counts as in contact ([`CONTACT_FRACTION`] of
    /// its share of the weight; 0 without gravity).
    pub fn contact_threshold(&self) -> f64 {
        CONTACT_FRACTION * self.total_mass() * f::norm(self.gravity) / self.elements() as f64
    }

    /// Whether a node with normal force `normal` (N) is in contact.
    pub fn in_contact(&self, normal: f64) -> bool {
        normal > self.contact_threshold()
    }

    /// Whether node `i` lies on the ground in `q`: its centre within `[solver]
    /// contact_tolerance` (times `a`) of its resting height. False without a ground.
    pub fn on_ground(&self, q: &[f64], i: usize) -> bool {
        self.ground.is_some()
            && q[dof::node(i) + 2] - 0.5 * self.diameter
                <= self.solver.contact_tolerance * self.diameter
    }

    /// Dimensionless groups.
    pub fn dimensionless(&self) -> Dimensionless {
        let g = f::norm(self.gravity);
        Dimensionless {
            scaled_weight: self.density * g * self.diameter.powi(2) * self.length.powi(3)
                / self.bend,
            aspect_ratio: self.length / self.diameter,
        }
    }
}
