//! Self-contact: two parts of the body cannot pass through each other (MODEL 3.1).
//!
//! The body is a tube of diameter `a`. Two edges `i < j` are *eligible* when the body between
//! them is longer than `2a` at rest (`s_j - s_{i+1} >= 2a`, `s_k` the arc length of node `k`):
//! closer parts could touch only through a bend of radius below about `0.53 a`, and including
//! them would give forces in ordinary bends. This is the conservative reading of "closest
//! points more than `2a` apart along the body": it leaves out at most one edge length beyond
//! `2a` and, unlike a test on the closest points, does not switch on and off as they move.
//! For an eligible pair, with `d` the distance between the closest points of the two edges
//! ([`crate::rod::segments::closest`]) and the gap `g = d - a`:
//!
//! ```text
//! b(g) = -kappa (g - g_hat)^2 ln(g / g_hat)   for 0 < g < g_hat,   0 for g >= g_hat,
//! ```
//!
//! the barrier of Incremental Potential Contact (Li et al. 2020; for rods, the codimensional
//! form of Li, Kaufman and Jiang 2021), added to the step's incremental potential
//! ([`crate::newton::Potential`]). It is `C^2` at the activation gap `g_hat` (`[self_contact]
//! activation` times `a`) and infinite at contact, so every iterate keeps `d > a`: Newton's
//! line searches start at the largest step that cannot cross a pair ([`SelfContact::max_step`],
//! conservative advancement: along `dq` a pair's distance falls at most as fast as the sum of
//! its two edges' largest node moves), and each step's start is drawn back toward the last
//! solution the same way. The force of a pair is `-b'(g)` along the line of the closest
//! points, shared between the four nodes by the closest points' parameters (the envelope
//! theorem: the gradient of `d` is that of `|p(s) - r(t)|` at fixed `s, t`); the pair is
//! frictionless. `kappa g_hat` is `[self_contact] stiffness` times `B / a^2`: the barrier's force
//! at half the activation gap is `1.19 kappa g_hat` (`kappa g_hat` itself at 0.53 of it), and it grows as `kappa g_hat^2 / g` below,
//! so any load is carried at some gap in `(0, g_hat)`.
//!
//! The Hessian of a pair is taken as `b''(g) grad d grad d^T` (Gauss-Newton: positive
//! semi-definite, rank one; the neglected `b'(g) grad^2 d` is negative semi-definite at fixed
//! closest points and of relative size `g / d`). It couples nodes far apart along the body,
//! outside the band, so it enters the Newton system as a low-rank part
//! ([`crate::band::Assembly::add_low_rank`]), solved by the Sherman-Morrison-Woodbury
//! identity in the band factorisation.
//!
//! Broad phase: the eligible pairs whose boxes (the two nodes of an edge, padded by
//! `(a + g_hat + r) / 2`) overlap at a reference configuration are the candidates
//! ([`crate::rod::segments::SortAndSweep`]); every pair left out is farther than
//! `a + g_hat + r` apart there, so the candidates stay complete while no node has moved more
//! than `r / 2` from the reference. Every evaluation checks that (one pass over the nodes) and
//! rebuilds the candidates where it fails (`r` at least `a / 2`, and more than twice the
//! largest node move of the step being checked), or where `r` is more than four times what
//! the evaluation needs (a margin grown for one long Newton step made nearly every eligible
//! pair a candidate for the rest of the run: at 400 elements self-contact then took three
//! quarters of the S-start's time with no pair near). A scene that never comes close evaluates no
//! pair and rebuilds about every `a / 4` of motion.

mod pair;
#[cfg(test)]
mod tests;

pub use pair::PairState;

use crate::band::Assembly;
use crate::model::Model;
use crate::rod::dof;
use crate::rod::segments::{Aabb, SortAndSweep};
use crate::rod::vec3::f;
use std::cell::RefCell;
use std::ops::Range;

