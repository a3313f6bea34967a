//! The canopy's lateral response to line pulls: a 2×2 map from pull to glide, and its inverse.
//!
//! Line `i` pulled by `u_i` whose site lies in the horizontal direction `d̂_i` from the sites'
//! centroid makes the *pull vector* `p = Σ_i u_i d̂_i` (m). The response model is linear in it:
//!
//! ```text
//!     Δv_h = S p,      S = k R(θ),      R(θ) = [[cos θ, −sin θ], [sin θ, cos θ]],
//! ```
//!
//! the change of the horizontal glide velocity (m/s) in steady descent: a rotation `θ` of the
//! pull direction (0: the canopy glides towards its pulled side, π: away from it) and a gain
//! `k` ((m/s)/m). Guidance wants the glide change along the miss `ê`; inverting S gives the
//! pull direction `p̂ = S⁻¹ ê / |S⁻¹ ê| = R(−θ) ê` (the gain `k > 0` drops out of the
//! direction). The measured values (docs/control.md and docs/notes/control-2026-12.md,
//! `scenarios/control-steer.toml`):
//!
//! * the flat square on four corner lines: `θ = 0`, `k = 1.36 (m/s)/m` (lines 1 and 2 pulled
//!   by 0.3 m: `p = (0.424, 0) m`, steady `Δv_h = (+0.577, 0) m/s`);
//! * the round canopy on rim lines: `θ = π`, `k ≈ 0.7 (m/s)/m` (line 0 pulled by 0.3 m in the
//!   crosswind of control-guidance.toml: `Δv_h ≈ (−0.19, −0.09) m/s` 3.5 s after the pull),
//!   valid only for the first seconds after a pull: the glide then turns, and other lines
//!   respond differently (docs/notes/control-2026-12.md has the measurements: no fixed S
//!   fits them all);
//! * the round canopy under the inflation pressure (`fluid.shell_drag = "inflation"`):
//!   `θ = 0`, `k ≈ 2.9 (m/s)/m` (line 0 pulled by 0.3 m in still air at dt 0.005 s glides
//!   towards +x at 0.9–1.05 m/s). The open-loop response is not repeatable (other lines and
//!   other dt glide elsewhere, docs/control.md); `θ = 0` is chosen because closed-loop
//!   guidance with it lands closer on every level measured.
use crate::scenario::{CanopyShape, PullSide, ShellDrag};

/// Gain of the flat square's response ((m/s)/m of pull vector), measured (module doc).
pub const SQUARE_GAIN: f64 = 1.36;
/// Gain of the round canopy's response ((m/s)/m), measured in the first seconds (module doc).
pub const ROUND_GAIN: f64 = 0.7;
/// Gain of the round canopy's response under the inflation pressure ((m/s)/m), measured in
/// the first seconds after a pull (module doc).
pub const INFLATED_ROUND_GAIN: f64 = 2.9;

/// The map `S = k R(θ)` from pull vector to glide change.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Response {
    /// `cos θ`.
    pub cos: f64,
    /// `sin θ`.
    pub sin: f64,
    /// `k` ((m/s)/m).
    pub gain: f64,
}

impl Response {
    /// Glides towards the pulled side (`θ = 0`).
    pub const fn towards(gain: f64) -> Self {
        Self {
            cos: 1.0,
            sin: 0.0,
            gain,
        }
    }

    /// Glides away from the pulled side (`θ = π`, exactly: `cos = −1`, `sin = 0`).
    pub const fn away(gain: f64) -> Self {
        Self {
            cos: -1.0,
            sin: 0.0,
            gain,
        }
    }

    /// Any rotation `theta` (rad) and gain.
    pub fn rotation(theta: f64, gain: f64) -> Self {
        Self {
            cos: theta.cos(),
            sin: theta.sin(),
            gain,
        }
    }

    /// The response `pull_side` selects for a canopy of outline `shape` under the shell drag
    /// law `drag`, or `None` when `"shape"` has no measured response for the pair.
    pub fn of(side: PullSide, shape: CanopyShape, drag: ShellDrag) -> Option<Self> {
        if drag == ShellDrag::Incidence && side == PullSide::Shape {
            return None; // not measured under the incidence law
        }
        let inflated = matches!(drag, ShellDrag::Inflation | ShellDrag::Incidence);
        let gain = match (shape, inflated) {
            (CanopyShape::Rectangle, _) => SQUARE_GAIN,
            (_, true) => INFLATED_ROUND_GAIN,
            (_, false) => ROUND_GAIN,
        };
        match (side, shape, inflated) {
            (PullSide::Towards, _, _) => Some(Self::towards(gain)),
            (PullSide::Away, _, _) => Some(Self::away(gain)),
            (PullSide::Shape, CanopyShape::Rectangle, false) => Some(Self::towards(gain)),
            (PullSide::Shape, CanopyShape::Circle, false) => Some(Self::away(gain)),
            (PullSide::Shape, CanopyShape::Circle, true) => Some(Self::towards(gain)),
            (PullSide::Shape, _, _) => None,
        }
    }

