//! The contact set: every contact of a run ([`Contact`]) with its normal force, owned by the
//! dispatcher ([`super::Dispatcher`]) and handed to whichever solver runs the step.
//!
//! The ground's contacts are the real nodes that are not clamped in height, each the
//! one-node stencil of its node, or (`[solver] ground_points = "curve"`) each node's lowest
//! point of the curve through it and its neighbours ([`lowest_point`]), chosen again for every
//! step at its first iterate, and once more at its solution where a node sinks below the
//! ground ([`ContactSet::rechoose`]). Their frames and slip origins are frozen at the start of
//! every step; the normal forces are the current value of the lagged fixed point (the conic
//! program) or the published solution (the semi-smooth Newton).

use super::point::{Contact, Frame, Stencil};
use crate::model::Model;
use crate::problem::GroundPoints;
use crate::rod::{dof, vec3::f};

/// Every contact and its normal force.
pub struct ContactSet {
    /// With `[solver] ground_points = "curve"`: the node whose neighbourhood each contact
    /// searches for its lowest point at every step's start (`None`: the contacts stay put).
    owners: Option<Vec<usize>>,
    /// With owners: put every contact at its owner node instead of its lowest point (the
    /// integrator's fallback for a step that failed on the curve, [`ContactSet::points_at_nodes`]).
    at_nodes: bool,
    /// The contacts.
    pub contacts: Vec<Contact>,
    /// Normal force at each contact (N), the current fixed-point value.
    pub normal: Vec<f64>,
    /// Normal forces from the last conic solve, not yet committed.
    pub pending: Vec<f64>,
    /// The normal forces at the start of the step (restored by a rejected step).
    normal_saved: Vec<f64>,
    /// Each contact's gap at the start of the step (m): negative where the step's point lies
    /// below the ground there.
    start_gap: Vec<f64>,
    /// With contacts on the curve: the step's start and slip origin, from which a point chosen
    /// again at the solution takes its frame and origin ([`ContactSet::rechoose`]).
    step_q: Vec<f64>,
    step_origin: Vec<f64>,
    /// The step's size `h` (s): the conic program scales its slips with it.
    pub h: f64,
}

impl ContactSet {
    /// The ground's contacts of a model at `q`: one at every real node not clamped in height.
    /// Initial normal forces: each node's weight if it touches the ground.
    pub fn ground(m: &Model, q: &[f64]) -> Self {
        let law = *m.ground.as_ref().expect("a contact set needs a ground");
        let g = f::norm(m.gravity);
        let contacts = m
            .real
            .clone()
            .filter(|&i| !m.fixed[dof::node(i) + 2])
            .map(|i| {
                let z = q[dof::node(i) + 2];
                let normal = if z - 0.5 * m.diameter <= 1e-9 * m.diameter {
                    m.mass[dof::node(i)] * g
                } else {
                    0.0
                };
                (Contact::new(Stencil::node(i), law), normal)
            });
        let mut set = Self::new(contacts.collect());
        if m.solver.ground_points == GroundPoints::Curve {
            set.owners = Some(
                m.real
                    .clone()
                    .filter(|&i| !m.fixed[dof::node(i) + 2])
                    .collect(),
            );
        }
        set
    }

    /// A contact set of the given contacts, each with its initial normal force (N).
    pub fn new(contacts: Vec<(Contact, f64)>) -> Self {
        let (contacts, normal): (Vec<Contact>, Vec<f64>) = contacts.into_iter().unzip();
        ContactSet {
            owners: None,
            at_nodes: false,
            contacts,
            pending: normal.clone(),
            normal,
            normal_saved: Vec::new(),
            start_gap: Vec::new(),
            step_q: Vec::new(),
            step_origin: Vec::new(),
            h: 0.0,
        }
    }

    /// Number of contacts.
    pub fn len(&self) -> usize {
        self.contacts.len()
    }

