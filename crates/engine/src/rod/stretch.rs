//! Axial stretching of edges, shared by rods and shell edges.
//!
//! Energy of an edge `e = x₁ − x₀` with rest length `l̄` and axial stiffness `k` (N):
//! `E = ½ k ε² l̄`, `ε = |e|/l̄ − 1`. With `ê = e/|e|`:
//! - force on node 1: `f₁ = −k ε ê`, on node 0: `f₀ = +k ε ê`;
//! - `∂f₁/∂x₁ = −H`, `H = (k/l̄) ê êᵀ + (k ε/|e|)(I − ê êᵀ)`; `∂f₀/∂x₁ = +H`.
//!
//! For a rod `k = E A`; for a shell edge `k = k_s = (√3/2) E h |ē|` (see `shell`).
//!
//! **Scheduled rest lengths** (a suspension line pulled shorter): the edges of a rod with a
//! [`RestSchedule`] have `l̄(t) = l̄₀ − (l̄₀/L₀) s(t)`, where `L₀` is the rod's rest length and
//! `s(t)` its shortening at the evaluation time [`EvalInput::t`] (the end of the step). The
//! rod shortens by `s(t)` in all, every edge by the same fraction of its length. The force is
//! then an explicit function of time: at fixed `t` it is `−∇E(q; t)` (conservative; the
//! Jacobian above with `l̄(t)`), but energy is not conserved while `l̄` changes — the pull
//! does the work `∫ ∂E/∂t dt`. [`Element::add_energy`] has no time argument, so the energy is
//! taken at the time of the latest evaluation (every evaluation of one implicit Euler step
//! has the same `t`). The stepper is unaware of all this.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::element::{node_stencils, Element, Family};
use crate::force::{BlockMut, EvalInput, JacobianKind};
use crate::vec3::{node, outer, M3, V3};

/// The edge-spring law: everything is per edge, except the rest-length schedules of pulled
/// rods, the commands a controller sets and the firings of triggered pulls (the family's
/// history: see [`StretchHistory`]).
#[derive(Debug, Default)]
pub struct StretchLaw {
    schedules: Vec<RestSchedule>,
    commands: Vec<Command>,
    /// Bits of the time of the latest evaluation (for [`Element::add_energy`]).
    time_bits: AtomicU64,
}

/// Rest length and stiffness of one edge spring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeSpring {
    /// Rest length `l̄₀` (m) (at zero shortening).
    pub rest_len: f64,
    /// Axial stiffness `k` (N).
    pub stiffness: f64,
    /// The schedule this edge follows, if any.
    pub scheduled: Option<Scheduled>,
}

/// An edge's part in a rest-length schedule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scheduled {
    /// Index of the schedule (in the order given to [`Stretch::with_schedules`]).
    pub schedule: usize,
    /// Fraction of the rod's shortening taken by this edge, `l̄₀/L₀`.
    pub share: f64,
}

/// One prescribed pull: the shortening rises linearly from 0 at `start` to `shorten` at
/// `start + ramp` (a step when `ramp = 0`), and, with `hold`, falls back to 0 over the same
/// ramp from `start + ramp + hold`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pull {
    /// Start of the ramp (s).
    pub start: f64,
    /// Duration of the ramp (s), ≥ 0.
    pub ramp: f64,
    /// Shortening when fully applied (m); negative lengthens.
    pub shorten: f64,
    /// Time fully applied before the release (s); `None`: never released.
    pub hold: Option<f64>,
}

/// Fraction `∈ [0, 1]` of a linear ramp of duration `ramp` at `dt` after its start.
fn ramp_fraction(dt: f64, ramp: f64) -> f64 {
    if ramp > 0.0 {
        (dt / ramp).clamp(0.0, 1.0)
    } else if dt >= 0.0 {
        1.0
    } else {
        0.0
    }
}

impl Pull {
    /// Applied fraction of `shorten` at time `t`: exactly 0 before the start and after the
    /// release, exactly 1 while held.
    pub fn fraction(&self, t: f64) -> f64 {
        let on = ramp_fraction(t - self.start, self.ramp);
        match self.hold {
            None => on,
            Some(h) => on - ramp_fraction(t - (self.start + self.ramp + h), self.ramp),
        }
    }

    /// End of the release (s); infinite without `hold`.
    pub fn end(&self) -> f64 {
        self.hold
            .map_or(f64::INFINITY, |h| self.start + 2.0 * self.ramp + h)
    }
}

/// A shortening commanded while running (by a controller, between steps): it moves linearly
/// from `from` at `t0` to `to` at `t0 + ramp` ([`RestSchedule::command_ramp`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Command {
    /// Shortening at `t0` (m).
    pub from: f64,
    /// Shortening from `t0 + ramp` on (m).
    pub to: f64,
    /// Time the command was given (s).
    pub t0: f64,
}

