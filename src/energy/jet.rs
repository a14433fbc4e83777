//! Second-order forward-mode numbers ("jets") with a fixed number `N` of variables: value,
//! gradient and full (symmetric) Hessian in plain arrays, so that the stencils can be
//! differentiated in stages over only the variables each intermediate depends on (an edge's
//! frame over its 3 edge coordinates, the curvature binormal and reference twist over the 6
//! positional coordinates, and the final strains over all 8).
//!
//! Real runs use them for the reference twist's derivatives ([`super::reftwist`]); the
//! staged stencil derivatives of the references are built from them.

use std::ops::{Add, Mul, Neg, Sub};

/// Value, gradient and Hessian of a scalar function of `N` variables.
#[derive(Clone, Copy, Debug)]
pub struct Jet<const N: usize> {
    /// Value.
    pub v: f64,
    /// Gradient.
    pub g: [f64; N],
    /// Hessian (full, symmetric).
    pub h: [[f64; N]; N],
}

impl<const N: usize> Jet<N> {
    /// A constant.
    #[inline(always)]
    pub fn cst(v: f64) -> Self {
        Jet {
            v,
            g: [0.0; N],
            h: [[0.0; N]; N],
        }
    }
    /// Variable `k` with value `v`.
    #[inline(always)]
    pub fn var(v: f64, k: usize) -> Self {
        let mut j = Self::cst(v);
        j.g[k] = 1.0;
        j
    }
    /// `f(self)` given `f`, `f'`, `f''` at the value.
    #[inline(always)]
    pub fn chain(&self, f0: f64, f1: f64, f2: f64) -> Self {
        let mut r = Self::cst(f0);
        for i in 0..N {
            r.g[i] = f1 * self.g[i];
        }
        for i in 0..N {
            let gi = f2 * self.g[i];
            for j in 0..N {
                r.h[i][j] = f1 * self.h[i][j] + gi * self.g[j];
            }
        }
        r
    }
    /// `1 / self`.
    #[inline(always)]
    pub fn recip(&self) -> Self {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }
    /// Square root.
    #[inline(always)]
    pub fn sqrt(&self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v))
    }
    /// `(sin, cos)`.
    #[inline(always)]
    pub fn sin_cos(&self) -> (Self, Self) {
        let (s, c) = self.v.sin_cos();
        (self.chain(s, c, -s), self.chain(c, -s, -c))
    }
    /// `atan2(self, x)`.
    #[inline(always)]
    pub fn atan2(&self, x: &Self) -> Self {
        let mut r = self.atan2_derivatives(x);
        r.v = self.v.atan2(x.v);
        r
    }
    /// The gradient and Hessian of `atan2(self, x)` only (value left at 0: no `atan2`
    /// call), for a caller that takes the angle's value elsewhere.
    #[inline(always)]
    pub fn atan2_derivatives(&self, x: &Self) -> Self {
        let (yv, xv) = (self.v, x.v);
        let rho = 1.0 / (xv * xv + yv * yv);
        let fy = xv * rho;
        let fx = -yv * rho;
        let fyy = -2.0 * xv * yv * rho * rho;
        let fxx = -fyy;
        let fxy = (yv * yv - xv * xv) * rho * rho;
        let mut r = Self::cst(0.0);
        for i in 0..N {
            r.g[i] = fy * self.g[i] + fx * x.g[i];
        }
        for i in 0..N {
            let (ay, ax) = (self.g[i], x.g[i]);
            let cy = fyy * ay + fxy * ax;
            let cx = fxx * ax + fxy * ay;
            for j in 0..N {
                r.h[i][j] = fy * self.h[i][j] + fx * x.h[i][j] + cy * self.g[j] + cx * x.g[j];
            }
        }
        r
    }
    /// This jet of `M <= N` variables seen as one of `N` variables, its variables at
    /// `off..off + M`.
    #[inline(always)]
    pub fn embed<const M: usize>(a: &Jet<M>, off: usize) -> Self {
        let mut r = Self::cst(a.v);
        for i in 0..M {
            r.g[off + i] = a.g[i];
            for j in 0..M {
                r.h[off + i][off + j] = a.h[i][j];
            }
        }
        r
    }
}

