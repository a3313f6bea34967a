//! Forward-mode automatic differentiation for the rod kernels.
//!
//! The bend–twist gradient is written in closed form (Bergou et al. 2008, plus the exact
//! frame-transport terms, see `bend_twist`), once, generically over a [`Real`] scalar. Run
//! with `f64` it gives the energy gradient; run with [`Dual`] numbers seeded on the local
//! variables it gives the *exact* Hessian (the derivative of the closed-form gradient) in
//! one pass, so the Hessian can never drift from the gradient.
//!
//! [`G3`] is a minimal 3-vector over any [`Real`] (nalgebra's vectors need more traits than
//! a dual number is worth implementing).

use std::ops::{Add, Div, Mul, Neg, Sub};

pub(crate) use crate::real::Real;

/// A dual number `v + Σ d_i ε_i` with `N` independent infinitesimals.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dual<const N: usize> {
    /// Value.
    pub v: f64,
    /// Derivatives with respect to the `N` seeded variables.
    pub d: [f64; N],
}

impl<const N: usize> Dual<N> {
    /// The `i`-th independent variable with value `v`.
    #[inline]
    pub fn var(v: f64, i: usize) -> Self {
        let mut d = [0.0; N];
        d[i] = 1.0;
        Self { v, d }
    }
    /// `f(v)` with derivative `df = f'(v)`.
    #[inline]
    fn chain(self, f: f64, df: f64) -> Self {
        let mut d = self.d;
        for x in d.iter_mut() {
            *x *= df;
        }
        Self { v: f, d }
    }
}

/// `+` and `−`: value and derivatives combine alike.
macro_rules! linear_op {
    ($trait:ident, $method:ident, $op:tt, $assign:tt) => {
        impl<const N: usize> $trait for Dual<N> {
            type Output = Self;
            #[inline]
            fn $method(self, o: Self) -> Self {
                let mut d = self.d;
                for (x, y) in d.iter_mut().zip(&o.d) {
                    *x $assign y;
                }
                Self { v: self.v $op o.v, d }
            }
        }
    };
}
linear_op!(Add, add, +, +=);
linear_op!(Sub, sub, -, -=);
impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut d = [0.0; N];
        for i in 0..N {
            d[i] = self.d[i] * o.v + self.v * o.d[i];
        }
        Self { v: self.v * o.v, d }
    }
}
impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    #[inline]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.v;
        let v = self.v * inv;
        let mut d = [0.0; N];
        for i in 0..N {
            d[i] = (self.d[i] - v * o.d[i]) * inv;
        }
        Self { v, d }
    }
}
impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self.chain(-self.v, -1.0)
    }
}
impl<const N: usize> Mul<f64> for Dual<N> {
    type Output = Self;
    #[inline]
    fn mul(self, s: f64) -> Self {
        self.chain(self.v * s, s)
    }
}
impl<const N: usize> Add<f64> for Dual<N> {
    type Output = Self;
    #[inline]
    fn add(self, s: f64) -> Self {
        Self {
            v: self.v + s,
            d: self.d,
        }
    }
}

impl<const N: usize> Real for Dual<N> {
    #[inline]
    fn cst(x: f64) -> Self {
        Self { v: x, d: [0.0; N] }
    }
    #[inline]
    fn val(self) -> f64 {
        self.v
    }
    #[inline]
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s)
    }
    #[inline]
    fn sin(self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }
    #[inline]
    fn cos(self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        // d atan2(y, x) = (x dy − y dx) / (x² + y²)
        let r2 = x.v * x.v + self.v * self.v;
        let mut d = [0.0; N];
        for i in 0..N {
            d[i] = (x.v * self.d[i] - self.v * x.d[i]) / r2;
        }
        Self {
            v: self.v.atan2(x.v),
            d,
        }
    }
}

/// A 3-vector over any [`Real`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct G3<T>(pub [T; 3]);

impl<T: Real> G3<T> {
    /// Lift an `f64` vector to constants.
    #[inline]
    pub fn cst(v: &crate::vec3::V3) -> Self {
        Self([T::cst(v.x), T::cst(v.y), T::cst(v.z)])
    }
    /// Values as an nalgebra vector.
    #[inline]
    pub fn val(&self) -> crate::vec3::V3 {
        crate::vec3::V3::new(self.0[0].val(), self.0[1].val(), self.0[2].val())
    }
    #[inline]
    pub fn dot(&self, o: &Self) -> T {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }
    #[inline]
    pub fn cross(&self, o: &Self) -> Self {
        let (a, b) = (&self.0, &o.0);
        Self([
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ])
    }
    #[inline]
    pub fn norm(&self) -> T {
        self.dot(self).sqrt()
    }
    /// `self · s` for a scalar `s`.
    #[inline]
    pub fn scale(&self, s: T) -> Self {
        Self([self.0[0] * s, self.0[1] * s, self.0[2] * s])
    }
}

impl<T: Real> Add for G3<T> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
}
impl<T: Real> Sub for G3<T> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }
}
impl<T: Real> Neg for G3<T> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self([-self.0[0], -self.0[1], -self.0[2]])
    }
}
impl<T: Real> Mul<f64> for G3<T> {
    type Output = Self;
    #[inline]
    fn mul(self, s: f64) -> Self {
        Self([self.0[0] * s, self.0[1] * s, self.0[2] * s])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dual_chain_rules() {
        let x = Dual::<2>::var(0.7, 0);
        let y = Dual::<2>::var(-1.3, 1);
        let f = (x * y).sin() / (x * x + y * y).sqrt() + y.atan2(x) * 3.0;
        let h = 1e-6;
        let ff = |x: f64, y: f64| (x * y).sin() / (x * x + y * y).sqrt() + 3.0 * y.atan2(x);
        let dx = (ff(0.7 + h, -1.3) - ff(0.7 - h, -1.3)) / (2.0 * h);
        let dy = (ff(0.7, -1.3 + h) - ff(0.7, -1.3 - h)) / (2.0 * h);
        assert!((f.d[0] - dx).abs() < 1e-8 && (f.d[1] - dy).abs() < 1e-8);
    }
}