impl Command {
    /// Length of one command in the family's history.
    pub const LEN: usize = 3;

    /// The commanded shortening at `t` (m).
    pub fn at(&self, t: f64, ramp: f64) -> f64 {
        self.from + (self.to - self.from) * ramp_fraction(t - self.t0, ramp)
    }
}

/// A pull that a trigger starts while running (a sensor reading judged by the application
/// between steps): it does nothing until it has fired, and then runs as `pull` from the
/// firing's start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriggeredPull {
    /// The pull; its `start` is replaced by the firing's.
    pub pull: Pull,
    /// The application's name for its trigger (chute: the `[[control]]` entry's index).
    pub source: usize,
    /// How it fired, once it has.
    pub fired: Option<Firing>,
}

/// The record of a trigger's firing, kept in the family's history so that a checkpoint carries
/// it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Firing {
    /// Start of the pull's ramp (s).
    pub start: f64,
    /// Time of the reading that fired it (s).
    pub reading_t: f64,
    /// That reading (in the sensor's unit).
    pub reading: f64,
}

impl Firing {
    /// Length of one firing in the family's history (an unfired pull has `start = ∞`).
    pub const LEN: usize = 3;
}

impl TriggeredPull {
    /// Its shortening at `t` (m): zero until fired.
    pub fn shortening(&self, t: f64) -> f64 {
        self.fired.map_or(0.0, |f| {
            let p = Pull {
                start: f.start,
                ..self.pull
            };
            p.shorten * p.fraction(t)
        })
    }
}

/// The rest-length schedule of one rod: fixed pulls, triggered pulls and a command.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RestSchedule {
    /// Prescribed pulls; they add.
    pub pulls: Vec<Pull>,
    /// Ramp of every command (s).
    pub command_ramp: f64,
    /// Pulls started by triggers; they add to the others once fired.
    pub triggered: Vec<TriggeredPull>,
}

impl RestSchedule {
    /// Shortening of the rod at `t` (m): the pulls, the fired triggered pulls and the command
    /// `cmd`.
    pub fn shortening(&self, t: f64, cmd: &Command) -> f64 {
        let pulls: f64 = self.pulls.iter().map(|p| p.shorten * p.fraction(t)).sum();
        let fired: f64 = self.triggered.iter().map(|p| p.shortening(t)).sum();
        pulls + fired + cmd.at(t, self.command_ramp)
    }
}

/// The history of a stretching family, decoded: one command per schedule, then the firings
/// of the triggered pulls (schedule by schedule, in their order).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StretchHistory {
    /// The controller's commands, one per schedule.
    pub commands: Vec<Command>,
    /// The firings of the triggered pulls (`None`: not fired).
    pub firings: Vec<Option<Firing>>,
}

impl StretchHistory {
    /// Decode `h` (a [`Stretch`]'s `history()`) of a family with `n_schedules` schedules.
    pub fn decode(h: &[f64], n_schedules: usize) -> Self {
        let (c, f) = h.split_at((Command::LEN * n_schedules).min(h.len()));
        let commands = c
            .chunks_exact(Command::LEN)
            .map(|c| Command {
                from: c[0],
                to: c[1],
                t0: c[2],
            })
            .collect();
        let firings = f
            .chunks_exact(Firing::LEN)
            .map(|f| {
                (f[0] != f64::INFINITY).then_some(Firing {
                    start: f[0],
                    reading_t: f[1],
                    reading: f[2],
                })
            })
            .collect();
        Self { commands, firings }
    }

    /// Write the firings into the triggered pulls of `schedules` (the family's schedules, in
    /// order: the history's order of firings).
    pub fn apply_firings<'a>(&self, schedules: impl IntoIterator<Item = &'a mut RestSchedule>) {
        let slots = schedules.into_iter().flat_map(|s| &mut s.triggered);
        for (p, f) in slots.zip(&self.firings) {
            p.fired = *f;
        }
    }

    /// Encode for [`crate::Force::restore_history`].
    pub fn encode(&self) -> Vec<f64> {
        let commands = self.commands.iter().flat_map(|c| [c.from, c.to, c.t0]);
        let firings = self.firings.iter().flat_map(|f| match f {
            Some(f) => [f.start, f.reading_t, f.reading],
            None => [f64::INFINITY, 0.0, 0.0],
        });
        commands.chain(firings).collect()
    }
}

/// A family of edge springs.
pub type Stretch = Family<StretchLaw>;