/// Most conservative-advancement rounds per pair in [`SelfContact::max_step`].
const ADVANCE_ROUNDS: usize = 100;
/// The broad phase's margin `r` over `a` (module doc): below `1 - activation`, so that two
/// parts just `2a` apart along a straight body are no candidates, and large enough that the
/// candidates last for a quarter of a diameter of motion.
const MARGIN: f64 = 0.5;
/// The gap that conservative advancement keeps, as a fraction of a pair's gap at the start.
const ADVANCE_FLOOR: f64 = 0.1;
/// The candidates are found again when their margin is more than this many times the one
/// the evaluation needs ([`SelfContact::ensure`]).
const OVERSIZED_MARGIN: f64 = 4.0;

/// The self-contact of a model's body: barrier, broad phase and conservative advancement.
#[derive(Debug)]
pub struct SelfContact {
    /// Diameter `a` (m).
    a: f64,
    /// Activation gap `g_hat` (m).
    g_hat: f64,
    /// Barrier stiffness `kappa` (N/m).
    kappa: f64,
    /// The real edges (internal indices).
    edges: Range<usize>,
    /// Arc length of every internal node at rest (m).
    arc: Vec<f64>,
    cache: RefCell<Cache>,
}

/// The candidate pairs and what they are valid for.
#[derive(Debug, Default)]
struct Cache {
    valid: bool,
    /// Node positions when the candidates were found.
    x_ref: Vec<[f64; 3]>,
    /// The margin `r` the candidates cover.
    margin: f64,
    pairs: Vec<(usize, usize)>,
    boxes: Vec<Aabb>,
    sweep: SortAndSweep,
}

/// What a configuration's self-contact looks like ([`SelfContact::measure`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measure {
    /// Closest centreline distance over the candidate pairs (m; exact wherever it is below
    /// `a + g_hat`, every pair left out being farther; infinite without candidates).
    pub closest: f64,
    /// Pairs within the activation gap (the barrier acts).
    pub active: usize,
    /// Largest pair force (N).
    pub max_force: f64,
}

fn node_x(q: &[f64], i: usize) -> [f64; 3] {
    let k = dof::node(i);
    [q[k], q[k + 1], q[k + 2]]
}

impl SelfContact {
    /// The self-contact of `m`, or `None` where the problem turned it off.
    pub fn of(m: &Model) -> Option<Self> {
        m.self_contact.as_ref().map(|p| Self::with(m, p))
    }

    /// The self-contact's geometry of `m` (eligible pairs, distances), on or off: for measuring
    /// how close parts came ([`closest_of_frame`]).
    pub fn geometry(m: &Model) -> Self {
        let p = crate::model::SelfContactParams {
            activation: crate::problem::keys::SELF_CONTACT_ACTIVATION.real(),
            stiffness: crate::problem::keys::SELF_CONTACT_STIFFNESS.real(),
        };
        Self::with(m, m.self_contact.as_ref().unwrap_or(&p))
    }

    fn with(m: &Model, p: &crate::model::SelfContactParams) -> Self {
        let mut arc = vec![0.0; m.nodes];
        for j in 0..m.nodes - 1 {
            arc[j + 1] = arc[j] + m.rest_len[j];
        }
        let g_hat = p.activation * m.diameter;
        SelfContact {
            a: m.diameter,
            g_hat,
            kappa: p.stiffness * m.bend / (m.diameter * m.diameter) / g_hat,
            edges: m.real_edges(),
            arc,
            cache: RefCell::new(Cache::default()),
        }
    }

    /// Activation gap `g_hat` (m).
    pub fn activation(&self) -> f64 {
        self.g_hat
    }

    /// Whether edges `i < j` are eligible (module doc).
    pub fn eligible(&self, i: usize, j: usize) -> bool {
        self.arc[j] - self.arc[i + 1] >= 2.0 * self.a * (1.0 - 1e-12)
    }