    /// Whether there is no contact.
    pub fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }

    /// The first coordinate (`x`; `y`, `z` follow) of contact `c`'s node, for a solver that
    /// holds a contact's coordinates: only a contact at a node has them
    /// ([`Stencil::single`]; the semi-smooth Newton checks every contact before it starts).
    pub(crate) fn node_dof(&self, c: usize) -> usize {
        let i = self.contacts[c]
            .stencil
            .single()
            .expect("a contact at a node (checked by the solver)");
        dof::node(i)
    }

    /// The first coordinate of the node of contact `c`'s stencil with the largest weight:
    /// whose mass scales the contact's penalties.
    pub(crate) fn pivot_dof(&self, c: usize) -> usize {
        let (mut best, mut weight) = (0, f64::NEG_INFINITY);
        for (i, w) in self.contacts[c].stencil.iter() {
            if w > weight {
                (best, weight) = (i, w);
            }
        }
        dof::node(best)
    }

    /// From the next step on, every contact at its owner node (`true`) or at its lowest point
    /// again (`false`). Returns whether the set has contacts between nodes to move
    /// (`[solver] ground_points = "curve"`); without them it does nothing.
    pub fn points_at_nodes(&mut self, on: bool) -> bool {
        if self.owners.is_none() {
            return false;
        }
        self.at_nodes = on;
        true
    }

    /// Mean weight per contact (N): the scale of normal-force tolerances.
    pub fn weight_scale(&self, m: &Model) -> f64 {
        (m.total_mass() * f::norm(m.gravity) / self.len().max(1) as f64).max(1e-300)
    }

    /// Start a step of size `h` from `q`: choose the points on the curve at `choose` (the step's
    /// first iterate, the predicted end of the step), freeze the contact frames (from `q`) and
    /// the slip origins (from `origin`), and save the normal forces.
    pub fn begin_step(&mut self, m: &Model, q: &[f64], choose: &[f64], origin: &[f64], h: f64) {
        self.h = h;
        if let Some(owners) = &self.owners {
            for (c, &i) in self.contacts.iter_mut().zip(owners) {
                c.stencil = if self.at_nodes {
                    Stencil::node(i)
                } else {
                    lowest_point(m, choose, i)
                };
            }
            if !self.at_nodes {
                self.step_q.clear();
                self.step_q.extend_from_slice(q);
                self.step_origin.clear();
                self.step_origin.extend_from_slice(origin);
            }
        }
        for c in &mut self.contacts {
            set_frame(m, c, q, origin);
        }
        self.start_gap.clear();
        self.start_gap
            .extend(self.contacts.iter().map(|c| c.gap(q, m.diameter)));
        self.normal_saved.clone_from(&self.normal);
    }

    /// Set `out[r]` (real node `r`) for every node of a contact whose point started the step
    /// below the ground by more than `depth` (m). On the curve a point can lie below the ground
    /// at the step's start where the parabola through a bend that lifts off dips below its
    /// nodes; the step lifts it by that depth whatever its size, like an impact.
    pub fn mark_started_below(&self, m: &Model, depth: f64, out: &mut [bool]) {
        for (c, g) in self.contacts.iter().zip(&self.start_gap) {
            if *g < -depth {
                for (i, _) in c.stencil.iter() {
                    out[i - m.real.start] = true;
                }
            }
        }
    }

    /// Choose again, at the step's solution `q`, the point of every contact on the curve whose
    /// node lies below the ground there by more than [`PENETRATION_TOLERANCE`] `a`; its frame
    /// and slip origin are set from the step's start and slip origin as
    /// [`ContactSet::begin_step`] sets them. Returns whether any point changed.
    ///
    /// A point chosen before the step is solved is the lowest of the curve there, not at the
    /// solution: where a bend lands or the body rolls, the lowest point moves and the body's
    /// nodes sink below the ground between the step's points (by up to 4.9e-5 m, 2.4e-3 `a`,
    /// on the bundled S-start with BDF2 at 3.6e-3 s, the points chosen at the step's start).
    /// Solved again with the point chosen at its solution, the step holds it, and the node
    /// lies no lower than its point (the point lies between the node and the parabola's
    /// vertex). Only sinking nodes count: the parabola through a bend that lifts off can dip
    /// below its nodes where the body (straight between nodes) does not, and a point chosen
    /// there and the node beside it would take turns sinking (the head's contact did, in 7 of
    /// 991 steps of that run).
    pub fn rechoose(&mut self, m: &Model, q: &[f64]) -> bool {
        let Some(owners) = &self.owners else {
            return false;
        };
        if self.at_nodes {
            return false;
        }
        let mut changed = false;
        for (c, &i) in owners.iter().enumerate() {
            if !sinks(m, q, i) {
                continue;
            }
            let p = lowest_point(m, q, i);
            let ct = &mut self.contacts[c];
            ct.stencil = p;
            set_frame(m, ct, &self.step_q, &self.step_origin);
            self.start_gap[c] = ct.gap(&self.step_q, m.diameter);
            changed = true;
        }
        changed
    }

    /// Whether a node of a contact on the curve lies below the ground at `q` by more than
    /// [`PENETRATION_TOLERANCE`] `a` (what [`ContactSet::rechoose`] would change).
    pub fn nodes_below(&self, m: &Model, q: &[f64]) -> bool {
        match &self.owners {
            Some(owners) if !self.at_nodes => owners.iter().any(|&i| sinks(m, q, i)),
            _ => false,
        }
    }

    /// Restore the normal forces saved at the start of the step.
    pub fn restore_normals(&mut self) {
        self.normal.clone_from(&self.normal_saved);
    }

    /// Tangential slip of contact `c` at `q` since the start of the step (m).
    pub fn slip(&self, c: usize, q: &[f64]) -> [f64; 2] {
        self.contacts[c].slip(q)
    }

    /// A force in contact `c`'s `(forward, side)` components as world `(x, y)`.
    pub fn to_world(&self, c: usize, fs: [f64; 2]) -> [f64; 2] {
        self.contacts[c].frame.to_world(fs)
    }

    /// A world `(x, y)` vector in contact `c`'s `(forward, side)` components.
    pub fn to_local(&self, c: usize, xy: [f64; 2]) -> [f64; 2] {
        self.contacts[c].frame.to_local(xy)
    }

    /// Friction dissipation `h D` at `q` with the lagged normal forces (J).
    pub fn dissipation(&self, q: &[f64]) -> f64 {
        let mut d = 0.0;
        for (c, ct) in self.contacts.iter().enumerate() {
            if self.normal[c] == 0.0 {
                continue;
            }
            let u = ct.law.scaled_slip(ct.slip(q));
            d += self.normal[c] * (u[0].powi(2) + u[1].powi(2)).sqrt();
        }
        d // h D = h N mu |v| = N mu |dx|
    }

    /// Lift the iterate's predicted penetrations onto the ground (a feasible start): every
    /// node of a contact's stencil to at least `a/2` (enough for weights that sum to one).
    pub fn lift(&self, m: &Model, q: &mut [f64]) {
        for c in &self.contacts {
            for (i, _) in c.stencil.iter() {
                let k = dof::node(i) + 2;
                q[k] = q[k].max(0.5 * m.diameter);
            }
        }
    }

    /// Normal force on every real node (N), into `out`: a contact at a node writes its force
    /// there, a contact between nodes adds its force spread over its stencil.
    pub fn normal_forces(&self, m: &Model, out: &mut [f64]) {
        out.fill(0.0);
        for (c, ct) in self.contacts.iter().enumerate() {
            if let Some(i) = ct.stencil.single() {
                out[i - m.real.start] = self.normal[c];
            }
        }
        for (c, ct) in self.contacts.iter().enumerate() {
            if ct.stencil.single().is_none() {
                for (i, w) in ct.stencil.iter() {
                    out[i - m.real.start] += w * self.normal[c];
                }
            }
        }
    }
}

