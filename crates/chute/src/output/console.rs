//! The summary printed for people after `chute run`: the key results first, in four
//! significant figures with units, then the warnings as plain lines, then the files written.
//! (`--json` prints `summary.json` instead; see docs/outputs.md §Console summary.)

use std::fmt::Write as _;
use std::path::Path;

use super::summary::Summary;
use crate::metrics::{FINAL_WINDOW_FRACTION, STEADY_TOLERANCE, TERMINAL_BAND};
use crate::scenario::derived::sig4;

/// Why the run did not reach terminal velocity, in a few words; `None` when it did.
pub fn not_reached_reason(s: &Summary) -> Option<String> {
    if s.reached_terminal {
        return None;
    }
    let warned = |prefix: &str| s.warnings.iter().any(|w| w.starts_with(prefix));
    let speed = s.terminal_velocity_mps.abs();
    let reason = if warned("metrics unavailable") {
        "the metrics could not be computed (see the warnings)".to_string()
    } else if warned("run too short") {
        format!(
            "run too short to judge (too few samples in the final {:.0} %)",
            100.0 * FINAL_WINDOW_FRACTION
        )
    } else if warned("canopy is not descending")
        || s.terminal_velocity_mps >= 0.0
        || s.terminal_velocity_mps.is_nan()
    {
        "the canopy is not descending".to_string()
    } else {
        let std = 100.0 * s.terminal_velocity_std_mps / speed;
        let trend = 100.0 * s.terminal_velocity_trend_mps.abs() / speed;
        let limit = 100.0 * STEADY_TOLERANCE;
        if std < limit && trend < limit {
            format!(
                "vz leaves the ±{:.0} % band during the final window",
                100.0 * TERMINAL_BAND
            )
        } else {
            format!(
                "vz still changing: std {} %, trend {} % of |v_t| (limit {limit:.0} %)",
                sig4(std),
                sig4(trend)
            )
        }
    };
    Some(if s.complete {
        reason
    } else {
        format!("the run stopped early; {reason}")
    })
}

/// A duration in seconds as `12.35 s`, `3 min 4 s` or `2 h 5 min`.
pub fn human_duration(s: f64) -> String {
    if !(s.is_finite() && s >= 0.0) {
        return format!("{s} s");
    }
    let whole = s.round() as u64;
    match whole {
        0..=99 => format!("{} s", sig4(s)),
        100..=3599 => format!("{} min {} s", whole / 60, whole % 60),
        _ => format!("{} h {} min", whole / 3600, (whole % 3600) / 60),
    }
}

/// `x` in four significant figures with `unit`, or "–" when it is not a number (metrics a
/// run could not compute are NaN).
fn quantity(x: f64, unit: &str) -> String {
    if x.is_finite() {
        format!("{} {unit}", sig4(x))
    } else {
        "–".to_string()
    }
}

/// The key results as (label, value) rows: terminal velocity (± its std), reached or why
/// not, time to terminal, drag area, extended height, force balance.
pub fn key_results(s: &Summary) -> Vec<(&'static str, String)> {
    let window = s.simulated_time_s - s.final_window_start_s;
    let mut rows = vec![(
        "terminal velocity",
        if s.terminal_velocity_mps.is_finite() {
            format!(
                "{} ± {} (mean and std of vz over the final {})",
                quantity(s.terminal_velocity_mps, "m/s"),
                quantity(s.terminal_velocity_std_mps, "m/s"),
                quantity(window, "s")
            )
        } else {
            "– (not computed: see the warnings)".to_string()
        },
    )];
    rows.push((
        "reached",
        match not_reached_reason(s) {
            None => "yes".to_string(),
            Some(why) => format!("no: {why}"),
        },
    ));
    rows.push((
        "time to terminal",
        s.time_to_terminal_s
            .map_or_else(|| "–".to_string(), |t| quantity(t, "s")),
    ));
    rows.push((
        "drag area C_D·A",
        match s.drag_area_m2 {
            Some(a) => quantity(a, "m²"),
            None => "– (no descent)".to_string(),
        },
    ));
    rows.push((
        "extended height",
        format!(
            "{} at the end, {} at most",
            quantity(s.final_extended_height_m, "m"),
            quantity(s.max_extended_height_m, "m")
        ),
    ));
    rows.push((
        "force balance",
        format!(
            "|drag_z − W|/W = {} (drag_z {}, W {}{})",
            quantity(100.0 * s.force_balance_error, "%"),
            quantity(s.mean_drag_z_n, "N"),
            quantity(s.total_weight_n, "N"),
            s.canopy_weight_n
                .filter(|w| w.is_finite() && *w > 0.0)
                .map_or(String::new(), |w| format!(
                    ": the load and lines {} and the canopy {}",
                    quantity(s.total_weight_n - w, "N"),
                    quantity(w, "N")
                ))
        ),
    ));
    if let Some(text) = opening_text(s) {
        rows.push(("opening", text));
    }
    rows.extend(s.triggers.iter().map(|r| ("sensor pull", trigger_text(r))));
    rows
}