    /// The predicted glide change `S p` (m/s) of the pull vector `p` (m).
    pub fn glide(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.gain * (self.cos * p[0] - self.sin * p[1]),
            self.gain * (self.sin * p[0] + self.cos * p[1]),
        ]
    }

    /// The unit pull direction whose predicted glide points along `e` (`R(−θ) ê`), or zero
    /// for `e = 0`.
    pub fn pull_direction(&self, e: [f64; 2]) -> [f64; 2] {
        let n = e[0].hypot(e[1]);
        if n == 0.0 {
            return [0.0; 2];
        }
        let (x, y) = (e[0] / n, e[1] / n);
        [self.cos * x + self.sin * y, -self.sin * x + self.cos * y]
    }
}

/// The pull vector `Σ u_i d̂_i` (m) of pulls `u` on lines whose sites lie at `sites`.
pub fn pull_vector(sites: &[[f64; 3]], u: &[f64]) -> [f64; 2] {
    let c = centroid(sites);
    let mut p = [0.0; 2];
    for (s, &u) in sites.iter().zip(u) {
        let d = [s[0] - c[0], s[1] - c[1]];
        let r = d[0].hypot(d[1]);
        if r > 0.0 {
            p[0] += u * d[0] / r;
            p[1] += u * d[1] / r;
        }
    }
    p
}

/// Horizontal centroid of `sites`.
pub fn centroid(sites: &[[f64; 3]]) -> [f64; 2] {
    let n = sites.len().max(1) as f64;
    [0, 1].map(|k| sites.iter().map(|p| p[k]).sum::<f64>() / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inverse is exact: the predicted glide of the chosen pull direction points along
    /// the requested one, for any rotation; mirrored requests give mirrored pulls when the
    /// response has no handedness (θ = 0 or π).
    #[test]
    fn the_pull_direction_inverts_the_response() {
        for theta in [0.0, 0.7, -2.0, std::f64::consts::PI] {
            let r = Response::rotation(theta, 0.5);
            for e in [[1.0, 0.0], [3.0, -4.0], [-0.2, 0.9]] {
                let g = r.glide(r.pull_direction(e));
                let cross = g[0] * e[1] - g[1] * e[0];
                assert!(cross.abs() < 1e-14 && g[0] * e[0] + g[1] * e[1] > 0.0);
                assert!((g[0].hypot(g[1]) - 0.5).abs() < 1e-14, "{g:?} for {e:?}");
            }
        }
        let away = Response::away(1.0);
        assert_eq!(away.pull_direction([3.0, -4.0]), [-0.6, 0.8]);
        assert_eq!(away.pull_direction([3.0, 4.0]), [-0.6, -0.8]);
        assert_eq!(
            Response::towards(1.0).pull_direction([0.0, 2.0]),
            [0.0, 1.0]
        );
        assert_eq!(away.pull_direction([0.0, 0.0]), [0.0, 0.0]);
    }

    #[test]
    fn the_pull_vector_of_one_line_points_at_its_site() {
        let sites = [
            [2.0, 1.0, 5.0],
            [0.0, 1.0, 5.0],
            [1.0, 2.0, 0.0],
            [1.0, 0.0, 0.0],
        ];
        assert_eq!(pull_vector(&sites, &[0.3, 0.0, 0.0, 0.0]), [0.3, 0.0]);
        assert_eq!(pull_vector(&sites, &[0.1, 0.1, 0.1, 0.1]), [0.0, 0.0]);
    }

    #[test]
    fn shape_picks_the_measured_response_of_each_outline_and_law() {
        let of = |s| Response::of(PullSide::Shape, s, ShellDrag::Report);
        assert_eq!(
            of(CanopyShape::Rectangle),
            Some(Response::towards(SQUARE_GAIN))
        );
        assert_eq!(of(CanopyShape::Circle), Some(Response::away(ROUND_GAIN)));
        assert_eq!(of(CanopyShape::Hexagon), None);
        assert_eq!(of(CanopyShape::Mesh), None);
        // Inflated, the round canopy glides towards its pulled side; the square under that
        // law is not measured.
        let inflated = |s| Response::of(PullSide::Shape, s, ShellDrag::Inflation);
        assert_eq!(
            inflated(CanopyShape::Circle),
            Some(Response::towards(INFLATED_ROUND_GAIN))
        );
        assert_eq!(inflated(CanopyShape::Rectangle), None);
        let away = Response::of(PullSide::Away, CanopyShape::Mesh, ShellDrag::Report).unwrap();
        assert_eq!((away.cos, away.sin), (-1.0, 0.0));
    }
}
