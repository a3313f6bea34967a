//! The checks every [`Force`] must pass, stamped on a force by
//! [`force_conformance!`](crate::force_conformance).
//!
//! On random configurations drawn by a [`Case`] (each trial builds the force afresh and
//! commits it at one random configuration, so forces with history are checked away from
//! their rest history, then evaluates it at another):
//! - [`check_energy_gradient`]: a conservative force is `−∇E` (central differences of the
//!   energy), and a force with an energy says it is conservative;
//! - [`check_jacobians`]: `∂F/∂q` and `∂F/∂v` against central differences of `F`, and a
//!   Jacobian the force does not declare is identically zero;
//! - [`check_force_only_path`]: the force-only path (`jacobian = false`, used by modified
//!   Newton) gives the full path's force to round-off;
//! - [`check_symmetry`]: a force that declares symmetric Jacobians has them;
//! - [`check_history_round_trip`]: the history restored on a freshly built force reproduces
//!   every evaluation bit for bit, and a history of the wrong length is refused.
//!
//! Finite-difference errors are relative to the largest entry of the analytic quantity (as in
//! fenris, see [`crate::fdcheck`]). With the step [`FD_STEP`] = 1e-6 on O(1) coordinates the
//! truncation error is O(h²) ≈ 1e-12 and the round-off O(1e-16/h) ≈ 1e-10, so a correct
//! derivative passes [`FD_TOL`] = 1e-6 with orders of magnitude to spare, while a missing
//! term shows up as an O(1) error.

use crate::fdcheck::{dense_eval, fd_jacobian, rel_err};
use crate::force::{EvalInput, Force};
use std::ops::Range;

/// Central-difference step (m, rad, m/s).
pub const FD_STEP: f64 = 1e-6;
/// Largest accepted finite-difference error, relative to the largest analytic entry.
pub const FD_TOL: f64 = 1e-6;
/// The step length (s) forces are evaluated for, for the forces that act through a step's
/// change of momentum ([`crate::force::EvalInput::dt`]).
pub const CONFORMANCE_DT: f64 = 1e-2;
/// Round-off tolerance of identities (force-only path, symmetry), relative to the largest
/// entry.
pub const ROUNDOFF: f64 = 1e-12;

/// A small deterministic generator (SplitMix64), so that the checks need no dependency and
/// every run draws the same configurations.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    /// Uniform in `[−amp, amp)`.
    pub fn symmetric(&mut self, amp: f64) -> f64 {
        self.uniform(-amp, amp)
    }
}

/// A post-processing step of the random draw: `(rng, q, v)`, e.g. to put the flow exactly
/// edge-on to a triangle.
pub type Adjust = Box<dyn Fn(&mut Rng, &mut [f64], &mut [f64])>;

/// A force under test and how its random configurations are drawn: every DOF `d` of `q` is
/// `q0[d] + U(−a_d, a_d)`, every velocity `U(−a_v, a_v)`, then an optional [`Adjust`].
pub struct Case {
    force: Box<dyn Force>,
    q0: Vec<f64>,
    q_amp: Vec<f64>,
    v_amp: f64,
    adjust: Option<Adjust>,
    trials: usize,
}

impl Case {
    /// `force` on a model with configuration `q0` (all DOFs), drawn unperturbed at rest until
    /// told otherwise; 6 trials.
    pub fn new(force: impl Force + 'static, q0: Vec<f64>) -> Self {
        Self::boxed(Box::new(force), q0)
    }

    /// [`Case::new`] for a force already boxed (e.g. taken out of a [`crate::Model`]).
    pub fn boxed(force: Box<dyn Force>, q0: Vec<f64>) -> Self {
        let n = q0.len();
        Self {
            force,
            q0,
            q_amp: vec![0.0; n],
            v_amp: 0.0,
            adjust: None,
            trials: 6,
        }
    }

    /// Perturb every position and twist by up to `amp` (m, rad).
    pub fn perturb(self, amp: f64) -> Self {
        let n = self.q0.len();
        self.perturb_dofs(0..n, amp)
    }

    /// Perturb the DOFs `dofs` by up to `amp` (m, rad).
    pub fn perturb_dofs(mut self, dofs: Range<usize>, amp: f64) -> Self {
        self.q_amp[dofs].iter_mut().for_each(|a| *a = amp);
        self
    }

    /// Random velocities up to `amp` (m/s, rad/s).
    pub fn velocities(mut self, amp: f64) -> Self {
        self.v_amp = amp;
        self
    }

