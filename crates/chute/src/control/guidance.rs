//! Guidance to a target on the ground by line pulls: a proportional law on the predicted miss.
//!
//! Every `update_s` the controller predicts where the payload would land if it kept its
//! current velocity, `p̂ = x_h + v_h t_go` with `t_go = h / max(−v_z, V_MIN)` (h the height
//! above the ground), and takes the miss `e = T − p̂` to the target `T`. It pulls by
//! `u = min(max_pull, gain |e|)` so that the canopy's predicted glide change points along `ê`:
//! with the response model `Δv_h = S p` of [`super::response`] (`S = k R(θ)`, `p` the pull
//! vector), the pull direction is `p̂ = R(−θ) ê`, and line `i`, whose site lies in the
//! horizontal direction `d̂_i` from the sites' centroid, gets `u_i = u · max(0, d̂_i · p̂)`.
//! `pull_side = "towards"` is `θ = 0` (the lines on the target's side: a flat square glides
//! towards its pulled side), `"away"` is `θ = π` (the far side), and `"shape"` (the default)
//! takes the measured response of the canopy's outline (rectangle: towards; circle: away).
//! Each decision ramps the lines from their current shortening to the new one over `ramp_s`.
//!
//! The controller holds no state of its own: its commands are the history of the lines'
//! stretching family (the time of the last decision included), which checkpoints carry, and a
//! decision depends only on the state and that history. A resumed run therefore decides
//! exactly as the uninterrupted one.
use crate::build::control::Lines;
use crate::build::Built;
use crate::control::response::{centroid, Response};
use crate::scenario::{CanopyShape, Guidance, ShellDrag};
use engine::rod::Command;

/// Smallest descent rate used for the time to go (m/s): a canopy not (yet) descending is
/// treated as descending slowly rather than dividing by zero.
pub const V_MIN: f64 = 0.1;

/// The guidance law of one run.
#[derive(Debug, Clone)]
pub struct Controller {
    target: [f64; 2],
    max_pull: f64,
    gain: f64,
    update_s: f64,
    ramp_s: f64,
    ground_z: f64,
    /// The canopy's response to pulls, inverted to choose the pull direction.
    response: Response,
}

/// One decision: the predicted landing point, the miss, and the pull of each line.
#[derive(Debug, Clone, PartialEq)]
pub struct Decision {
    /// Predicted landing point `p̂` (m).
    pub predicted_m: [f64; 2],
    /// Miss `T − p̂` (m).
    pub miss_m: [f64; 2],
    /// Shortening commanded for each line (m).
    pub pulls_m: Vec<f64>,
}

impl Controller {
    /// The controller of guidance `g` for a canopy of outline `shape` under the pressure law
    /// `law`, with ground at model height `ground_z` (m); `None` without a response for its
    /// `pull_side` (which the scenario check refuses).
    pub fn new(g: &Guidance, shape: CanopyShape, law: ShellDrag, ground_z: f64) -> Option<Self> {
        Some(Self {
            response: Response::of(g.pull_side, shape, law)?,
            target: [g.target_m[0], g.target_m[1]],
            max_pull: g.max_pull_m,
            gain: g.gain,
            update_s: g.update_s,
            ramp_s: g.ramp_s,
            ground_z,
        })
    }

    /// The target `[x, y]` (m).
    pub fn target(&self) -> [f64; 2] {
        self.target
    }

    /// Distance (m) from `point` `[x, y]` to the target.
    pub fn miss_m(&self, point: [f64; 2]) -> f64 {
        (point[0] - self.target[0]).hypot(point[1] - self.target[1])
    }

    /// Whether a decision is due at time `t`, `update_s` after the last one (at `t0` of the
    /// commands; the first is due at `update_s`).
    pub fn due(&self, t: f64, commands: &[Command]) -> bool {
        let last = commands.first().map_or(0.0, |c| c.t0);
        t >= last + self.update_s * (1.0 - 1e-9)
    }