/// How far (in units of the diameter `a`) a node may lie below the ground at a step's
/// solution with contacts on the curve before its point is chosen again and the step solved
/// again ([`ContactSet::rechoose`]): 1e-8 m on the bundled S-start, where node contacts keep
/// to 3.4e-9 m (record ground-points-penetration).
pub const PENETRATION_TOLERANCE: f64 = 5e-7;

/// Whether real node `i` lies below the ground at `q` by more than [`PENETRATION_TOLERANCE`] `a`.
fn sinks(m: &Model, q: &[f64], i: usize) -> bool {
    q[dof::node(i) + 2] - 0.5 * m.diameter < -PENETRATION_TOLERANCE * m.diameter
}

/// A contact's frame (forward toward the head: from the node after the point to the one
/// before it, ends one-sided, on the ground) at `q`, and its slip origin at `origin`.
fn set_frame(m: &Model, c: &mut Contact, q: &[f64], origin: &[f64]) {
    let (lo, hi) = c.stencil.span();
    let lo = if lo > m.real.start { lo - 1 } else { lo };
    let hi = if hi + 1 < m.real.end { hi + 1 } else { hi };
    let x = |k: usize| [q[dof::node(k)], q[dof::node(k) + 1], q[dof::node(k) + 2]];
    c.frame = Frame::from_tangent(f::sub(x(lo), x(hi)));
    c.origin = c.stencil.position(origin);
}

