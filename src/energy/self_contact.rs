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
//! largest node move of the step being checked). A scene that never comes close evaluates no
//! pair and rebuilds about every `a / 4` of motion.

use crate::band::{Assembly, LOW_RANK_ENTRIES};
use crate::model::Model;
use crate::rod::dof;
use crate::rod::segments::{closest, Aabb, Closest, SortAndSweep};
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

/// One pair's state at a configuration.
#[derive(Clone, Copy, Debug)]
pub struct PairState {
    /// The two edges.
    pub edges: (usize, usize),
    /// Their closest points.
    pub closest: Closest,
    /// The gap `d - a` (m).
    pub gap: f64,
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
    /// Sum of the pair forces (N).
    pub total_force: f64,
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
        if c.valid && Self::largest_move(&c, q, dq, nodes.clone()) <= 0.5 * c.margin {
            return;
        }
        let step = dq.map_or(0.0, |dq| {
            nodes
                .clone()
                .map(|i| f::norm(node_x(dq, i)))
                .fold(0.0, f64::max)
        });
        let margin = (MARGIN * self.a).max(2.5 * step);
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

    /// A pair's state at `q`.
    pub fn pair(&self, q: &[f64], i: usize, j: usize) -> PairState {
        let c = closest(
            node_x(q, i),
            node_x(q, i + 1),
            node_x(q, j),
            node_x(q, j + 1),
        );
        PairState {
            edges: (i, j),
            closest: c,
            gap: c.dist - self.a,
        }
    }

    /// Whether the pair `(i, j)` is certainly beyond the activation gap at `q`: the distance of
    /// the edges' midpoints less their half-lengths (a bound below the distance) exceeds
    /// `a + g_hat`. Cheaper than the closest points for the candidates that are far.
    fn surely_apart(&self, q: &[f64], i: usize, j: usize) -> bool {
        self.distance_bound(q, i, j) > self.a + self.g_hat
    }

    /// A lower bound of the pair's distance at `q`: the distance of the edges' midpoints less
    /// their half-lengths.
    fn distance_bound(&self, q: &[f64], i: usize, j: usize) -> f64 {
        let (a0, a1) = (node_x(q, i), node_x(q, i + 1));
        let (b0, b1) = (node_x(q, j), node_x(q, j + 1));
        let mid = f::norm(f::sub(f::add(a0, a1), f::add(b0, b1)));
        0.5 * (mid - f::norm(f::sub(a1, a0)) - f::norm(f::sub(b1, b0)))
    }

    /// Barrier energy at `q` (J; infinite when a pair touches or overlaps).
    pub fn value(&self, q: &[f64]) -> f64 {
        self.with_pairs(q, None, |pairs| {
            let mut e = 0.0;
            for &(i, j) in pairs {
                if self.surely_apart(q, i, j) {
                    continue;
                }
                let p = self.pair(q, i, j);
                if p.gap < self.g_hat {
                    e += self.barrier(p.gap).0;
                }
            }
            e
        })
    }

    /// The gradient of a pair's distance over its four nodes' coordinates, and their indices.
    fn distance_gradient(p: &PairState) -> ([usize; LOW_RANK_ENTRIES], [f64; LOW_RANK_ENTRIES]) {
        let (i, j) = p.edges;
        let c = &p.closest;
        let n = f::scale(c.delta, 1.0 / c.dist);
        let w = [1.0 - c.s, c.s, -(1.0 - c.t), -c.t];
        let nodes = [i, i + 1, j, j + 1];
        let mut idx = [0; LOW_RANK_ENTRIES];
        let mut val = [0.0; LOW_RANK_ENTRIES];
        for (r, (&node, &wr)) in nodes.iter().zip(&w).enumerate() {
            for k in 0..3 {
                idx[3 * r + k] = dof::node(node) + k;
                val[3 * r + k] = wr * n[k];
            }
        }
        (idx, val)
    }

