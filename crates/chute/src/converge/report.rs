//! `convergence.json` and `convergence.md`.

use serde::Serialize;

use super::analyse::StudyReport;
use crate::scenario::derived::sig4;

/// The mark by which chute tells its own reports from a user's file of their names:
/// `written_by` of `convergence.json`, the closing comment of `convergence.md`
/// ([`MD_MARK`]), the `Software` text of `convergence.png` (`output::plots`).
pub const WRITTEN_BY: &str = "chute converge";

/// The last line of `convergence.md` as written to the file (not printed).
pub const MD_MARK: &str =
    "<!-- written by chute converge; replaced by the next run of the ladder -->\n";

/// Everything `chute converge` found (the root of `convergence.json`).
#[derive(Debug, Clone, Serialize)]
pub struct ConvergenceReport {
    /// [`WRITTEN_BY`].
    pub written_by: &'static str,
    /// The scenario file.
    pub scenario: String,
    /// The `--set` overrides applied to every level.
    pub set: Vec<String>,
    /// One per `--vary`.
    pub studies: Vec<StudyReport>,
}

impl ConvergenceReport {
    /// Pretty JSON with a trailing newline (non-finite numbers become null).
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self)
            .unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
        s.push('\n');
        s
    }

    /// The Markdown report: per varied key, the levels and the estimates.
    pub fn to_markdown(&self) -> String {
        let mut md = format!("# Convergence of `{}`\n\n", self.scenario);
        // A `--set` of a varied key holds on no level: each level sets its own value.
        let varied = |o: &&String| {
            let key = o.split_once('=').map_or(o.as_str(), |(k, _)| k.trim());
            self.studies.iter().any(|st| st.key == key)
        };
        let on_every: Vec<&String> = self.set.iter().filter(|o| !varied(o)).collect();
        if !on_every.is_empty() {
            let texts: Vec<&str> = on_every.iter().map(|s| s.as_str()).collect();
            md.push_str(&format!(
                "Overrides on every level: `{}`.\n\n",
                texts.join("`, `")
            ));
        }
        for st in &self.studies {
            md.push_str(&study_markdown(st));
        }
        md
    }
}

fn opt(v: Option<f64>) -> String {
    v.map_or("—".into(), sig4)
}

fn pct(v: Option<f64>) -> String {
    v.map_or("—".into(), |x| {
        if x != 0.0 && x.abs() < 1e-4 {
            format!("{:.1e} %", 100.0 * x)
        } else {
            format!("{:.3} %", 100.0 * x)
        }
    })
}

fn study_markdown(st: &StudyReport) -> String {
    let mut md = format!(
        "## `{}` ({} ladder)\n\n",
        st.key,
        match st.axis {
            super::plan::Axis::Space => "mesh",
            super::plan::Axis::Time => "time-step",
            super::plan::Axis::Tolerance => "error-tolerance",
        }
    );
    md.push_str(&levels_table(st));
    md.push_str(&estimates_table(st));
    md.push_str(&format!(
        "\nRound-off resolution: the Newton tolerance leaves a fraction ε_F = {:.2e} of the weight unresolved; a quantity whose finest difference is below its share of it is `round-off` (docs/convergence.md).\n",
        st.relative_force_resolution
    ));
    let msgs: Vec<String> = st
        .reported()
        .filter_map(|q| {
            let r = st.quantities.get(q.name)?;
            r.message.as_ref().map(|m| format!("{}: {m}", q.label))
        })
        .collect();
    for n in st.notes.iter().chain(&msgs) {
        md.push_str(&format!("\n- {n}"));
    }
    md.push_str("\n\n");
    md
}

/// One row per level: value, h, nodes, status, the quantities, wall time.
fn levels_table(st: &StudyReport) -> String {
    let mut md = String::from("| value | h | nodes | status | used |");
    for q in st.reported() {
        md.push_str(&format!(" {} |", q.label));
    }
    md.push_str(" wall (s) |\n|");
    md.push_str(&"---|".repeat(6 + st.reported().count()));
    md.push('\n');
    for (i, l) in st.levels.iter().enumerate() {
        md.push_str(&format!(
            "| {} | {} | {} | {} | {} |",
            l.text,
            sig4(l.h),
            l.nodes,
            l.status,
            if l.used { "yes" } else { "no" }
        ));
        for q in st.reported() {
            let v = st.quantities.get(q.name).and_then(|r| r.results[i]);
            md.push_str(&format!(" {} |", opt(v)));
        }
        md.push_str(&format!(
            " {} |\n",
            l.wall_time_s.map_or("—".into(), |w| format!("{w:.0}"))
        ));
    }
    md
}

/// One row per quantity: verdict, finest value, order, extrapolation, errors, GCIs.
fn estimates_table(st: &StudyReport) -> String {
    let mut md = String::from("\n| quantity | verdict | finest | p | extrapolated | e_a | e_ext | GCI (fine) | GCI by level |\n|---|---|---|---|---|---|---|---|---|\n");
    for q in st.reported() {
        let Some(r) = st.quantities.get(q.name) else {
            continue;
        };
        let finest = r.levels_used.first().and_then(|&i| r.results[i]);
        let p = match (r.observed_order, r.order_used) {
            (Some(p), _) => format!("{p:.2}"),
            (None, Some(p)) => format!("{p} (assumed)"),
            _ => "—".into(),
        };
        let by_level: Vec<String> = st
            .levels
            .iter()
            .zip(&r.gci_by_level)
            .filter_map(|(l, g)| g.map(|g| format!("{}: {}", l.text, pct(Some(g)))))
            .collect();
        md.push_str(&format!(
            "| {} | {} | {} | {p} | {} | {} | {} | {} | {} |\n",
            q.label,
            r.verdict.unwrap_or("—"),
            opt(finest),
            opt(r.extrapolated),
            pct(r.approximate_error),
            pct(r.extrapolated_error),
            pct(r.gci),
            if by_level.is_empty() {
                "—".to_string()
            } else {
                by_level.join(", ")
            }
        ));
    }
    md
}