/// The opening of a packed canopy: its shock, load factor, fill time and distance.
fn opening_text(s: &Summary) -> Option<String> {
    let r = &s.recovery;
    let peak = r.opening_peak_force_n?;
    let at = r
        .time_of_peak_line_tension_s
        .map_or(String::new(), |t| format!(" at {}", quantity(t, "s")));
    let factor = r.opening_load_factor.map_or_else(
        || "opening-load factor – (no steady descent)".to_string(),
        |x| format!("opening-load factor {x:.3} (C_x·X₁)"),
    );
    let fill = match (r.opening_fill_time_s, r.opening_fill_distance_diameters) {
        (Some(t), Some(d)) => format!("filled in {} over {d:.3} D₀", quantity(t, "s")),
        _ => "fill time – (no steady diameter)".to_string(),
    };
    Some(format!(
        "peak force {}{at}, {factor}, {fill}",
        quantity(peak, "N")
    ))
}

/// One sensor-started pull: which, and when and at what reading it fired.
fn trigger_text(r: &crate::control::TriggerRecord) -> String {
    let fired = match (r.reading_time_s, r.reading_m, r.pull_start_s) {
        (Some(t), Some(h), Some(start)) => format!(
            "fired by the reading {} at {}; ramp from {}",
            quantity(h, "m"),
            quantity(t, "s"),
            quantity(start, "s")
        ),
        _ => "did not fire".to_string(),
    };
    format!(
        "control[{}] (sensor `{}`, ≤ {}): {fired}",
        r.control,
        r.sensor,
        quantity(r.below_m, "m")
    )
}

/// The files of run directory `dir`, for the summary: sorted names, the frames directory as
/// one entry with its count, hidden files left out.
pub fn files_in(dir: &Path) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut names: Vec<String> = entries
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            if name.starts_with('.') {
                return None;
            }
            if e.path().is_dir() {
                let n = std::fs::read_dir(e.path()).map_or(0, |d| d.count());
                return Some(format!("{name}/ ({n} files)"));
            }
            Some(name)
        })
        .collect();
    names.sort();
    names
}

/// The whole summary printed after a run of `s` into `dir`.
pub fn format_run_summary(s: &Summary, dir: &Path) -> String {
    let mut out = String::new();
    let state = if s.complete { "complete" } else { "INCOMPLETE" };
    let per_step = s.newton_iterations as f64 / (s.steps.max(1) as f64);
    let _ = writeln!(
        out,
        "run `{}` {state}: {} s simulated in {} ({} steps, {} Newton iterations per step, {} DOFs)",
        s.scenario_name,
        sig4(s.simulated_time_s),
        human_duration(s.wall_time_s),
        s.steps,
        sig4(per_step),
        s.dofs
    );
    out.push('\n');
    out += &pairs_text(&key_results(s));
    if !s.warnings.is_empty() {
        out.push_str("\nwarnings:\n");
        for warning in &s.warnings {
            let _ = writeln!(out, "  {warning}");
        }
    }
    let _ = writeln!(out, "\nfiles in {}:", dir.display());
    let files = files_in(dir);
    for f in &files {
        let _ = writeln!(out, "  {f}");
    }
    if files.iter().any(|f| f == super::viewer::VIEWER_HTML) {
        let _ = writeln!(
            out,
            "\nopen {} in a browser to see the flight",
            dir.join(super::viewer::VIEWER_HTML).display()
        );
    }
    out
}

/// `(label, value)` pairs as indented lines, the values aligned in one column.
pub fn pairs_text<K: AsRef<str>, V: std::fmt::Display>(pairs: &[(K, V)]) -> String {
    let w = pairs
        .iter()
        .map(|(k, _)| k.as_ref().chars().count())
        .max()
        .unwrap_or(0);
    pairs
        .iter()
        .map(|(k, v)| format!("  {:<w$}  {v}\n", k.as_ref()))
        .collect()
}

/// After `chute run`: with `json`, `dir/summary.json` verbatim on stdout; otherwise, unless
/// `quiet`, [`format_run_summary`] of `summary` (the run's `summary.json` contents).
pub fn print_run_report(
    dir: &Path,
    summary: &serde_json::Value,
    json: bool,
    quiet: bool,
) -> std::io::Result<()> {
    let text = if json {
        super::atomic::read_own_string(&dir.join("summary.json"))?
    } else if quiet {
        return Ok(());
    } else {
        match serde_json::from_value::<Summary>(summary.clone()) {
            Ok(s) => format_run_summary(&s, dir),
            // Not expected (the run wrote this summary), but never hide the results.
            Err(_) => format!("{summary:#}\n"),
        }
    };
    // A stdout that cannot take it is the command's failure (exit 1), not summary.json's.
    crate::out_text!("{text}");
    Ok(())
}

/// The first error writing a command's results to stdout, if any ([`crate::out_text!`]).
static STDOUT_ERROR: std::sync::Mutex<Option<String>> = std::sync::Mutex::new(None);

/// Remember that writing to stdout failed with `e` (the first error is kept).
pub fn stdout_failed(e: std::io::Error) {
    if let Ok(mut first) = STDOUT_ERROR.lock() {
        first.get_or_insert_with(|| e.to_string());
    }
}

/// Why the command's results could not all be written to stdout, if they could not.
pub fn stdout_error() -> Option<String> {
    STDOUT_ERROR.lock().ok().and_then(|e| e.clone())
}