    /// The exact Hessian of a pair's distance over its four nodes' twelve coordinates (order
    /// `x_i, x_{i+1}, x_j, x_{j+1}`). With `delta = A(s, t) x` and `F = |delta|`, the closest
    /// points' parameters that lie inside `(0, 1)` (the free ones, `z`) move with `x`, so the
    /// Hessian is the Schur complement `F_xx - F_xz F_zz^-1 F_zx` of the Hessian of `F` over
    /// `(x, z)`; a parameter at an end of its edge stays there. Where the two edges are
    /// parallel (`F_zz` singular) `s` is held as well.
    pub fn distance_hessian(&self, q: &[f64], p: &PairState) -> [[f64; 12]; 12] {
        let (i, j) = p.edges;
        let c = &p.closest;
        let d = c.dist;
        let n = f::scale(c.delta, 1.0 / d);
        let e1 = f::sub(node_x(q, i + 1), node_x(q, i));
        let e2 = f::sub(node_x(q, j + 1), node_x(q, j));
        // P v / d with P = I - n n^T.
        let proj = |v: [f64; 3]| f::scale(f::sub(v, f::scale(n, f::dot(n, v))), 1.0 / d);
        let w = [1.0 - c.s, c.s, -(1.0 - c.t), -c.t];
        let mut h = [[0.0; 12]; 12];
        for a in 0..4 {
            for b in 0..4 {
                for r in 0..3 {
                    for k in 0..3 {
                        let pij = if r == k { 1.0 } else { 0.0 } - n[r] * n[k];
                        h[3 * a + r][3 * b + k] = w[a] * w[b] * pij / d;
                    }
                }
            }
        }
        // Mixed rows F_xz: for s, (dA/ds)^T n + A^T P e1 / d; for t, (dA/dt)^T n - A^T P e2 / d.
        let pe1 = proj(e1);
        let pe2 = proj(e2);
        let mut fxz = [[0.0; 12]; 2];
        for a in 0..4 {
            for r in 0..3 {
                fxz[0][3 * a + r] = w[a] * pe1[r];
                fxz[1][3 * a + r] = -w[a] * pe2[r];
            }
        }
        for r in 0..3 {
            fxz[0][r] -= n[r];
            fxz[0][3 + r] += n[r];
            fxz[1][6 + r] += n[r];
            fxz[1][9 + r] -= n[r];
        }
        let fss = f::dot(e1, pe1);
        let ftt = f::dot(e2, pe2);
        let fst = -f::dot(e1, pe2);
        let inside = |x: f64| x > 0.0 && x < 1.0;
        let (mut free_s, free_t) = (inside(c.s), inside(c.t));
        if free_s && free_t && fss * ftt - fst * fst <= 1e-10 * fss * ftt {
            free_s = false;
        }
        let mut sub = |g: &[f64; 12], k: &[f64; 12], coef: f64| {
            for r in 0..12 {
                for col in 0..12 {
                    h[r][col] -= coef * g[r] * k[col];
                }
            }
        };
        match (free_s, free_t) {
            (true, true) => {
                let det = fss * ftt - fst * fst;
                let (iss, itt, ist) = (ftt / det, fss / det, -fst / det);
                sub(&fxz[0], &fxz[0], iss);
                sub(&fxz[1], &fxz[1], itt);
                sub(&fxz[0], &fxz[1], ist);
                sub(&fxz[1], &fxz[0], ist);
            }
            (true, false) => sub(&fxz[0], &fxz[0], 1.0 / fss),
            (false, true) => sub(&fxz[1], &fxz[1], 1.0 / ftt),
            (false, false) => {}
        }
        h
    }

