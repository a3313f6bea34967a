//! Second-order forward-mode automatic differentiation over a fixed number of variables: a
//! value with its gradient and Hessian, carried through `+ − × ÷` and `√` by the chain rule.
//! The contact distances are short rational expressions in 12 coordinates whose second
//! derivatives by hand are long and error-prone (IPC's line–line distance); one generic
//! formula evaluated on [`D2`] gives the exact gradient and Hessian, and the same formula on
//! `f64` gives the value alone.

use std::ops::{Add, Div, Mul, Neg, Sub};

pub(crate) use crate::real::Real;

/// `v`, `∂v/∂x_i` and `∂²v/∂x_i∂x_j` over `N` variables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct D2<const N: usize> {
    /// The value.
    pub v: f64,
    /// The gradient.
    pub g: [f64; N],
    /// The Hessian (symmetric).
    pub h: [[f64; N]; N],
}

impl<const N: usize> D2<N> {
    /// Variable `i` at value `v`: gradient `e_i`, zero Hessian.
    pub fn variable(v: f64, i: usize) -> Self {
        let mut d = Self::constant(v);
        d.g[i] = 1.0;
        d
    }

    /// `f(self)` from `f`, `f'` and `f''` at `self.v`: `∇f = f' ∇x`,
    /// `∇²f = f' ∇²x + f'' ∇x ∇xᵀ`.
    pub fn chain(self, f: f64, f1: f64, f2: f64) -> Self {
        let mut out = Self::constant(f);
        for i in 0..N {
            out.g[i] = f1 * self.g[i];
            for j in 0..N {
                out.h[i][j] = f1 * self.h[i][j] + f2 * self.g[i] * self.g[j];
            }
        }
        out
    }

    /// 1/x.
    fn recip(self) -> Self {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }
}

impl<const N: usize> D2<N> {
    /// A constant: zero gradient and Hessian.
    pub fn constant(v: f64) -> Self {
        Self {
            v,
            g: [0.0; N],
            h: [[0.0; N]; N],
        }
    }
}

impl<const N: usize> Real for D2<N> {
    fn cst(v: f64) -> Self {
        Self::constant(v)
    }
    fn val(self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v))
    }
    fn sin(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(s, c, -s)
    }
    fn cos(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(c, -s, -c)
    }
    /// atan2's derivatives are those of atan(y/x) (or of −atan(x/y) where |y| > |x|, which
    /// differs from it by a constant); its value is the quadrant-aware one.
    fn atan2(self, x: Self) -> Self {
        let atan = |u: Self| {
            let d = 1.0 + u.v * u.v;
            u.chain(u.v.atan(), 1.0 / d, -2.0 * u.v / (d * d))
        };
        let mut t = match x.v.abs() >= self.v.abs() {
            true => atan(self / x),
            false => -atan(x / self),
        };
        t.v = self.v.atan2(x.v);
        t
    }
}

impl<const N: usize> Add<f64> for D2<N> {
    type Output = Self;
    fn add(mut self, k: f64) -> Self {
        self.v += k;
        self
    }
}

impl<const N: usize> Add for D2<N> {
    type Output = Self;
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

impl<const N: usize> Neg for D2<N> {
    type Output = Self;
    fn neg(self) -> Self {
        self * -1.0
    }
}

impl<const N: usize> Sub for D2<N> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self + (-o)
    }
}

impl<const N: usize> Mul<f64> for D2<N> {
    type Output = Self;
    fn mul(mut self, k: f64) -> Self {
        self.v *= k;
        for i in 0..N {
            self.g[i] *= k;
            for j in 0..N {
                self.h[i][j] *= k;
            }
        }
        self
    }
}

impl<const N: usize> Mul for D2<N> {
    type Output = Self;
    /// `∇(ab) = a∇b + b∇a`, `∇²(ab) = a∇²b + b∇²a + ∇a∇bᵀ + ∇b∇aᵀ`.
    fn mul(self, o: Self) -> Self {
        let mut out = Self::constant(self.v * o.v);
        for i in 0..N {
            out.g[i] = self.g[i] * o.v + o.g[i] * self.v;
            for j in 0..N {
                out.h[i][j] = self.h[i][j] * o.v
                    + o.h[i][j] * self.v
                    + self.g[i] * o.g[j]
                    + o.g[i] * self.g[j];
            }
        }
        out
    }
}