    /// The decision for the payload at `x`, velocity `v` and the line sites at `sites`.
    pub fn decide(&self, x: [f64; 3], v: [f64; 3], sites: &[[f64; 3]]) -> Decision {
        let h = (x[2] - self.ground_z).max(0.0);
        let t_go = h / (-v[2]).max(V_MIN);
        let predicted_m = [x[0] + v[0] * t_go, x[1] + v[1] * t_go];
        let miss_m = [
            self.target[0] - predicted_m[0],
            self.target[1] - predicted_m[1],
        ];
        let dist = miss_m[0].hypot(miss_m[1]);
        let u = (self.gain * dist).min(self.max_pull);
        let c = centroid(sites);
        let p = self.response.pull_direction(miss_m);
        let pulls_m = sites
            .iter()
            .map(|s| {
                let d = [s[0] - c[0], s[1] - c[1]];
                let r = d[0].hypot(d[1]);
                if dist == 0.0 || r == 0.0 {
                    return 0.0;
                }
                u * ((d[0] * p[0] + d[1] * p[1]) / r).max(0.0)
            })
            .collect();
        Decision {
            predicted_m,
            miss_m,
            pulls_m,
        }
    }

    /// After an accepted step (at `built.state`): when a decision is due, decide and command the
    /// lines (ramping from their current shortening). Returns the decision taken.
    pub fn after_step(&self, built: &mut Built) -> Option<Decision> {
        let lines = built.lines.as_ref()?;
        let mut history = lines.history(&built.model);
        let state = &built.state;
        if !self.due(state.t, &history.commands) {
            return None;
        }
        let p = built.payload_node?;
        let node = |v: &[f64], i: usize| [v[3 * i], v[3 * i + 1], v[3 * i + 2]];
        let sites: Vec<[f64; 3]> = lines.lines.iter().map(|l| node(&state.q, l.site)).collect();
        let d = self.decide(node(&state.q, p), node(&state.v, p), &sites);
        self.command(lines, &mut history.commands, &d, state.t);
        lines.set_history(&mut built.model, &history);
        Some(d)
    }

    /// The new commands: each line ramps from its shortening at `t` to its decided pull.
    fn command(&self, lines: &Lines, commands: &mut [Command], d: &Decision, t: f64) {
        for (line, &u) in lines.lines.iter().zip(&d.pulls_m) {
            if let Some((_, k)) = &line.schedule {
                let now = commands[*k].at(t, self.ramp_s);
                commands[*k] = Command {
                    from: now,
                    to: u,
                    t0: t,
                };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn controller() -> Controller {
        Controller {
            target: [10.0, 0.0],
            max_pull: 0.3,
            gain: 0.05,
            update_s: 0.5,
            ramp_s: 0.25,
            ground_z: -30.0,
            response: Response::towards(1.0),
        }
    }

    /// Four sites on ±x, ±y around the payload.
    const SITES: [[f64; 3]; 4] = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
    ];

    #[test]
    fn pulls_the_lines_facing_the_predicted_miss() {
        let c = controller();
        // 30 m up at 5 m/s: 6 s to go; drifting at 1 m/s along +y lands at (0, 6).
        let d = c.decide([0.0, 0.0, 0.0], [0.0, 1.0, -5.0], &SITES);
        assert!((d.predicted_m[1] - 6.0).abs() < 1e-12);
        assert_eq!(d.miss_m, [10.0, -6.0]);
        let u = (0.05 * 136f64.sqrt()).min(0.3);
        let e = [10.0 / 136f64.sqrt(), -6.0 / 136f64.sqrt()];
        let want = [u * e[0], 0.0, 0.0, -u * e[1]];
        for (got, want) in d.pulls_m.iter().zip(want) {
            assert!((got - want).abs() < 1e-12, "{:?}", d.pulls_m);
        }
        // On target: nothing to pull; far away: saturated at max_pull.
        let d = c.decide([10.0, 0.0, 0.0], [0.0, 0.0, -5.0], &SITES);
        assert!(d.pulls_m.iter().all(|&u| u == 0.0));
        let d = c.decide([-100.0, 0.0, 0.0], [0.0, 0.0, -5.0], &SITES);
        assert_eq!(d.pulls_m, [0.3, 0.0, 0.0, 0.0]);
        // Pulling the far side instead: the line facing away.
        let away = Controller {
            response: Response::away(1.0),
            ..c
        };
        let d = away.decide([-100.0, 0.0, 0.0], [0.0, 0.0, -5.0], &SITES);
        assert_eq!(d.pulls_m, [0.0, 0.0, 0.3, 0.0]);
    }

    #[test]
    fn decisions_are_due_every_update_after_the_last() {
        let c = controller();
        let at = |t0| {
            [Command {
                from: 0.0,
                to: 0.1,
                t0,
            }]
        };
        assert!(!c.due(0.4, &at(0.0)));
        assert!(c.due(0.5, &at(0.0)));
        assert!(!c.due(0.9, &at(0.5)));
        assert!(c.due(1.0, &at(0.5)));
    }
}