impl Stretch {
    /// Springs on `edges` (node pairs) with rest lengths from `q_rest` and stiffness `k`.
    pub fn new(name: &str, edges: &[[usize; 2]], q_rest: &[f64], stiffness: Vec<f64>) -> Self {
        let rest_len = edges
            .iter()
            .map(|&[a, b]| (node(q_rest, b) - node(q_rest, a)).norm())
            .collect();
        Self::with_rest_lengths(name, edges, rest_len, stiffness)
    }

    /// Springs with explicit rest lengths.
    pub fn with_rest_lengths(
        name: &str,
        edges: &[[usize; 2]],
        rest_len: Vec<f64>,
        stiffness: Vec<f64>,
    ) -> Self {
        assert_eq!(edges.len(), rest_len.len());
        assert_eq!(edges.len(), stiffness.len());
        let scheduled = vec![None; edges.len()];
        Self::with_schedules(name, edges, rest_len, stiffness, Vec::new(), scheduled)
    }

    /// Springs with explicit rest lengths, of which the edges with `scheduled[i]` follow a
    /// schedule of `schedules` (commands start at zero).
    pub fn with_schedules(
        name: &str,
        edges: &[[usize; 2]],
        rest_len: Vec<f64>,
        stiffness: Vec<f64>,
        schedules: Vec<RestSchedule>,
        scheduled: Vec<Option<Scheduled>>,
    ) -> Self {
        assert_eq!(edges.len(), rest_len.len());
        assert_eq!(edges.len(), stiffness.len());
        assert_eq!(edges.len(), scheduled.len());
        assert!(scheduled
            .iter()
            .flatten()
            .all(|s| s.schedule < schedules.len()));
        let data = (0..edges.len())
            .map(|i| EdgeSpring {
                rest_len: rest_len[i],
                stiffness: stiffness[i],
                scheduled: scheduled[i],
            })
            .collect();
        let law = StretchLaw {
            commands: vec![Command::default(); schedules.len()],
            schedules,
            time_bits: AtomicU64::new(0.0f64.to_bits()),
        };
        Family::from_elements(name, law, node_stencils(edges), data)
    }

    /// Node indices of edge `i`.
    pub fn edge(&self, i: usize) -> [usize; 2] {
        let st = self.stencil(i);
        [st[0] / 3, st[3] / 3]
    }
}

impl StretchLaw {
    /// The rest-length schedules.
    pub fn schedules(&self) -> &[RestSchedule] {
        &self.schedules
    }

    /// The current commands, one per schedule.
    pub fn commands(&self) -> &[Command] {
        &self.commands
    }

    /// The triggered pulls, schedule by schedule (the order of their firings in the history).
    pub fn triggered(&self) -> impl Iterator<Item = &TriggeredPull> {
        self.schedules.iter().flat_map(|s| &s.triggered)
    }

    /// Rest length (m) of edge `el` at time `t`.
    pub fn rest_len(&self, el: &EdgeSpring, t: f64) -> f64 {
        match el.scheduled {
            None => el.rest_len,
            Some(s) => {
                let cmd = &self.commands[s.schedule];
                el.rest_len - s.share * self.schedules[s.schedule].shortening(t, cmd)
            }
        }
    }
}

/// Edge vector, length and strain of the edge on stencil `st`.
#[inline]
fn kinematics(q: &[f64], st: &[usize], rest: f64) -> (V3, f64, f64) {
    let e = node(q, st[3] / 3) - node(q, st[0] / 3);
    let l = e.norm();
    (e, l, l / rest - 1.0)
}

impl Element for StretchLaw {
    const STENCIL: usize = 6;
    const KIND: JacobianKind = JacobianKind::ELASTIC;
    type Data = EdgeSpring;

    fn evaluate(&self, el: &EdgeSpring, st: &[usize], input: &EvalInput<'_>, b: BlockMut<'_>) {
        if el.scheduled.is_some() {
            self.time_bits.store(input.t.to_bits(), Ordering::Relaxed);
        }
        let (k, rest) = (el.stiffness, self.rest_len(el, input.t));
        let (e, l, eps) = kinematics(input.q, st, rest);
        let t = e / l;
        let f1 = -k * eps * t;
        for c in 0..3 {
            b.f[c] = -f1[c];
            b.f[3 + c] = f1[c];
        }
        if b.dfdq.is_empty() {
            return;
        }
        let tt = outer(&t, &t);
        let h: M3 = tt * (k / rest) + (M3::identity() - tt) * (k * eps / l);
        for r in 0..3 {
            for c in 0..3 {
                let x = h[(r, c)];
                b.dfdq[r * 6 + c] = -x;
                b.dfdq[r * 6 + 3 + c] = x;
                b.dfdq[(3 + r) * 6 + c] = x;
                b.dfdq[(3 + r) * 6 + 3 + c] = -x;
            }
        }
    }

