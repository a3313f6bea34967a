//! Small fixed-size helpers on top of nalgebra, used by every element.
pub use nalgebra::{Matrix3, Vector3};

/// 3-vector type (SI units of whatever it holds).
pub type V3 = Vector3<f64>;
/// 3×3 matrix type.
pub type M3 = Matrix3<f64>;

/// Node `i`'s position read from `q`.
#[inline]
pub fn node(q: &[f64], i: usize) -> V3 {
    V3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2])
}

/// Skew-symmetric cross-product matrix `[a]×` with `[a]× b = a × b`.
#[inline]
pub fn skew(a: &V3) -> M3 {
    M3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Outer product `a bᵀ`.
#[inline]
pub fn outer(a: &V3, b: &V3) -> M3 {
    a * b.transpose()
}