/// The regularisation of [`lowest_point`] in units of the diameter `a`.
pub const LOWEST_POINT_TAU: f64 = 1e-4;

/// The sag (second difference of three nodes' heights) in units of the diameter `a` below
/// which a contact on the curve stays at its node ([`lowest_point`]): the largest second
/// difference of Newton's unresolved corrections at the default `[solver] tolerance` (5e-6 `a`
/// per coordinate, four of them in a second difference). Without it the points of a body lying
/// flat sat between nodes by `s c / tau^2` of an element, set by those ripples: solver noise
/// became a shift of the normal forces of order 1e-4 of a weight, above the tolerance, and two
/// runs of the bundled S-start at the default and a thousandth of the tolerances parted by
/// 6.6e-5 `a` in 400 steps (2.7e-6 `a` with it; 5.4e-6 `a` with node contacts).
pub const LOWEST_POINT_DEAD_ZONE: f64 = 2e-5;

/// The lowest point of the body near real node `i` at `q`: the minimum over the half element
/// on either side of `i` of the parabola through the heights of `i` and its two neighbours (at
/// an end, the end node and the next two, over the half element inward), as the stencil of
/// those three nodes. A parabola that does not sag (`c <= 0`: straight or arched) lies above
/// its chords, so the node itself is the lowest point that matters, and so is it for one that
/// sags by less than [`LOWEST_POINT_DEAD_ZONE`] `d`; the vertex of one that sags more is
/// approached by the fraction `(c - d)^2 / ((c - d)^2 + tau^2)`, `tau = 1e-4 a`, so that the
/// point moves continuously as the curve flattens and a flat body's points sit on its nodes.
/// `tau` lies above what Newton resolves (corrections below `[solver] tolerance`, 5e-6 a per
/// coordinate, so up to 2e-5 a in a second difference) and below a real sag (at 800 elements
/// a bend lifting off the ground sags about 8e-4 a, and its point moves 98 % of the way): at
/// `1e-6 a` a flat region's unresolved height ripples (about 1e-8 m at 800 elements) put its
/// points between nodes at random, nearly dependent contacts whose normal forces never settled
/// (`lab/ground_points/fine.sh`). A neighbour clamped in height keeps the contact at the node.
pub fn lowest_point(m: &Model, q: &[f64], i: usize) -> Stencil {
    let (lo, hi) = (m.real.start, m.real.end - 1);
    if hi - lo < 2 {
        return Stencil::node(i);
    }
    // Three nodes and the node's position among them (element units, -1, 0, 1 about the
    // middle one), and the interval of the parameter.
    let (mid, range) = if i == lo {
        (lo + 1, (-1.0, -0.5))
    } else if i == hi {
        (hi - 1, (0.5, 1.0))
    } else {
        (i, (-0.5, 0.5))
    };
    let nodes = [mid - 1, mid, mid + 1];
    if nodes.iter().any(|&k| m.fixed[dof::node(k) + 2]) {
        return Stencil::node(i);
    }
    let z = nodes.map(|k| q[dof::node(k) + 2]);
    let s = 0.5 * (z[2] - z[0]);
    let c = z[2] - 2.0 * z[1] + z[0];
    let node_t = if i == lo {
        -1.0
    } else if i == hi {
        1.0
    } else {
        0.0
    };
    // The sag beyond the dead zone, where Newton's unresolved ripples lie.
    let ce = c - LOWEST_POINT_DEAD_ZONE * m.diameter;
    let t = if ce > 0.0 {
        let tau = LOWEST_POINT_TAU * m.diameter;
        // The vertex relative to the node, regularised, then clamped to the node's interval.
        let vertex = -s / c;
        let blend = ce * ce / (ce * ce + tau * tau);
        (node_t + blend * (vertex - node_t)).clamp(range.0, range.1)
    } else {
        node_t
    };
    if t == node_t {
        return Stencil::node(i);
    }
    let w = [0.5 * t * (t - 1.0), 1.0 - t * t, 0.5 * t * (t + 1.0)];
    Stencil::new(&nodes, &w).expect("three distinct nodes with finite weights")
}