    fn add_energy(&self, el: &EdgeSpring, st: &[usize], q: &[f64], acc: &mut f64) {
        let t = f64::from_bits(self.time_bits.load(Ordering::Relaxed));
        let rest = self.rest_len(el, t);
        let (_, _, eps) = kinematics(q, st, rest);
        *acc += 0.5 * el.stiffness * eps * eps * rest;
    }

    fn history_len(&self, _n_elements: usize) -> usize {
        let triggered: usize = self.schedules.iter().map(|s| s.triggered.len()).sum();
        Command::LEN * self.commands.len() + Firing::LEN * triggered
    }

    fn history(&self, _els: &[EdgeSpring]) -> Vec<f64> {
        let firings = self.triggered().map(|p| p.fired).collect();
        StretchHistory {
            commands: self.commands.clone(),
            firings,
        }
        .encode()
    }

    fn restore_history(&mut self, _els: &mut [EdgeSpring], h: &[f64]) {
        let decoded = StretchHistory::decode(h, self.commands.len());
        decoded.apply_firings(&mut self.schedules);
        self.commands = decoded.commands;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::force::Force;

    /// A two-edge line (rest lengths 1 and 3) on one schedule: a pull of 0.8 m from t = 1
    /// over a 0.5 s ramp, held 2 s, released over 0.5 s.
    fn line() -> Stretch {
        let pull = Pull {
            start: 1.0,
            ramp: 0.5,
            shorten: 0.8,
            hold: Some(2.0),
        };
        let sch = RestSchedule {
            pulls: vec![pull],
            ..RestSchedule::default()
        };
        let part = |share| Some(Scheduled { schedule: 0, share });
        Stretch::with_schedules(
            "line",
            &[[0, 1], [1, 2]],
            vec![1.0, 3.0],
            vec![100.0, 100.0],
            vec![sch],
            vec![part(0.25), part(0.75)],
        )
    }

    #[test]
    fn rest_length_follows_ramp_hold_and_release_exactly() {
        let f = line();
        let law = f.law();
        let total = |t: f64| law.rest_len(&f.data()[0], t) + law.rest_len(&f.data()[1], t);
        // (t, shortening): before, mid-ramp, held, mid-release, after.
        let cases = [
            (0.0, 0.0),
            (0.999, 0.0),
            (1.0, 0.0),
            (1.25, 0.4),
            (1.5, 0.8),
            (3.0, 0.8),
            (3.5, 0.8),
            (3.75, 0.4),
            (4.0, 0.0),
            (9.0, 0.0),
        ];
        for (t, s) in cases {
            assert!(
                (total(t) - (4.0 - s)).abs() < 1e-15,
                "t = {t}: {}",
                total(t)
            );
            // Each edge takes its share: the line's strain is uniform.
            let ratio = law.rest_len(&f.data()[1], t) / law.rest_len(&f.data()[0], t);
            assert!((ratio - 3.0).abs() < 1e-14, "t = {t}");
        }
        assert_eq!(total(0.5), 4.0);
        assert_eq!(total(4.0), 4.0);
        assert_eq!(f.data()[0].rest_len, 1.0);
    }

    #[test]
    fn force_reads_the_evaluation_time_and_commands_ramp() {
        let mut f = line();
        // Straight along x at the rest lengths: no force before the pull, tension k·ε held.
        let q = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 4.0, 0.0, 0.0];
        let tension = |f: &Stretch, t: f64| {
            let mut b = f.new_blocks();
            let input = EvalInput::outside_step(&q, &[0.0; 9], t, false);
            f.evaluate(&input, &mut b);
            b.f[0] // pull on node 0 towards node 1 = k ε
        };
        assert_eq!(tension(&f, 0.5), 0.0);
        let eps = 1.0 / 0.8 - 1.0; // first edge: rest 1 − 0.25·0.8 = 0.8 at length 1
        assert!((tension(&f, 2.0) - 100.0 * eps).abs() < 1e-12);
        assert!(tension(&f, 5.0).abs() < 1e-12);
        // A command of 0.4 m from t0 = 5 (step: ramp 0): energy at the evaluated time.
        f.restore_history(&[0.0, 0.4, 5.0]).unwrap();
        assert_eq!(f.history(), vec![0.0, 0.4, 5.0]);
        let eps = 1.0 / 0.9 - 1.0;
        assert!((tension(&f, 5.0) - 100.0 * eps).abs() < 1e-12);
        let e = f.energy(&q).unwrap();
        let e_expected =
            0.5 * 100.0 * eps * eps * 0.9 + 0.5 * 100.0 * (3.0 / 2.7 - 1.0f64).powi(2) * 2.7;
        assert!((e - e_expected).abs() < 1e-12, "{e} vs {e_expected}");
    }
}
