//! Whether a modified-Newton solve starts from the factorisation held from earlier steps
//! (*stale start*) or refactorises at the predictor (*fresh start*).
//!
//! Which is cheaper depends on the problem, and no fixed rule wins everywhere: some models
//! converge fastest from the stale factors of the last step (the Jacobian at the unconverged
//! predictor can be a worse model of the solution than the one of the previous converged
//! state), others need several times fewer iterations from a fresh start
//! (docs/performance.md §Engine tuning). So the policy *measures*: it keeps an exponential
//! moving average of the work of solves started each way and starts the next one the cheaper
//! way, trying the other way every [`PROBE_EVERY`] solves so that a change of regime is
//! noticed.
//!
//! Work is counted deterministically (residual evaluations plus [`FACTOR_WORK`] per numeric
//! factorisation), never by wall time, so runs stay bit-reproducible; the state is reset
//! together with the held factors (sync points, resume).

/// Work of one numeric factorisation, in residual evaluations (the measured ratios of the
/// bundled models are 3–4.3, docs/performance.md §Engine tuning).
pub const FACTOR_WORK: f64 = 4.0;

/// Every this many solves with a choice, the way not currently preferred is tried.
pub const PROBE_EVERY: u64 = 8;

/// Weight of the newest solve in the moving averages.
const EMA_WEIGHT: f64 = 0.25;

/// Moving averages of the work of stale- and fresh-start solves.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StartPolicy {
    /// Average work of solves started from held factors (`None` before the first).
    stale: Option<f64>,
    /// Average work of solves started with a refactorisation at the predictor.
    fresh: Option<f64>,
    /// Solves with a choice so far.
    choices: u64,
}

impl StartPolicy {
    /// Whether the next solve (one that could reuse held factors) should refactorise first.
    pub fn fresh_next(&self) -> bool {
        let prefer_fresh = match (self.stale, self.fresh) {
            (Some(s), Some(f)) => f < s,
            // Until both ways are measured: start stale, then probe fresh once.
            (Some(_), None) => self.choices >= 1,
            _ => false,
        };
        let probe = self.choices % PROBE_EVERY == PROBE_EVERY - 1;
        prefer_fresh != probe
    }

    /// Record the work (evaluations + `FACTOR_WORK` × factorisations) of a solve that had the
    /// choice, started fresh or not. A failed solve's work counts too (it is what the way
    /// cost).
    pub fn record(&mut self, fresh: bool, work: f64) {
        let avg = if fresh {
            &mut self.fresh
        } else {
            &mut self.stale
        };
        *avg = Some(match *avg {
            Some(a) => (1.0 - EMA_WEIGHT) * a + EMA_WEIGHT * work,
            None => work,
        });
        self.choices += 1;
    }

    /// Forget the measurements (with the held factors).
    pub fn reset(&mut self) {
        *self = Self::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn starts_stale_then_probes_fresh_and_keeps_the_cheaper_way() {
        let mut p = StartPolicy::default();
        assert!(!p.fresh_next(), "first choice: stale");
        p.record(false, 20.0);
        assert!(p.fresh_next(), "second choice: probe fresh");
        p.record(true, 8.0);
        // Fresh is cheaper: kept, except on every PROBE_EVERY-th choice.
        let mut fresh_count = 0;
        for _ in 0..2 * PROBE_EVERY {
            let f = p.fresh_next();
            fresh_count += usize::from(f);
            p.record(f, if f { 8.0 } else { 20.0 });
        }
        assert_eq!(fresh_count as u64, 2 * PROBE_EVERY - 2);
    }

    #[test]
    fn a_change_of_regime_is_followed() {
        let mut p = StartPolicy::default();
        p.record(false, 10.0);
        p.record(true, 5.0);
        assert!(p.fresh_next());
        // Fresh starts become expensive: within a few solves the policy turns to stale.
        let mut switched = None;
        for i in 0..40 {
            let f = p.fresh_next();
            if !f && switched.is_none() && i % PROBE_EVERY as usize != PROBE_EVERY as usize - 1 {
                switched = Some(i);
            }
            p.record(f, if f { 30.0 } else { 10.0 });
        }
        assert!(switched.is_some_and(|i| i < 8), "switched at {switched:?}");
    }

    #[test]
    fn reset_forgets() {
        let mut p = StartPolicy::default();
        p.record(false, 1.0);
        p.record(true, 0.5);
        p.reset();
        assert_eq!(p, StartPolicy::default());
    }
}