    /// Post-process every draw with `f`.
    pub fn adjust(mut self, f: impl Fn(&mut Rng, &mut [f64], &mut [f64]) + 'static) -> Self {
        self.adjust = Some(Box::new(f));
        self
    }

    /// Number of random trials of each check.
    pub fn trials(mut self, n: usize) -> Self {
        self.trials = n;
        self
    }

    /// The force under test.
    pub fn force(&self) -> &dyn Force {
        self.force.as_ref()
    }

    /// One random configuration `(q, v)`.
    pub fn draw(&self, rng: &mut Rng) -> (Vec<f64>, Vec<f64>) {
        let mut q: Vec<f64> = self
            .q0
            .iter()
            .zip(&self.q_amp)
            .map(|(&x, &a)| x + rng.symmetric(a))
            .collect();
        let mut v: Vec<f64> = (0..q.len()).map(|_| rng.symmetric(self.v_amp)).collect();
        if let Some(f) = &self.adjust {
            f(rng, &mut q, &mut v);
        }
        (q, v)
    }
}

/// Run `check` on `trials` fresh cases, each committed at one random draw and handed
/// another; `check` returns the error it measured, and the worst is printed (visible with
/// `--nocapture`) under `what`.
fn trials(
    build: &dyn Fn() -> Case,
    seed: u64,
    what: &str,
    check: impl Fn(&Case, &[f64], &[f64], usize) -> f64,
) {
    let mut rng = Rng::new(seed);
    let n = build().trials;
    let mut worst = 0.0f64;
    let mut name = String::new();
    for trial in 0..n {
        let mut case = build();
        let (q_mid, v_mid) = case.draw(&mut rng);
        case.force.commit(&q_mid, &v_mid);
        let (q, v) = case.draw(&mut rng);
        worst = worst.max(check(&case, &q, &v, trial));
        name = case.force.name().to_string();
    }
    eprintln!("{name}: {what}: worst {worst:.2e} over {n} trials");
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The force equals `−∇E` when it has an energy; it has one exactly when it says it is
/// conservative.
pub fn check_energy_gradient(build: &dyn Fn() -> Case) {
    trials(build, 1, "force vs −∇E", |case, q, v, trial| {
        let f = case.force();
        let has_energy = f.energy(q).is_some();
        assert_eq!(
            has_energy,
            f.conservative(),
            "{}: energy() is Some exactly when conservative()",
            f.name()
        );
        if !has_energy {
            return 0.0;
        }
        let n = q.len();
        let (force, _, _) = dense_eval(f, q, v);
        let mut grad = vec![0.0; n];
        let mut qp = q.to_vec();
        for j in 0..n {
            qp[j] = q[j] + FD_STEP;
            let ep = f.energy(&qp).unwrap_or(f64::NAN);
            qp[j] = q[j] - FD_STEP;
            let em = f.energy(&qp).unwrap_or(f64::NAN);
            qp[j] = q[j];
            grad[j] = -(ep - em) / (2.0 * FD_STEP);
        }
        let err = rel_err(&force, &grad);
        assert!(
            err < FD_TOL,
            "{} trial {trial}: force vs −∇E error {err:.3e}",
            f.name()
        );
        err
    });
}

/// `∂F/∂q`, `∂F/∂v` against central differences; undeclared Jacobians vanish.
pub fn check_jacobians(build: &dyn Fn() -> Case) {
    trials(build, 2, "Jacobians vs FD", |case, q, v, trial| {
        let f = case.force();
        let kind = f.jacobian_kind();
        let (_, kq, kv) = dense_eval(f, q, v);
        let mut worst = 0.0f64;
        for (declared, analytic, wrt_q, what) in [
            (kind.dq, &kq, true, "∂F/∂q"),
            (kind.dv || f.low_rank_rank() > 0, &kv, false, "∂F/∂v"),
        ] {
            let fd = fd_jacobian(f, q, v, FD_STEP, wrt_q);
            if declared {
                let err = rel_err(analytic, &fd);
                assert!(
                    err < FD_TOL,
                    "{} trial {trial}: {what} error {err:.3e}",
                    f.name()
                );
                worst = worst.max(err);
            } else {
                let dep = max_abs(&fd);
                assert!(
                    dep == 0.0,
                    "{} trial {trial}: {what} is not declared but F depends on it ({dep:.3e})",
                    f.name()
                );
            }
        }
        worst
    });
}

/// The force of one evaluation with or without Jacobians, per stencil entry.
fn local_forces(f: &dyn Force, q: &[f64], v: &[f64], jacobian: bool) -> Vec<f64> {
    let mut b = f.new_blocks();
    f.evaluate(
        &EvalInput {
            q,
            v,
            t: 0.0,
            jacobian,
            dt: CONFORMANCE_DT,
        },
        &mut b,
    );
    b.f
}

/// The force-only path gives the full path's force to round-off.
pub fn check_force_only_path(build: &dyn Fn() -> Case) {
    trials(build, 3, "force-only vs full path", |case, q, v, trial| {
        let f = case.force();
        let full = local_forces(f, q, v, true);
        let only = local_forces(f, q, v, false);
        let scale = max_abs(&full);
        let diff = full
            .iter()
            .zip(&only)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            diff <= ROUNDOFF * scale,
            "{} trial {trial}: force-only path differs by {diff:.3e} (|F| {scale:.3e})",
            f.name()
        );
        diff / scale.max(f64::MIN_POSITIVE)
    });
}

