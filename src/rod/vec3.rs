//! A 3-vector generic over the scalar, so that one stencil energy serves both plain
//! evaluation (`f64`) and exact automatic second derivatives (`num_dual::Dual2Vec`).

use num_dual::DualNum;

/// A 3-vector with components of type `T` (`f64` or a dual number).
#[derive(Clone, Debug, PartialEq)]
pub struct V3<T>(pub [T; 3]);

impl<T: DualNum<Primitive = f64>> V3<T> {
    /// Lift a plain vector into the scalar type `T` (constant, zero derivatives).
    pub fn lift(v: [f64; 3]) -> Self {
        V3([T::from(v[0]), T::from(v[1]), T::from(v[2])])
    }
    /// Dot product.
    pub fn dot(&self, o: &Self) -> T {
        self.0[0].clone() * o.0[0].clone()
            + self.0[1].clone() * o.0[1].clone()
            + self.0[2].clone() * o.0[2].clone()
    }
    /// Cross product.
    pub fn cross(&self, o: &Self) -> Self {
        let [a0, a1, a2] = &self.0;
        let [b0, b1, b2] = &o.0;
        V3([
            a1.clone() * b2.clone() - a2.clone() * b1.clone(),
            a2.clone() * b0.clone() - a0.clone() * b2.clone(),
            a0.clone() * b1.clone() - a1.clone() * b0.clone(),
        ])
    }
    /// Sum.
    pub fn add(&self, o: &Self) -> Self {
        V3([
            self.0[0].clone() + o.0[0].clone(),
            self.0[1].clone() + o.0[1].clone(),
            self.0[2].clone() + o.0[2].clone(),
        ])
    }
    /// Difference.
    pub fn sub(&self, o: &Self) -> Self {
        V3([
            self.0[0].clone() - o.0[0].clone(),
            self.0[1].clone() - o.0[1].clone(),
            self.0[2].clone() - o.0[2].clone(),
        ])
    }
    /// Scale by a scalar of the same type.
    pub fn scale(&self, s: &T) -> Self {
        V3([
            self.0[0].clone() * s.clone(),
            self.0[1].clone() * s.clone(),
            self.0[2].clone() * s.clone(),
        ])
    }
    /// Euclidean norm.
    pub fn norm(&self) -> T {
        self.dot(self).sqrt()
    }
}

/// Parallel transport of `u` from unit tangent `t1` to unit tangent `t2`: the rotation about
/// `t1 x t2` that takes `t1` to `t2`, in the closed form
/// `P u = c u + v x u + (v.u) v / (1 + c)` with `c = t1.t2`, `v = t1 x t2`
/// (smooth everywhere except `t2 = -t1`).
pub fn transport<T: DualNum<Primitive = f64>>(t1: &V3<T>, t2: &V3<T>, u: &V3<T>) -> V3<T> {
    let c = t1.dot(t2);
    let v = t1.cross(t2);
    let vu = v.dot(u);
    let k = vu / (c.clone() + 1.0);
    u.scale(&c).add(&v.cross(u)).add(&v.scale(&k))
}

/// Plain-`f64` helpers used outside the stencils.
pub mod f {
    /// Dot product.
    pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }
    /// Cross product.
    pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
    /// Difference.
    pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
    /// Sum.
    pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
    }
    /// Scale.
    pub fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
        [a[0] * s, a[1] * s, a[2] * s]
    }
    /// Norm.
    pub fn norm(a: [f64; 3]) -> f64 {
        dot(a, a).sqrt()
    }
    /// Unit vector.
    pub fn unit(a: [f64; 3]) -> [f64; 3] {
        scale(a, 1.0 / norm(a))
    }
    /// Parallel transport (see [`super::transport`]).
    pub fn transport(t1: [f64; 3], t2: [f64; 3], u: [f64; 3]) -> [f64; 3] {
        let c = dot(t1, t2);
        let v = cross(t1, t2);
        let k = dot(v, u) / (1.0 + c);
        add(add(scale(u, c), cross(v, u)), scale(v, k))
    }
}
