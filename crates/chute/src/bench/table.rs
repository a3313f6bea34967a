//! The text table of `chute bench` and the process-memory readings of its cases.

use super::CaseResult;

/// A `/proc/self/status` memory field (`VmRSS`, `VmHWM`, …) in MiB; 0 where `/proc` is
/// unavailable.
fn status_mib(field: &str) -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.strip_prefix(field).is_some_and(|r| r.starts_with(':')))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map_or(0.0, |kb| kb / 1024.0)
}

/// Current and peak resident memory, for the `--mem` stage report.
pub(super) fn rss_mib() -> String {
    format!(
        "RSS {:.1} MiB (peak {:.1} MiB)",
        status_mib("VmRSS"),
        status_mib("VmHWM")
    )
}

/// `VmHWM` of this process (MiB); 0 where `/proc` is unavailable.
pub fn peak_rss_mib() -> f64 {
    status_mib("VmHWM")
}

pub(super) fn header() -> String {
    format!(
        "{:<16} {:>6} {:>7} {:>9} {:>9} {:>6} {:>8} {:>6} {:>6} {:>5} {:>5} {:>5} {:>8}",
        "case",
        "nodes",
        "DOFs",
        "nnz",
        "ms/step",
        "it/st",
        "ms/it",
        "fac/st",
        "ev/st",
        "asm%",
        "fac%",
        "sol%",
        "RSS MiB"
    )
}

/// What the columns of [`header`] mean, printed under the table.
pub(super) const LEGEND: &str =
    "columns: nnz = stored nonzeros of the Jacobian; ms/step = wall time per time step; \
it/st = Newton iterations (linear solves) per step; ms/it = wall time per iteration; \
fac/st = numeric factorisations per step; ev/st = residual evaluations (element passes) per step; \
asm% / fac% / sol% = shares of the time in assembly, factorisation and triangular solves; \
RSS MiB = peak resident memory of the case's process";

pub(super) fn row(r: &CaseResult) -> String {
    format!(
        "{:<16} {:>6} {:>7} {:>9} {:>9.3} {:>6.2} {:>8.3} {:>6.2} {:>6.2} {:>5.1} {:>5.1} {:>5.1} {:>8.1}",
        r.name,
        r.nodes,
        r.dofs,
        r.nnz,
        r.ms_per_step,
        r.newton_per_step,
        r.ms_per_newton,
        r.factorizations_per_step,
        r.evaluations_per_step,
        100.0 * r.share_assembly,
        100.0 * r.share_factor,
        100.0 * r.share_solve,
        r.peak_rss_mib
    )
}
