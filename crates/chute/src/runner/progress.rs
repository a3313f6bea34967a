//! The progress bar of a run on a terminal: simulated time, step rate, Newton iterations and
//! the time left at the recent pace (docs/cli.md §`chute run`).

use std::collections::VecDeque;
use std::time::Instant;

use super::RunConfig;

/// Positions of the bar: the simulated time in thousandths of the run.
const TICKS: u64 = 1000;

/// Fraction of the simulated time after which the bar estimates the time left.
const ETA_AFTER: f64 = 0.05;

/// The span of simulated time (a fraction of the run) over which the pace is measured.
const PACE_WINDOW: f64 = 0.1;

/// The bar for a run with `cfg`, when it shows progress on a terminal.
pub(super) fn bar(cfg: &RunConfig) -> Option<indicatif::ProgressBar> {
    use std::io::IsTerminal;
    if !cfg.progress || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(TICKS);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {percent:>3}% [{elapsed_precise} < {recent_eta}] {msg}",
        )
        .map(|st| st.with_key("recent_eta", RecentPace::default()))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    Some(bar)
}

/// Show the simulated time, the step rate and the last step's Newton iterations.
pub(super) fn show(
    bar: &indicatif::ProgressBar,
    t: f64,
    cfg: &RunConfig,
    steps: u64,
    wall: &Instant,
    iterations: usize,
) {
    bar.set_position((t / cfg.stepping.duration_s * TICKS as f64) as u64);
    let rate = steps as f64 / wall.elapsed().as_secs_f64().max(1e-9);
    bar.set_message(format!(
        "t = {t:.3} s, {rate:.0} steps/s, {iterations} Newton it/step"
    ));
}

/// The time left at the pace of the last [`PACE_WINDOW`] of the run (wall time per simulated
/// time). indicatif's own estimate follows the last few steps and swings by orders of
/// magnitude across an opening (a step there costs 100× one at terminal speed); the mean
/// pace since the start stays long for the whole run after an opening. Over a window of a
/// tenth of the run the estimate follows a change of pace within that tenth. Before
/// [`ETA_AFTER`] of the run it is `?`.
#[derive(Clone, Default)]
struct RecentPace {
    /// (fraction of the run done, when), one sample per new position, oldest first.
    samples: VecDeque<(f64, Instant)>,
}

impl RecentPace {
    /// Record that `done` of the run was reached at `now`, keeping the samples that span the
    /// window (and one before it).
    fn record(&mut self, done: f64, now: Instant) {
        if self.samples.back().is_some_and(|&(f, _)| f >= done) {
            return;
        }
        self.samples.push_back((done, now));
        while self.samples.len() > 2 && self.samples[1].0 <= done - PACE_WINDOW {
            self.samples.pop_front();
        }
    }
}

/// Seconds left when `done` of the run is reached at `now` and `since` is the oldest sample
/// of the window: `None` before [`ETA_AFTER`] or without a span to measure.
fn seconds_left(since: Option<(f64, Instant)>, done: f64, now: Instant) -> Option<f64> {
    let (f0, t0) = since?;
    let span = done - f0;
    if done < ETA_AFTER || span <= 0.0 {
        return None;
    }
    Some(now.saturating_duration_since(t0).as_secs_f64() / span * (1.0 - done))
}

impl indicatif::style::ProgressTracker for RecentPace {
    fn clone_box(&self) -> Box<dyn indicatif::style::ProgressTracker> {
        Box::new(self.clone())
    }

    fn tick(&mut self, state: &indicatif::ProgressState, now: Instant) {
        self.record(state.fraction() as f64, now);
    }

    fn reset(&mut self, _: &indicatif::ProgressState, _: Instant) {
        self.samples.clear();
    }

    fn write(&self, state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write) {
        let done = state.fraction() as f64;
        match seconds_left(self.samples.front().copied(), done, Instant::now()) {
            Some(left) => {
                let left = left.round() as u64;
                let _ = write!(w, "{}:{:02}:{:02}", left / 3600, left / 60 % 60, left % 60);
            }
            None => {
                let _ = write!(w, "?");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    /// A run whose first 20 % cost 100 s and whose rest goes at 10 s per 10 %: once the
    /// expensive part has left the window, the time left is the cheap pace's (80 s at 20 %
    /// would be 400 s at the mean pace).
    #[test]
    fn time_left_follows_the_recent_pace() {
        let t0 = Instant::now();
        let mut p = RecentPace::default();
        let at = |done: f64, s: f64, p: &mut RecentPace| {
            let now = t0 + Duration::from_secs_f64(s);
            p.record(done, now);
            seconds_left(p.samples.front().copied(), done, now)
        };
        assert_eq!(at(0.0, 0.0, &mut p), None);
        // Still before ETA_AFTER: no estimate.
        assert_eq!(at(0.04, 20.0, &mut p), None);
        for k in 1..=10 {
            at(0.2 * k as f64 / 10.0, 10.0 * k as f64, &mut p);
        }
        let mut left = 0.0;
        for k in 1..=30 {
            let done = 0.2 + 0.01 * k as f64;
            left = at(done, 100.0 + k as f64, &mut p).expect("an estimate");
        }
        // At 50 %: 50 % left at 1 s per 1 % = 50 s.
        assert!((left - 50.0).abs() < 1e-6, "{left}");
        assert!(p.samples.len() <= 12, "{} samples kept", p.samples.len());
    }

    /// A position that does not advance adds no sample.
    #[test]
    fn a_repeated_position_is_one_sample() {
        let t0 = Instant::now();
        let mut p = RecentPace::default();
        p.record(0.1, t0);
        p.record(0.1, t0 + Duration::from_secs(5));
        assert_eq!(p.samples.len(), 1);
    }
}