/// Declared-symmetric Jacobians are symmetric to round-off.
pub fn check_symmetry(build: &dyn Fn() -> Case) {
    trials(build, 4, "asymmetry", |case, q, v, trial| {
        let f = case.force();
        if !f.jacobian_kind().symmetric {
            return 0.0;
        }
        let n = q.len();
        let (_, kq, kv) = dense_eval(f, q, v);
        let mut worst = 0.0f64;
        for (k, what) in [(&kq, "∂F/∂q"), (&kv, "∂F/∂v")] {
            let scale = max_abs(k);
            for a in 0..n {
                for b in 0..a {
                    let d = (k[a * n + b] - k[b * n + a]).abs();
                    assert!(
                        d <= ROUNDOFF * scale,
                        "{} trial {trial}: {what} not symmetric at ({a}, {b}): {d:.3e}",
                        f.name()
                    );
                    worst = worst.max(d / scale);
                }
            }
        }
        worst
    });
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The history of a committed force, restored on a freshly built one, reproduces its
/// evaluations bit for bit; a history of the wrong length is an error naming the force.
pub fn check_history_round_trip(build: &dyn Fn() -> Case) {
    trials(
        build,
        5,
        "history round trip (bit differences)",
        |case, q, v, trial| {
            let a = case.force();
            let h = a.history();
            let mut fresh = build();
            let b = fresh.force.as_mut();
            let mut longer = h.clone();
            longer.push(0.0);
            let err = b
                .restore_history(&longer)
                .expect_err("a history of the wrong length must be refused");
            assert!(err.to_string().contains(b.name()), "{err}");
            b.restore_history(&h)
                .unwrap_or_else(|e| panic!("trial {trial}: {e}"));
            assert_eq!(bits(&b.history()), bits(&h), "{}: history", a.name());
            let (fa, qa, va) = dense_eval(a, q, v);
            let (fb, qb, vb) = dense_eval(b, q, v);
            let name = a.name();
            assert_eq!(bits(&fa), bits(&fb), "{name} trial {trial}: force");
            assert_eq!(bits(&qa), bits(&qb), "{name} trial {trial}: ∂F/∂q");
            assert_eq!(bits(&va), bits(&vb), "{name} trial {trial}: ∂F/∂v");
            let e = |f: &dyn Force| f.energy(q).map(f64::to_bits);
            assert_eq!(e(a), e(b), "{name} trial {trial}: energy");
            0.0
        },
    );
}

/// Every check of this module.
pub fn check_all(build: &dyn Fn() -> Case) {
    check_energy_gradient(build);
    check_jacobians(build);
    check_force_only_path(build);
    check_symmetry(build);
    check_history_round_trip(build);
}

/// Stamp the checks of [`crate::conformance`] on a force, one `#[test]` each, in a module
/// `$name`: `force_conformance!(rod_stretch, Case::new(Stretch::new(…), q).perturb(0.3));`.
/// The case expression is evaluated afresh for every trial (the history check builds the
/// force twice), so it must be deterministic; names in scope where the macro is invoked are
/// in scope in it.
#[macro_export]
macro_rules! force_conformance {
    ($name:ident, $case:expr) => {
        $crate::force_conformance!(
            @checks $name,
            $case,
            check_energy_gradient,
            check_jacobians,
            check_force_only_path,
            check_symmetry,
            check_history_round_trip
        );
    };
    (@checks $name:ident, $case:expr, $($check:ident),*) => {
        mod $name {
            #[allow(unused_imports)]
            use super::*;

            fn case() -> $crate::conformance::Case {
                $case
            }

            $(
                #[test]
                fn $check() {
                    $crate::conformance::$check(&case);
                }
            )*
        }
    };
}
