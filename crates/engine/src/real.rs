//! The scalar of the formulas written once and evaluated both for values and for exact
//! derivatives (forward-mode automatic differentiation): the rod kernels' first-order dual
//! numbers (`rod::scalar`) and the contact distances' second-order numbers (`contact::ad`).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A real scalar: `f64`, or a number that carries derivatives (the rods' first-order
/// `Dual`, the contact's second-order `D2`).
pub(crate) trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
    + Add<f64, Output = Self>
{
    /// A constant.
    fn cst(x: f64) -> Self;
    /// The value (real part).
    fn val(self) -> f64;
    fn sqrt(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    /// `atan2(self, x)`.
    fn atan2(self, x: Self) -> Self;
}

impl Real for f64 {
    #[inline]
    fn cst(x: f64) -> Self {
        x
    }
    #[inline]
    fn val(self) -> f64 {
        self
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline]
    fn sin(self) -> Self {
        f64::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        f64::cos(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
}
