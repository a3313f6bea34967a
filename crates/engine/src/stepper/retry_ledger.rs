//! What the exact retry may cost: its failures are charged against the work of the solves
//! that succeeded, and a retry is only attempted while they have not cost more.
//!
//! An exact retry that converges saves a halving of `dt` (docs/engine.md: the report's
//! cases, the Kevlar case and the bench ladder take every step whole with it). One that fails
//! is pure waste — the caller halves anyway — and through its continuation and step homotopy
//! it can cost hundreds of factorisations: on the fabric canopy's opening
//! (`scenarios/round-fabric.toml` with the retry on, at dt 2 ms) failed retries of ~450 factorisations
//! each, repeated at every halving of the same step, made the run 33× slower than halving
//! straight away (docs/notes/engineering-2026-12.md). The ledger bounds that waste: a solve
//! whose modified-Newton path fails is retried only while the factorisations spent in failed
//! solves so far do not exceed those of the solves that succeeded; otherwise the failure
//! goes straight to the caller. Runs whose retries never fail (every case above) are
//! unchanged bit for bit. Work is counted in factorisations, which is what a retry spends
//! (the start policy's unit also weighs residual evaluations).
//!
//! The ledger is cleared with the held factors at the run's sync points
//! ([`crate::ImplicitEuler::invalidate_factorization`]), so that a resumed run decides like
//! an uninterrupted one.

/// Factorisations spent in failed and in successful solves since the last reset.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RetryLedger {
    /// Factorisations of solves that failed (their modified-Newton attempt and their retry).
    pub wasted: u64,
    /// Factorisations of solves that succeeded (retries that converged included).
    pub useful: u64,
}

impl RetryLedger {
    /// Whether a failed solve may be retried: failures have not yet cost more than
    /// successes.
    pub fn allows_retry(&self) -> bool {
        self.wasted <= self.useful
    }

    /// Record a solve's factorisations.
    pub fn record(&mut self, ok: bool, factorizations: u64) {
        if ok {
            self.useful += factorizations;
        } else {
            self.wasted += factorizations;
        }
    }

    /// Forget (with the held factors).
    pub fn reset(&mut self) {
        *self = Self::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_retry_is_allowed_until_failures_cost_more_than_successes() {
        let mut l = RetryLedger::default();
        assert!(l.allows_retry(), "the first failure is always retried");
        l.record(true, 10);
        l.record(false, 10);
        assert!(l.allows_retry(), "equal: still allowed");
        l.record(false, 1);
        assert!(!l.allows_retry(), "failures now cost more");
        l.record(true, 1);
        assert!(l.allows_retry(), "successes refill the allowance");
        l.reset();
        assert_eq!(l, RetryLedger::default());
    }
}
