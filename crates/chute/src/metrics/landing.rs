//! Landing: where and how fast the payload (without one, the lowest canopy node) reaches the
//! ground, interpolated between the two accepted steps around the crossing.

/// The state of the body that lands at one accepted step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Time (s).
    pub t_s: f64,
    /// Position (m, model frame).
    pub x_m: [f64; 3],
    /// Velocity (m/s).
    pub v_mps: [f64; 3],
}

/// The touchdown, linearly interpolated in time to the crossing of the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Landing {
    /// Time of the crossing (s from the start).
    pub flight_time_s: f64,
    /// Vertical velocity at the crossing (m/s; negative = descending).
    pub velocity_mps: f64,
    /// Horizontal position [x, y] at the crossing (m).
    pub point_m: [f64; 2],
}

/// Watches the landing body step by step for the first crossing of the ground height.
#[derive(Debug, Clone)]
pub struct GroundWatch {
    ground_z_m: f64,
    last: Option<BodyState>,
}

impl GroundWatch {
    /// A watch for the ground at model height `ground_z_m` (m).
    pub fn new(ground_z_m: f64) -> Self {
        Self {
            ground_z_m,
            last: None,
        }
    }

    /// Record the body's state after an accepted step; the landing at the first state at or
    /// below the ground. With `z₀ > z_g ≥ z₁` on the last two states the crossing is at
    /// `α = (z₀ − z_g)/(z₀ − z₁)` of the step, and time, vertical velocity and horizontal
    /// position are interpolated linearly there (error O(dt²) of the step's curvature). A
    /// first state already on the ground lands at once.
    pub fn observe(&mut self, s: BodyState) -> Option<Landing> {
        let g = self.ground_z_m;
        let prev = self.last.replace(s);
        if s.x_m[2] > g {
            return None;
        }
        let p = prev.filter(|p| p.x_m[2] > g).unwrap_or(s);
        let dz = p.x_m[2] - s.x_m[2];
        let a = if dz > 0.0 { (p.x_m[2] - g) / dz } else { 1.0 };
        let lerp = |x0: f64, x1: f64| x0 + a * (x1 - x0);
        Some(Landing {
            flight_time_s: lerp(p.t_s, s.t_s),
            velocity_mps: lerp(p.v_mps[2], s.v_mps[2]),
            point_m: [lerp(p.x_m[0], s.x_m[0]), lerp(p.x_m[1], s.x_m[1])],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(t: f64, z: f64, vz: f64) -> BodyState {
        BodyState {
            t_s: t,
            x_m: [2.0 * t, -t, z],
            v_mps: [2.0, -1.0, vz],
        }
    }

    #[test]
    fn crossing_is_interpolated() {
        let mut w = GroundWatch::new(-10.0);
        assert_eq!(w.observe(at(0.0, -9.0, -4.0)), None);
        let l = w.observe(at(0.5, -11.0, -6.0)).expect("landed");
        assert!((l.flight_time_s - 0.25).abs() < 1e-15);
        assert!((l.velocity_mps + 5.0).abs() < 1e-15);
        assert_eq!(l.point_m, [0.5, -0.25]);
    }

    #[test]
    fn exactly_on_the_ground_lands_there() {
        let mut w = GroundWatch::new(0.0);
        w.observe(at(1.0, 1.0, -2.0));
        let l = w.observe(at(2.0, 0.0, -3.0)).expect("landed");
        assert_eq!((l.flight_time_s, l.velocity_mps), (2.0, -3.0));
    }
}