    /// The pair's barrier Hessian `b'' grad d grad d^T + b' grad^2 d`, projected to positive
    /// semi-definite, as low-rank columns `sqrt(lambda) v` of its positive eigenpairs.
    fn add_pair_hessian(&self, q: &[f64], p: &PairState, db: f64, ddb: f64, asm: &mut Assembly) {
        let (idx, g) = Self::distance_gradient(p);
        let hd = self.distance_hessian(q, p);
        let k = nalgebra::SMatrix::<f64, 12, 12>::from_fn(|r, c| ddb * g[r] * g[c] + db * hd[r][c]);
        let k = 0.5 * (k + k.transpose());
        let eig = k.symmetric_eigen();
        let top = eig.eigenvalues.max();
        for (l, lam) in eig.eigenvalues.iter().enumerate() {
            if *lam > 1e-12 * top {
                let v = eig.eigenvectors.column(l);
                let root = lam.sqrt();
                asm.add_low_rank(idx, std::array::from_fn(|r| root * v[r]));
            }
        }
    }

    /// Add the barrier's gradient and its Hessian (projected, low-rank) at `q` to `asm`;
    /// returns its value.
    pub fn assemble(&self, q: &[f64], asm: &mut Assembly) -> f64 {
        self.with_pairs(q, None, |pairs| {
            let mut e = 0.0;
            for &(i, j) in pairs {
                if self.surely_apart(q, i, j) {
                    continue;
                }
                let p = self.pair(q, i, j);
                if p.gap >= self.g_hat {
                    continue;
                }
                let (b, db, ddb) = self.barrier(p.gap);
                e += b;
                if !b.is_finite() {
                    asm.grad[dof::node(i)] = f64::NAN;
                    continue;
                }
                let (idx, val) = Self::distance_gradient(&p);
                for (&k, v) in idx.iter().zip(&val) {
                    asm.grad[k] += db * v;
                }
                self.add_pair_hessian(q, &p, db, ddb, asm);
            }
            e
        })
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
        let mv = |k: usize| f::norm(node_x(dq, k));
        let speed = mv(i).max(mv(i + 1)) + mv(j).max(mv(j + 1));
        // Far enough apart for the whole step by the cheap bound: no closest points needed.
        if speed == 0.0 || self.distance_bound(q, i, j) - self.a >= speed {
            return 1.0;
        }
        let g0 = self.pair(q, i, j).gap;
        if speed == 0.0 || g0 >= speed {
            return 1.0;
        }
        let floor = ADVANCE_FLOOR * g0;
        let mut t = 0.0;
        let mut g = g0;
        let mut x = q.to_vec();
        for _ in 0..ADVANCE_ROUNDS {
            let dt = (g - floor) / speed;
            if t + dt >= 1.0 {
                return 1.0;
            }
            t += dt;
            for node in [i, i + 1, j, j + 1] {
                for k in dof::node(node)..dof::node(node) + 3 {
                    x[k] = q[k] + t * dq[k];
                }
            }
            g = self.pair(&x, i, j).gap;
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
                    m.total_force += force;
                }
            }
            m
        })
    }

    /// The active pairs at `q` with their forces on the four nodes (N, in the order
    /// `x_i, x_{i+1}, x_j, x_{j+1}`: minus the barrier's gradient).
    pub fn forces(&self, q: &[f64]) -> Vec<(PairState, [[f64; 3]; 4])> {
        self.with_pairs(q, None, |pairs| {
            let mut out = Vec::new();
            for &(i, j) in pairs {
                let p = self.pair(q, i, j);
                if p.gap >= self.g_hat {
                    continue;
                }
                let db = self.barrier(p.gap).1;
                let (_, val) = Self::distance_gradient(&p);
                let mut fs = [[0.0; 3]; 4];
                for r in 0..4 {
                    for k in 0..3 {
                        fs[r][k] = -db * val[3 * r + k];
                    }
                }
                out.push((p, fs));
            }
            out
        })
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

/// Closest centreline distance between eligible parts (m) of a recorded frame: `x`, the real
/// nodes (head first); infinite when no pair is eligible.
pub fn closest_of_frame(sc: &SelfContact, m: &Model, x: &[[f64; 3]]) -> f64 {
    let mut q = m.q0.clone();
    for (i, xi) in m.real.clone().zip(x) {
        q[dof::node(i)..dof::node(i) + 3].copy_from_slice(xi);
    }
    sc.closest_distance(&q)
}

/// The real nodes (head first) of a recorded frame that belong to an edge of an eligible
/// pair within the activation gap (or overlapping: a body that passes through itself).
pub fn touching_of_frame(sc: &SelfContact, m: &Model, x: &[[f64; 3]]) -> Vec<bool> {
    let mut q = m.q0.clone();
    for (i, xi) in m.real.clone().zip(x) {
        q[dof::node(i)..dof::node(i) + 3].copy_from_slice(xi);
    }
    let mut touching = vec![false; m.nodes];
    sc.with_pairs(&q, None, |pairs| {
        for &(i, j) in pairs {
            if sc.pair(&q, i, j).gap < sc.g_hat {
                for k in [i, i + 1, j, j + 1] {
                    touching[k] = true;
                }
            }
        }
    });
    m.real.clone().map(|i| touching[i]).collect()
}

/// Cumulative self-contact statistics of a run (`summary.json`, block `self_contact`).
#[derive(Clone, Copy, Debug, serde::Serialize, PartialEq)]
pub struct Stats {
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

impl Default for Stats {
    fn default() -> Self {
        Stats {
            closest_over_a: None,
            active_steps: 0,
            max_force: 0.0,
            max_pairs: 0,
        }
    }
}

impl Stats {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fd;

    /// A free 24-element rod of 0.24 m (`a` = 0.02 m, edges of half a diameter) without
    /// gravity, with its coordinates folded so that the head half lies across the tail half
    /// at `gap` (m) beyond contact, plus a random jitter of up to `jitter / 2` (m) per
    /// coordinate. The activation gap is 2e-4 m.
    fn folded(gap: f64, jitter: f64, seed: u64) -> (Model, Vec<f64>) {
        let toml =
            "[rod]\nlength = 0.24\ndiameter = 0.02\nelements = 24\nbending_stiffness = 0.01\n\
                    [gravity]\ng = 0.0\n[time]\ndt = 1e-3\nduration = 0.01\n";
        let p = crate::problem::parse(toml, std::path::Path::new("<test>")).unwrap();
        let m = Model::new(&p);
        let a = m.diameter;
        let mut q = m.q0.clone();
        let mut x = seed;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        // Nodes 0..=10 along -y at x = 0.05 (node 7 at y = 0), a + gap above nodes 13..=24
        // along -x at y = 0 (node 19 at x = 0.05); nodes 11 and 12 fold the rod well apart.
        for i in 0..m.nodes {
            let k = dof::node(i);
            let xyz = match i {
                0..=10 => [
                    0.05 + 0.3 * a * next(),
                    0.07 - 0.01 * i as f64,
                    a / 2.0 + a + gap,
                ],
                11 => [0.09, -0.03, 1.5 * a],
                12 => [0.12, -0.01, a],
                _ => [0.24 - 0.01 * i as f64, 0.0, a / 2.0],
            };
            for c in 0..3 {
                q[k + c] = xyz[c] + jitter * next();
            }
        }
        (m, q)
    }

    /// The barrier's gradient is that of its value (central differences), with pairs across
    /// the activation gap; `b'` and `b''` are those of `b`.
    #[test]
    fn barrier_derivatives_match_finite_differences() {
        for (gap, seed) in [(1.6e-4, 3u64), (1e-4, 5), (4e-5, 7), (6e-6, 11)] {
            let (m, q) = folded(gap, 2e-7, seed);
            let sc = SelfContact::of(&m).unwrap();
            let mut asm = Assembly::new(m.ndof);
            let e = sc.assemble(&q, &mut asm);
            assert!(e > 0.0, "gap {gap}: no active pair");
            assert!(!asm.low_rank.is_empty());
            let mut value = |x: &[f64]| sc.value(x);
            let num = fd::gradient(&mut value, &q, 1e-9);
            let err = fd::rel_error(&asm.grad, &num, 1e-12);
            assert!(err < 1e-5, "gap {gap}: gradient error {err:.2e}");
            // b' and b'' against differences of b and b'.
            for g in [0.1, 0.5, 0.9].map(|f| f * sc.activation()) {
                let hstep = 1e-6 * sc.activation();
                let (b, db, ddb) = sc.barrier(g);
                let (bp, dbp, _) = sc.barrier(g + hstep);
                let (bm, dbm, _) = sc.barrier(g - hstep);
                assert!(b > 0.0);
                assert!(((bp - bm) / (2.0 * hstep) - db).abs() <= 1e-6 * db.abs());
                assert!(((dbp - dbm) / (2.0 * hstep) - ddb).abs() <= 1e-6 * ddb.abs());
            }
            // The low-rank part is positive semi-definite (it is the projection of
            // b'' grad d grad d^T + b' grad^2 d, whose parts the tests here check).
            let mut v = vec![0.0; m.ndof];
            for (k, x) in v.iter_mut().enumerate() {
                *x = ((k * 7919) % 13) as f64 - 6.0;
            }
            let form: f64 = asm.low_rank.iter().map(|u| u.dot(&v).powi(2)).sum();
            assert!(form > 0.0);
        }
    }

    /// The exact Hessian of a pair's distance is the Jacobian of its gradient (central
    /// differences), for crossing edges (both closest points inside), an end against an edge
    /// and two ends; and the projected barrier Hessian is positive semi-definite.
    #[test]
    fn distance_hessian_matches_finite_differences() {
        let (m, _) = folded(1e-4, 0.0, 1);
        let sc = SelfContact::of(&m).unwrap();
        let a = m.diameter;
        let mut q = m.q0.clone();
        let set = |q: &mut Vec<f64>, i: usize, x: [f64; 3]| {
            q[dof::node(i)..dof::node(i) + 3].copy_from_slice(&x);
        };
        let cases: [[[f64; 3]; 4]; 4] = [
            // Crossing, skew.
            [
                [0.0, 0.0, 0.0],
                [0.01, 0.001, 0.0005],
                [0.004, -0.005, 1.01 * a],
                [0.006, 0.005, 1.02 * a],
            ],
            // The second edge's end above the first edge's inside.
            [
                [0.0, 0.0, 0.0],
                [0.01, 0.0, 0.001],
                [0.005, 0.0, 1.01 * a],
                [0.007, 0.008, 1.3 * a],
            ],
            // End to end.
            [
                [0.0, 0.0, 0.0],
                [0.01, 0.002, 0.0],
                [0.0105, 0.003, 1.01 * a],
                [0.02, 0.009, 1.4 * a],
            ],
            // Nearly parallel, offset along.
            [
                [0.0, 0.0, 0.0],
                [0.01, 0.0, 0.0],
                [0.004, 0.0003, 1.01 * a],
                [0.014, 0.0, 1.0101 * a],
            ],
        ];
        let (i, j) = (2usize, 20usize);
        for (n, pts) in cases.iter().enumerate() {
            set(&mut q, i, pts[0]);
            set(&mut q, i + 1, pts[1]);
            set(&mut q, j, pts[2]);
            set(&mut q, j + 1, pts[3]);
            let p = sc.pair(&q, i, j);
            let h = sc.distance_hessian(&q, &p);
            let (idx, _) = SelfContact::distance_gradient(&p);
            let x0: Vec<f64> = idx.iter().map(|&k| q[k]).collect();
            let mut grad = |x: &[f64]| {
                let mut y = q.clone();
                for (&k, v) in idx.iter().zip(x) {
                    y[k] = *v;
                }
                SelfContact::distance_gradient(&sc.pair(&y, i, j))
                    .1
                    .to_vec()
            };
            let jac = fd::jacobian(&mut grad, &x0, 1e-8);
            let scale = h.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
            for r in 0..12 {
                for c in 0..12 {
                    assert!(
                        (h[r][c] - jac[r][c]).abs() <= 1e-5 * scale,
                        "case {n}: ({r}, {c}) {} vs {}",
                        h[r][c],
                        jac[r][c]
                    );
                }
            }
            let mut asm = Assembly::new(m.ndof);
            let (_, db, ddb) = sc.barrier(0.5 * sc.activation());
            sc.add_pair_hessian(&q, &p, db, ddb, &mut asm);
            assert!(!asm.low_rank.is_empty());
        }
    }

    /// The four forces of every active pair add up to zero (equal and opposite on the two
    /// edges), and push the edges apart.
    #[test]
    fn pair_forces_are_equal_and_opposite() {
        let (m, q) = folded(1e-4, 2e-7, 13);
        let sc = SelfContact::of(&m).unwrap();
        let pairs = sc.forces(&q);
        assert!(!pairs.is_empty());
        for (p, fs) in pairs {
            let on_i = f::add(fs[0], fs[1]);
            let on_j = f::add(fs[2], fs[3]);
            let scale = f::norm(on_i);
            assert!(scale > 0.0);
            assert!(f::norm(f::add(on_i, on_j)) <= 1e-14 * scale);
            // Along p(s) - r(t): pushes edge i away from edge j.
            assert!(f::dot(on_i, p.closest.delta) > 0.0);
        }
    }

    /// Conservative advancement never lets a pair cross: along random directions large
    /// enough to pass the upper half through the lower, the capped step ends with every
    /// candidate gap positive, and so does every point of the way there (sampled).
    #[test]
    fn max_step_never_crosses() {
        for seed in 1..20u64 {
            let (m, q) = folded(3e-3, 0.0, seed);
            let sc = SelfContact::of(&m).unwrap();
            let mut dq = vec![0.0; m.ndof];
            let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
            for i in 0..=10 {
                let k = dof::node(i);
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let r = (x >> 11) as f64 / (1u64 << 53) as f64;
                // Down through the lower half, 1 to 3 diameters.
                dq[k + 2] = -(1.0 + 2.0 * r) * m.diameter;
                dq[k] = 0.5 * (r - 0.5) * m.diameter;
            }
            let alpha = sc.max_step(&q, &dq);
            assert!(alpha < 1.0 && alpha > 0.0, "seed {seed}: alpha {alpha}");
            for f in 1..=50 {
                let t = alpha * f as f64 / 50.0;
                let y: Vec<f64> = q.iter().zip(&dq).map(|(a, b)| a + t * b).collect();
                let c = sc.closest_distance(&y);
                assert!(c > m.diameter, "seed {seed}: t {t}: {c}");
            }
            // Without the cap the full step crosses.
            let y: Vec<f64> = q.iter().zip(&dq).map(|(a, b)| a + b).collect();
            let _ = sc.value(&y);
        }
    }

    /// The candidate set's closest distance, and the exact one by the doubling sweep, equal
    /// a brute-force minimum over every eligible pair.
    #[test]
    fn closest_distance_matches_brute_force() {
        for (gap, jitter, seed) in [
            (1e-4, 0.0, 1u64),
            (3e-3, 0.0, 2),
            (0.02, 0.006, 3),
            (0.1, 0.01, 4),
        ] {
            let (m, q) = folded(gap, jitter, seed);
            let sc = SelfContact::of(&m).unwrap();
            let mut best = f64::INFINITY;
            for i in m.real_edges() {
                for j in i + 1..m.real_edges().end {
                    if sc.eligible(i, j) {
                        best = best.min(sc.pair(&q, i, j).closest.dist);
                    }
                }
            }
            assert_eq!(sc.closest_distance(&q), best, "gap {gap}");
            let measured = sc.measure(&q).closest;
            if best < m.diameter + sc.activation() {
                assert_eq!(measured, best);
            }
        }
    }
}
