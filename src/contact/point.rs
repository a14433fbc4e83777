//! A contact: a point anywhere on the body, with its gap, its frame and its friction law.
//!
//! The point is a [`Stencil`]: a weighted sum of a few node positions, `x_c = sum_i w_i x_i`
//! (the nodes of one or two segments). Everything a contact solver needs is linear in `q`
//! through it: the gap `x_c . e_z - a/2` against the plane `z = 0` (MODEL 3; an incline tilts
//! gravity, not the plane), the slip `x_c - x_c(origin)` and, transposed, where a contact
//! force acts (`w_i F` on node `i`). A ground contact at a node is the stencil of one node
//! with weight 1 ([`Stencil::node`]); a point between nodes (the lowest point of the parabola
//! through three nodes, [`super::set::lowest_point`]) is the same type with more nodes, so
//! the conic program takes it as it is, and a solver that eliminates a contact's coordinates
//! (the semi-smooth Newton) asks [`Stencil::single`] whether it can.

use crate::model::Ground;
use crate::rod::{dof, vec3::f};

/// Most nodes a stencil may weigh: the four nodes of two segments (or of a cubic through
/// four nodes).
pub const MAX_STENCIL: usize = 4;

/// A point of the body as a weighted sum of node positions, `x_c = sum_i w_i x_i`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stencil {
    len: usize,
    nodes: [usize; MAX_STENCIL],
    weights: [f64; MAX_STENCIL],
}

/// Why a stencil was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StencilError {
    /// No node, more than [`MAX_STENCIL`], or node and weight lists of different lengths.
    #[error("a stencil needs 1 to {MAX_STENCIL} nodes, each with one weight ({nodes} nodes, {weights} weights)")]
    Size {
        /// Nodes given.
        nodes: usize,
        /// Weights given.
        weights: usize,
    },
    /// A node listed twice.
    #[error("node {0} appears twice in the stencil")]
    Repeated(usize),
    /// A weight that is not finite.
    #[error("weight {0} of the stencil is not finite")]
    NonFinite(f64),
}

impl Stencil {
    /// The point at node `i` (weight 1): a ground contact at a node.
    pub fn node(i: usize) -> Self {
        let mut s = Stencil {
            len: 1,
            nodes: [0; MAX_STENCIL],
            weights: [0.0; MAX_STENCIL],
        };
        s.nodes[0] = i;
        s.weights[0] = 1.0;
        s
    }

    /// The point `sum_k weights[k] x_{nodes[k]}` (internal node indices, each at most once).
    pub fn new(nodes: &[usize], weights: &[f64]) -> Result<Self, StencilError> {
        if nodes.is_empty() || nodes.len() > MAX_STENCIL || nodes.len() != weights.len() {
            return Err(StencilError::Size {
                nodes: nodes.len(),
                weights: weights.len(),
            });
        }
        let mut s = Stencil {
            len: nodes.len(),
            nodes: [0; MAX_STENCIL],
            weights: [0.0; MAX_STENCIL],
        };
        for (k, (&i, &w)) in nodes.iter().zip(weights).enumerate() {
            if nodes[..k].contains(&i) {
                return Err(StencilError::Repeated(i));
            }
            if !w.is_finite() {
                return Err(StencilError::NonFinite(w));
            }
            s.nodes[k] = i;
            s.weights[k] = w;
        }
        Ok(s)
    }

    /// The stencil's nodes with their weights.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.nodes[..self.len]
            .iter()
            .copied()
            .zip(self.weights[..self.len].iter().copied())
    }

    /// The node of a one-node stencil of weight 1 (a contact at a node), else `None`.
    pub fn single(&self) -> Option<usize> {
        (self.len == 1 && self.weights[0] == 1.0).then_some(self.nodes[0])
    }

    /// The lowest and highest node index of the stencil.
    pub fn span(&self) -> (usize, usize) {
        let n = &self.nodes[..self.len];
        (
            *n.iter().min().expect("a stencil has a node"),
            *n.iter().max().expect("a stencil has a node"),
        )
    }

    /// The point's position in `q`. The first node's term is taken as it is and the others
    /// added to it, so a one-node stencil of weight 1 gives the node's coordinates exactly.
    pub fn position(&self, q: &[f64]) -> [f64; 3] {
        let at = |i: usize, w: f64| {
            let k = dof::node(i);
            [w * q[k], w * q[k + 1], w * q[k + 2]]
        };
        let mut x = at(self.nodes[0], self.weights[0]);
        for k in 1..self.len {
            x = f::add(x, at(self.nodes[k], self.weights[k]));
        }
        x
    }

    /// Add the force `force` acting at the point to the nodes' coordinates of `out` (indexed
    /// like `q`): `w_i force` on node `i`, the transpose of [`Stencil::position`].
    pub fn spread(&self, force: [f64; 3], out: &mut [f64]) {
        for (i, w) in self.iter() {
            let k = dof::node(i);
            for a in 0..3 {
                out[k + a] += w * force[a];
            }
        }
    }
}

