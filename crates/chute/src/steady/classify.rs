//! A mode shape in a designer's words: how much of its kinetic energy is the body's rigid
//! motion (sideways or vertical translation, tilt, spin) and how much deformation.

use engine::stability::Mode;
use faer::c64;
use nalgebra::{Matrix3, Vector3};

/// Shares of a mode's kinetic energy `Σ mᵢ |φᵢ|²` (each in [0, 1], summing to 1).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Shares {
    /// Rigid translation across the descent (x, y).
    pub lateral: f64,
    /// Rigid translation along z.
    pub vertical: f64,
    /// Rigid rotation about a horizontal axis through the centre of mass (tilt, swing).
    pub tilt: f64,
    /// Rigid rotation about the vertical axis (spin).
    pub spin: f64,
    /// What no rigid motion explains (breathing, folding, line stretch).
    pub deformation: f64,
}

/// `|λ|` below this (1/s) is a neutral mode: a change of position or heading that neither
/// grows nor decays.
pub const NEUTRAL: f64 = engine::stability::NEUTRAL_RATE;

/// The energy shares of `mode` for nodes at `q` with lumped masses `mass` (per DOF).
pub fn shares(mode: &Mode, q: &[f64], mass: &[f64], n_nodes: usize) -> Shares {
    let node = |i: usize| Vector3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2]);
    let phi = |i: usize| [0, 1, 2].map(|k| mode.shape[3 * i + k]);
    let m = |i: usize| mass[3 * i];
    let total_m: f64 = (0..n_nodes).map(m).sum();
    let centre = (0..n_nodes).map(|i| m(i) * node(i)).sum::<Vector3<f64>>() / total_m;
    // Real and imaginary parts separately: each is a real displacement field.
    let mut e = [0.0; 5];
    let mut total = 0.0;
    let parts: [fn(c64) -> f64; 2] = [|z| z.re, |z| z.im];
    for part in parts {
        let u = |i: usize| Vector3::from(phi(i).map(part));
        let t = (0..n_nodes).map(|i| m(i) * u(i)).sum::<Vector3<f64>>() / total_m;
        let mut inertia = Matrix3::zeros();
        let mut moment = Vector3::zeros();
        for i in 0..n_nodes {
            let r = node(i) - centre;
            inertia += m(i) * (Matrix3::identity() * r.dot(&r) - r * r.transpose());
            moment += m(i) * r.cross(&(u(i) - t));
        }
        let omega = inertia
            .try_inverse()
            .map_or(Vector3::zeros(), |inv| inv * moment);
        let horizontal = Vector3::new(omega.x, omega.y, 0.0);
        let about_z = Vector3::new(0.0, 0.0, omega.z);
        e[0] += total_m * (t.x * t.x + t.y * t.y);
        e[1] += total_m * t.z * t.z;
        e[2] += horizontal.dot(&(inertia * horizontal));
        e[3] += about_z.dot(&(inertia * about_z));
        total += (0..n_nodes)
            .map(|i| m(i) * u(i).norm_squared())
            .sum::<f64>();
    }
    let rigid: f64 = e[..4].iter().sum();
    let s = |x: f64| if total > 0.0 { x / total } else { 0.0 };
    Shares {
        lateral: s(e[0]),
        vertical: s(e[1]),
        tilt: s(e[2]),
        spin: s(e[3]),
        deformation: s((total - rigid).max(0.0)),
    }
}

/// A one-line description of a mode with eigenvalue `lambda` and energy shares `s`.
pub fn describe(lambda: c64, s: &Shares) -> String {
    let neutral = lambda.norm() < NEUTRAL;
    let oscillating = lambda.im.abs() > NEUTRAL;
    let kinds = [
        (
            s.lateral,
            [
                "sideways position",
                "sideways drift",
                "sideways oscillation",
            ],
        ),
        (
            s.vertical,
            ["height", "descent-speed change", "vertical oscillation"],
        ),
        (s.tilt, ["attitude", "tilt", "swing (pendulum)"]),
        (s.spin, ["heading", "spin", "yaw oscillation"]),
        (
            s.deformation,
            [
                "shape",
                "deformation (breathing, folding)",
                "oscillating deformation",
            ],
        ),
    ];
    let (share, names) = kinds
        .into_iter()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or((0.0, ["", "", ""]));
    let (behaviour, name) = match (neutral, oscillating) {
        (true, _) => ("neutral", names[0]),
        (false, false) => (if lambda.re > 0.0 { "grows" } else { "decays" }, names[1]),
        (false, true) => (if lambda.re > 0.0 { "grows" } else { "decays" }, names[2]),
    };
    format!("{behaviour}: {name} ({:.0} % of its energy)", 100.0 * share)
}