impl<const N: usize> Div for D2<N> {
    type Output = Self;
    // a/b as a × (1/b): the product rule and 1/b's chain rule give the quotient's terms.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: Self) -> Self {
        self * o.recip()
    }
}

/// The 3-vectors of the formulas.
pub type V<T> = [T; 3];

/// `a − b`.
pub(crate) fn sub<T: Real>(a: V<T>, b: V<T>) -> V<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a · b`.
pub(crate) fn dot<T: Real>(a: V<T>, b: V<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `|a|`.
pub(crate) fn norm(a: V<f64>) -> f64 {
    dot(a, a).sqrt()
}

/// Node `i` of positions `x` (3 per node).
pub(crate) fn node(x: &[f64], i: usize) -> V<f64> {
    [x[3 * i], x[3 * i + 1], x[3 * i + 2]]
}

/// `a × b`.
pub(crate) fn cross<T: Real>(a: V<T>, b: V<T>) -> V<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The four points of a 12-coordinate stencil as variables 0–11.
pub fn variables(x: &[f64; 12]) -> [V<D2<12>>; 4] {
    std::array::from_fn(|k| std::array::from_fn(|d| D2::variable(x[3 * k + d], 3 * k + d)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f(x, y) = x² y / (1 + y) + √(x + 2 y): the derivatives against their closed forms.
    #[test]
    fn products_quotients_and_roots_carry_exact_derivatives() {
        let (x0, y0) = (0.7, 1.3);
        let (x, y) = (D2::<2>::variable(x0, 0), D2::<2>::variable(y0, 1));
        let one = D2::constant(1.0);
        let f = x * x * y / (one + y) + (x + y * 2.0).sqrt();
        let s = (x0 + 2.0 * y0).sqrt();
        let q = y0 / (1.0 + y0);
        let dq = 1.0 / (1.0 + y0).powi(2);
        let want_g = [2.0 * x0 * q + 0.5 / s, x0 * x0 * dq + 1.0 / s];
        let d2q = -2.0 / (1.0 + y0).powi(3);
        let r = -0.25 / (s * s * s);
        let want_h = [
            [2.0 * q + r, 2.0 * x0 * dq + 2.0 * r],
            [2.0 * x0 * dq + 2.0 * r, x0 * x0 * d2q + 4.0 * r],
        ];
        assert!((f.v - (x0 * x0 * q + s)).abs() < 1e-15);
        for i in 0..2 {
            assert!((f.g[i] - want_g[i]).abs() < 1e-14, "{:?}", f.g);
            for j in 0..2 {
                assert!((f.h[i][j] - want_h[i][j]).abs() < 1e-14, "{:?}", f.h);
            }
        }
    }

    /// atan2 in every quadrant (both branches) and sin, cos: gradient and Hessian against
    /// central differences of the same formula on f64 (step 1e-5: truncation ~1e-10).
    #[test]
    fn atan2_sin_and_cos_carry_exact_derivatives() {
        fn f<T: Real>(x: T, y: T) -> T {
            y.atan2(x) + x.sin() * y.cos() + 0.5
        }
        let h = 1e-5;
        for (x0, y0) in [(0.8, 0.3), (-0.4, 0.9), (-0.7, -0.2), (0.1, -1.3)] {
            let d = f(D2::<2>::variable(x0, 0), D2::<2>::variable(y0, 1));
            assert!((d.v - f(x0, y0)).abs() < 1e-15);
            let g = |x: f64, y: f64| {
                let d = f(D2::<2>::variable(x, 0), D2::<2>::variable(y, 1));
                d.g
            };
            let fd = [
                (f(x0 + h, y0) - f(x0 - h, y0)) / (2.0 * h),
                (f(x0, y0 + h) - f(x0, y0 - h)) / (2.0 * h),
            ];
            let hd = [
                [g(x0 + h, y0), g(x0 - h, y0)],
                [g(x0, y0 + h), g(x0, y0 - h)],
            ];
            for i in 0..2 {
                assert!((d.g[i] - fd[i]).abs() < 1e-8, "({x0}, {y0}) ∂{i}");
                for j in 0..2 {
                    let want = (hd[i][0][j] - hd[i][1][j]) / (2.0 * h);
                    assert!((d.h[i][j] - want).abs() < 1e-7, "({x0}, {y0}) ∂²{i}{j}");
                }
            }
        }
    }
}