    /// Barrier `b(g)` and its first two derivatives.
    pub fn barrier(&self, g: f64) -> (f64, f64, f64) {
        if g >= self.g_hat {
            return (0.0, 0.0, 0.0);
        }
        if !(g > 0.0) {
            return (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
        }
        let (k, gh) = (self.kappa, self.g_hat);
        let d = g - gh;
        let l = (g / gh).ln();
        (
            -k * d * d * l,
            -k * (2.0 * d * l + d * d / g),
            -k * (2.0 * l + 4.0 * d / g - d * d / (g * g)),
        )
    }

    /// Largest distance of a node from its reference position, at `q` and, if given, at
    /// `q + dq` (the straight path between lies within the larger: [`Self::ensure`]).
    fn largest_move(c: &Cache, q: &[f64], dq: Option<&[f64]>, nodes: Range<usize>) -> f64 {
        let mut worst: f64 = 0.0;
        for i in nodes {
            let x = node_x(q, i);
            let r = c.x_ref[i];
            let mut d2 = f::dot(f::sub(x, r), f::sub(x, r));
            if let Some(dq) = dq {
                let e = f::add(x, node_x(dq, i));
                d2 = d2.max(f::dot(f::sub(e, r), f::sub(e, r)));
            }
            worst = worst.max(d2);
        }
        worst.sqrt()
    }

    fn node_range(&self) -> Range<usize> {
        self.edges.start..self.edges.end + 1
    }

    /// Make the candidates cover `q` and, if given, the straight path from `q` to `q + dq`.
    fn ensure(&self, q: &[f64], dq: Option<&[f64]>) {
        let mut c = self.cache.borrow_mut();
        let nodes = self.node_range();
        let step = dq.map_or(0.0, |dq| {
            nodes
                .clone()
                .map(|i| f::norm(node_x(dq, i)))
                .fold(0.0, f64::max)
        });
        let margin = (MARGIN * self.a).max(2.5 * step);
        // A margin grown for one long Newton step is dropped once the steps are short again:
        // it would keep nearly every eligible pair a candidate for every later evaluation.
        if c.valid
            && c.margin <= OVERSIZED_MARGIN * margin
            && Self::largest_move(&c, q, dq, nodes.clone()) <= 0.5 * c.margin
        {
            return;
        }
        let pad = 0.5 * (self.a + self.g_hat + margin);
        let c = &mut *c;
        c.x_ref.resize(nodes.end, [0.0; 3]);
        for i in nodes.clone() {
            c.x_ref[i] = node_x(q, i);
        }
        c.boxes.clear();
        for j in self.edges.clone() {
            c.boxes
                .push(Aabb::around(&[c.x_ref[j], c.x_ref[j + 1]], pad));
        }
        let e0 = self.edges.start;
        let keep = |i: usize, j: usize| self.eligible(i + e0, j + e0);
        c.sweep.pairs(&c.boxes, &keep, &mut c.pairs);
        for p in c.pairs.iter_mut() {
            *p = (p.0 + e0, p.1 + e0);
        }
        c.margin = margin;
        c.valid = true;
    }

    /// The candidate pairs at `q` (as [`Self::ensure`] leaves them).
    fn with_pairs<R>(
        &self,
        q: &[f64],
        dq: Option<&[f64]>,
        f: impl FnOnce(&[(usize, usize)]) -> R,
    ) -> R {
        self.ensure(q, dq);
        let c = self.cache.borrow();
        f(&c.pairs)
    }

    /// Call `f` with every eligible pair within the activation gap at `q` (or overlapping).
    fn for_each_active(&self, q: &[f64], mut f: impl FnMut(&PairState)) {
        self.with_pairs(q, None, |pairs| {
            for &(i, j) in pairs {
                if self.surely_apart(q, i, j) {
                    continue;
                }
                let p = self.pair(q, i, j);
                if p.gap < self.g_hat {
                    f(&p);
                }
            }
        })
    }

    /// Barrier energy at `q` (J; infinite when a pair touches or overlaps).
    pub fn value(&self, q: &[f64]) -> f64 {
        let mut e = 0.0;
        self.for_each_active(q, |p| e += self.barrier(p.gap).0);
        e
    }

    /// Add the barrier's gradient and its Hessian (projected, low-rank) at `q` to `asm`;
    /// returns its value.
    pub fn assemble(&self, q: &[f64], asm: &mut Assembly) -> f64 {
        let mut e = 0.0;
        self.for_each_active(q, |p| {
            let (b, db, ddb) = self.barrier(p.gap);
            e += b;
            if !b.is_finite() {
                asm.grad[dof::node(p.edges.0)] = f64::NAN;
                return;
            }
            let (idx, val) = Self::distance_gradient(p);
            for (&k, v) in idx.iter().zip(&val) {
                asm.grad[k] += db * v;
            }
            self.add_pair_hessian(q, p, db, ddb, asm);
        });
        e
    }

    /// The largest step length in `(0, 1]` along `dq` from `q` (where every pair is apart)
    /// that no pair can cross: 1 unless a pair could come within its gap's floor.
    pub fn max_step(&self, q: &[f64], dq: &[f64]) -> f64 {
        self.with_pairs(q, Some(dq), |pairs| {
            let mut alpha: f64 = 1.0;
            for &(i, j) in pairs {
                alpha = alpha.min(self.advance(q, dq, i, j));
            }
            alpha
        })
    }

    /// Conservative advancement of one pair along `dq` (module doc).
    fn advance(&self, q: &[f64], dq: &[f64], i: usize, j: usize) -> f64 {
        let step = Self::nodes(dq, i, j);
        let speed = f::norm(step[0]).max(f::norm(step[1])) + f::norm(step[2]).max(f::norm(step[3]));
        // Far enough apart for the whole step by the cheap bound: no closest points needed.
        if speed == 0.0 || self.distance_bound(q, i, j) - self.a >= speed {
            return 1.0;
        }
        let start = Self::nodes(q, i, j);
        let g0 = self.pair_at((i, j), start).gap;
        if g0 >= speed {
            return 1.0;
        }
        let floor = ADVANCE_FLOOR * g0;
        let mut t = 0.0;
        let mut g = g0;
        for _ in 0..ADVANCE_ROUNDS {
            let dt = (g - floor) / speed;
            if t + dt >= 1.0 {
                return 1.0;
            }
            t += dt;
            let x = std::array::from_fn(|r| f::add(start[r], f::scale(step[r], t)));
            g = self.pair_at((i, j), x).gap;
            if g - floor < 1e-2 * g0 {
                break;
            }
        }
        t
    }

    /// The self-contact at `q`: closest distance over the candidates, active pairs, forces.
    pub fn measure(&self, q: &[f64]) -> Measure {
        self.with_pairs(q, None, |pairs| {
            let mut m = Measure {
                closest: f64::INFINITY,
                ..Measure::default()
            };
            for &(i, j) in pairs {
                // Neither closer than the closest so far nor within the activation gap.
                let bound = self.distance_bound(q, i, j);
                if bound >= m.closest && bound > self.a + self.g_hat {
                    continue;
                }
                let p = self.pair(q, i, j);
                m.closest = m.closest.min(p.closest.dist);
                if p.gap < self.g_hat {
                    m.active += 1;
                    let force = -self.barrier(p.gap).1;
                    m.max_force = m.max_force.max(force);
                }
            }
            m
        })
    }

    /// The active pairs at `q` with their forces on the four nodes (N, in the order
    /// `x_i, x_{i+1}, x_j, x_{j+1}`: minus the barrier's gradient).
    pub fn forces(&self, q: &[f64]) -> Vec<(PairState, [[f64; 3]; 4])> {
        let mut out = Vec::new();
        self.for_each_active(q, |p| {
            let db = self.barrier(p.gap).1;
            let (_, val) = Self::distance_gradient(p);
            out.push((
                *p,
                std::array::from_fn(|r| std::array::from_fn(|k| -db * val[3 * r + k])),
            ));
        });
        out
    }

    /// Closest centreline distance over every eligible pair at `q` (m; infinite when no pair
    /// is eligible): the sweep's padding doubles until it finds a pair within it.
    pub fn closest_distance(&self, q: &[f64]) -> f64 {
        let mut sweep = SortAndSweep::default();
        let mut pairs = Vec::new();
        let e0 = self.edges.start;
        let keep = |i: usize, j: usize| self.eligible(i + e0, j + e0);
        let mut reach = 2.0 * self.a;
        let extent = self.arc[self.edges.end] + self.a;
        loop {
            let boxes: Vec<Aabb> = self
                .edges
                .clone()
                .map(|j| Aabb::around(&[node_x(q, j), node_x(q, j + 1)], 0.5 * reach))
                .collect();
            sweep.pairs(&boxes, &keep, &mut pairs);
            let best = pairs
                .iter()
                .map(|&(i, j)| self.pair(q, i + e0, j + e0).closest.dist)
                .fold(f64::INFINITY, f64::min);
            if best <= reach || reach > 2.0 * extent {
                return best;
            }
            reach *= 2.0;
        }
    }
}

/// The coordinates of a recorded frame: the model's initial ones with the real nodes (head
/// first) at `x`.
fn frame_q(m: &Model, x: &[[f64; 3]]) -> Vec<f64> {
    let mut q = m.q0.clone();
    for (i, xi) in m.real.clone().zip(x) {
        q[dof::node(i)..dof::node(i) + 3].copy_from_slice(xi);
    }
    q
}

/// Closest centreline distance between eligible parts (m) of a recorded frame: `x`, the real
/// nodes (head first); infinite when no pair is eligible.
pub fn closest_of_frame(sc: &SelfContact, m: &Model, x: &[[f64; 3]]) -> f64 {
    sc.closest_distance(&frame_q(m, x))
}

/// The real nodes (head first) of a recorded frame that belong to an edge of an eligible
/// pair within the activation gap (or overlapping: a body that passes through itself).
pub fn touching_of_frame(sc: &SelfContact, m: &Model, x: &[[f64; 3]]) -> Vec<bool> {
    let mut touching = vec![false; m.nodes];
    sc.for_each_active(&frame_q(m, x), |p| {
        let (i, j) = p.edges;
        for k in [i, i + 1, j, j + 1] {
            touching[k] = true;
        }
    });
    m.real.clone().map(|i| touching[i]).collect()
}

/// Cumulative self-contact statistics of a run (`summary.json`, block `self_contact`).
#[derive(Clone, Copy, Debug, Default, serde::Serialize, PartialEq)]
pub struct SelfContactStats {
    /// Closest centreline distance between eligible parts over every accepted step, over `a`
    /// (the broad phase's candidates at each step, exact wherever it is below
    /// `1 + activation`; the run adds every recorded frame's exact distance; `null` when no
    /// pair was a candidate at any step or frame).
    pub closest_over_a: Option<f64>,
    /// Accepted steps that ended with at least one pair within the activation gap.
    pub active_steps: usize,
    /// Largest force of one pair at the end of a step (N).
    pub max_force: f64,
    /// Most pairs within the activation gap at once.
    pub max_pairs: usize,
}

impl SelfContactStats {
    /// Count an accepted step's measure.
    pub fn count(&mut self, m: &Measure, a: f64) {
        if m.closest.is_finite() {
            let c = m.closest / a;
            self.closest_over_a = Some(self.closest_over_a.map_or(c, |x| x.min(c)));
        }
        if m.active > 0 {
            self.active_steps += 1;
        }
        self.max_force = self.max_force.max(m.max_force);
        self.max_pairs = self.max_pairs.max(m.active);
    }
}