impl<const N: usize> Add for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, o: Self) -> Self {
        self.v += o.v;
        for i in 0..N {
            self.g[i] += o.g[i];
            for j in 0..N {
                self.h[i][j] += o.h[i][j];
            }
        }
        self
    }
}
impl<const N: usize> Sub for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, o: Self) -> Self {
        self.v -= o.v;
        for i in 0..N {
            self.g[i] -= o.g[i];
            for j in 0..N {
                self.h[i][j] -= o.h[i][j];
            }
        }
        self
    }
}
impl<const N: usize> Neg for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self * -1.0
    }
}
impl<const N: usize> Add<f64> for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, o: f64) -> Self {
        self.v += o;
        self
    }
}
impl<const N: usize> Sub<f64> for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, o: f64) -> Self {
        self.v -= o;
        self
    }
}
impl<const N: usize> Mul<f64> for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(mut self, s: f64) -> Self {
        self.v *= s;
        for i in 0..N {
            self.g[i] *= s;
            for j in 0..N {
                self.h[i][j] *= s;
            }
        }
        self
    }
}
impl<const N: usize> Mul for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let mut r = Self::cst(self.v * o.v);
        for i in 0..N {
            r.g[i] = self.v * o.g[i] + o.v * self.g[i];
        }
        for i in 0..N {
            let (a, b) = (self.g[i], o.g[i]);
            for j in 0..N {
                r.h[i][j] = self.v * o.h[i][j] + o.v * self.h[i][j] + a * o.g[j] + b * self.g[j];
            }
        }
        r
    }
}

/// A 3-vector of jets.
pub type JV<const N: usize> = [Jet<N>; 3];

/// Constant vector.
#[inline(always)]
pub fn lift<const N: usize>(v: [f64; 3]) -> JV<N> {
    [Jet::cst(v[0]), Jet::cst(v[1]), Jet::cst(v[2])]
}
/// Dot product.
#[inline(always)]
pub fn dot<const N: usize>(a: &JV<N>, b: &JV<N>) -> Jet<N> {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// Cross product.
#[inline(always)]
pub fn cross<const N: usize>(a: &JV<N>, b: &JV<N>) -> JV<N> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// Sum.
#[inline(always)]
pub fn add<const N: usize>(a: &JV<N>, b: &JV<N>) -> JV<N> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
/// Scale by a jet.
#[inline(always)]
pub fn scale<const N: usize>(a: &JV<N>, s: &Jet<N>) -> JV<N> {
    [a[0] * *s, a[1] * *s, a[2] * *s]
}
/// Embed every component (see [`Jet::embed`]).
#[inline(always)]
pub fn embed<const M: usize, const N: usize>(a: &JV<M>, off: usize) -> JV<N> {
    [
        Jet::embed(&a[0], off),
        Jet::embed(&a[1], off),
        Jet::embed(&a[2], off),
    ]
}
/// Parallel transport of `u` from `t1` to `t2` (as [`crate::rod::vec3::transport`]).
#[inline(always)]
pub fn transport<const N: usize>(t1: &JV<N>, t2: &JV<N>, u: &JV<N>) -> JV<N> {
    let c = dot(t1, t2);
    let v = cross(t1, t2);
    let vu = dot(&v, u);
    let k = vu * (c + 1.0).recip();
    add(&add(&scale(u, &c), &cross(&v, u)), &scale(&v, &k))
}

/// Value, gradient and Hessian as nalgebra types.
pub fn to_na(j: &Jet<8>) -> (f64, nalgebra::SVector<f64, 8>, nalgebra::SMatrix<f64, 8, 8>) {
    (
        j.v,
        nalgebra::SVector::from(j.g),
        nalgebra::SMatrix::from_fn(|a, b| j.h[a][b]),
    )
}