/// A contact's frame, frozen at the start of a step: forward `f` (the body tangent projected
/// on the ground, toward the head), sideways `s = e_z x f`, and the ground's normal `e_z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Forward, on the ground.
    pub forward: [f64; 3],
    /// Sideways, on the ground.
    pub side: [f64; 3],
    /// The ground's normal, `e_z`.
    pub normal: [f64; 3],
}

impl Frame {
    /// The frame whose forward direction is the ground projection of `tangent` (`e_x` where
    /// that vanishes).
    pub fn from_tangent(tangent: [f64; 3]) -> Self {
        let mut fw = [tangent[0], tangent[1], 0.0];
        if f::norm(fw) < 1e-12 {
            fw = [1.0, 0.0, 0.0];
        }
        let fw = f::unit(fw);
        Frame {
            forward: fw,
            side: f::cross([0.0, 0.0, 1.0], fw),
            normal: [0.0, 0.0, 1.0],
        }
    }

    /// A world `(x, y)` vector in `(forward, side)` components.
    pub fn to_local(&self, xy: [f64; 2]) -> [f64; 2] {
        let (f, s) = (self.forward, self.side);
        [xy[0] * f[0] + xy[1] * f[1], xy[0] * s[0] + xy[1] * s[1]]
    }

    /// A `(forward, side)` vector as world `(x, y)`.
    pub fn to_world(&self, fs: [f64; 2]) -> [f64; 2] {
        let (f, s) = (self.forward, self.side);
        [fs[0] * f[0] + fs[1] * s[0], fs[0] * f[1] + fs[1] * s[1]]
    }
}

/// One contact: where it is on the body, its frame, its slip origin and its friction law.
#[derive(Clone, Debug)]
pub struct Contact {
    /// The point of the body.
    pub stencil: Stencil,
    /// Its frame (set at the start of every step).
    pub frame: Frame,
    /// The point's position the slip is measured from (set at the start of every step).
    pub origin: [f64; 3],
    /// Its friction law.
    pub law: Ground,
}

impl Contact {
    /// The contact at `stencil` with friction law `law` (frame and origin set by the step).
    pub fn new(stencil: Stencil, law: Ground) -> Self {
        Contact {
            stencil,
            frame: Frame::from_tangent([1.0, 0.0, 0.0]),
            origin: [0.0; 3],
            law,
        }
    }

    /// The gap `z_c - a/2` at `q` (m) of a body of diameter `a`: the point's height over the
    /// plane `z = 0` less the body's radius.
    pub fn gap(&self, q: &[f64], a: f64) -> f64 {
        self.stencil.position(q)[2] - 0.5 * a
    }

    /// The tangential slip `(dx . f, dx . s)` at `q` since the origin (m).
    pub fn slip(&self, q: &[f64]) -> [f64; 2] {
        let dx = f::sub(self.stencil.position(q), self.origin);
        [f::dot(dx, self.frame.forward), f::dot(dx, self.frame.side)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A two-node stencil's position is the weighted sum and its spread the transpose: `F .
    /// dx_c = sum_i (spread F)_i . dx_i` for any displacement, checked on random numbers; a
    /// one-node stencil of weight 1 returns the node's coordinates bit for bit.
    #[test]
    fn a_stencil_is_linear_and_its_spread_is_the_transpose() {
        let mut seed = 7u64;
        let mut rnd = || 2.0 * crate::fd::uniform(&mut seed);
        let n = dof::count(6);
        let q: Vec<f64> = (0..n).map(|_| rnd()).collect();
        let dq: Vec<f64> = (0..n).map(|_| rnd()).collect();
        let s = Stencil::new(&[2, 3], &[0.25, 0.75]).unwrap();
        let x = s.position(&q);
        for a in 0..3 {
            let want = 0.25 * q[dof::node(2) + a] + 0.75 * q[dof::node(3) + a];
            assert!((x[a] - want).abs() <= 1e-15, "{} vs {want}", x[a]);
        }
        let q1: Vec<f64> = q.iter().zip(&dq).map(|(a, b)| a + b).collect();
        let dx = f::sub(s.position(&q1), x);
        let force = [rnd(), rnd(), rnd()];
        let mut spread = vec![0.0; n];
        s.spread(force, &mut spread);
        let work: f64 = spread.iter().zip(&dq).map(|(a, b)| a * b).sum();
        assert!(
            (work - f::dot(force, dx)).abs() <= 1e-14,
            "{work} vs {}",
            f::dot(force, dx)
        );
        assert_eq!(spread.iter().filter(|v| **v != 0.0).count(), 6);
        let one = Stencil::node(4);
        assert_eq!(one.single(), Some(4));
        assert_eq!(s.single(), None);
        let k = dof::node(4);
        assert_eq!(one.position(&q), [q[k], q[k + 1], q[k + 2]]);
        assert_eq!(s.span(), (2, 3));
        assert_eq!(
            Stencil::new(&[1, 1], &[0.5, 0.5]),
            Err(StencilError::Repeated(1))
        );
        assert!(Stencil::new(&[1, 2, 3, 4, 5], &[0.2; 5]).is_err());
        assert!(Stencil::new(&[1], &[f64::NAN]).is_err());
    }
}
