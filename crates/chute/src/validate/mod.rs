//! `chute validate`: the verification cases against analytic references, as a command.
//!
//! Every case returns one or more [`Check`]s: a quantity, its reference value and source,
//! the simulated value and a tolerance set from physics and discretisation error. The table
//! (or JSON) lists them all; the command exits non-zero when any check fails.
//!
//! A test-only hook, the environment variable `CHUTE_VALIDATE_BREAK=<case name>`, scales that
//! case's references by 1.5 so tests can prove that a wrong reference makes the command fail.

mod cases;
pub mod convergence;
pub mod shell_cases;
mod system;

use serde::Serialize;
use std::time::Instant;

/// One verified quantity.
#[derive(Debug, Clone, Serialize)]
pub struct Check {
    /// Case name (e.g. `elastica-alpha-5`).
    pub name: String,
    /// What is compared (with units).
    pub quantity: String,
    /// Reference value.
    pub reference: f64,
    /// Where the reference comes from.
    pub source: String,
    /// Simulated value.
    pub simulated: f64,
    /// |simulated − reference| / |reference|.
    pub rel_error: f64,
    /// Tolerance on `rel_error`.
    pub tolerance: f64,
    /// `rel_error ≤ tolerance`.
    pub pass: bool,
    /// Wall time of the whole case the check belongs to (s).
    pub wall_s: f64,
}

impl Check {
    /// A check comparing `simulated` with `reference` at relative tolerance `tolerance`.
    pub fn new(
        name: &str,
        quantity: &str,
        reference: f64,
        source: &str,
        simulated: f64,
        tolerance: f64,
    ) -> Self {
        let reference = match (broken(name), reference == 0.0) {
            (true, false) => 1.5 * reference,
            (true, true) => 1.0,
            (false, _) => reference,
        };
        let rel_error = ((simulated - reference) / reference).abs();
        Self {
            name: name.into(),
            quantity: quantity.into(),
            reference,
            source: source.into(),
            simulated,
            rel_error,
            tolerance,
            pass: rel_error <= tolerance && simulated.is_finite(),
            wall_s: 0.0,
        }
    }
    /// A check of a dimensionless quantity whose exact value is zero (a symmetry): the
    /// error is `|simulated|` itself, i.e. relative to the scale the quantity was divided
    /// by (stated in `quantity`).
    pub fn near_zero(
        name: &str,
        quantity: &str,
        source: &str,
        simulated: f64,
        tolerance: f64,
    ) -> Self {
        let reference = if broken(name) { 1.0 } else { 0.0 };
        let rel_error = (simulated - reference).abs();
        Self {
            name: name.into(),
            quantity: quantity.into(),
            reference,
            source: source.into(),
            simulated,
            rel_error,
            tolerance,
            pass: rel_error <= tolerance && simulated.is_finite(),
            wall_s: 0.0,
        }
    }
    /// A check that failed to run (the error becomes the quantity text).
    pub fn failed(name: &str, why: &str) -> Self {
        Self {
            name: name.into(),
            quantity: format!("FAILED TO RUN: {why}"),
            reference: f64::NAN,
            source: String::new(),
            simulated: f64::NAN,
            rel_error: f64::NAN,
            tolerance: 0.0,
            pass: false,
            wall_s: 0.0,
        }
    }
}

fn broken(name: &str) -> bool {
    std::env::var("CHUTE_VALIDATE_BREAK").is_ok_and(|b| !b.is_empty() && name.starts_with(&b))
}

/// A registered case.
pub struct Case {
    /// Name prefix of its checks.
    pub name: &'static str,
    /// Included in `--quick`.
    pub quick: bool,
    /// Runs the case; `quick` asks for the cheaper variant where one exists.
    pub run: fn(quick: bool) -> Result<Vec<Check>, String>,
}

/// Options of `chute validate`.
#[derive(Debug, Clone, Default)]
pub struct ValidateOptions {
    /// Only the quick cases (under a minute on 2 cores).
    pub quick: bool,
    /// Print JSON instead of a table.
    pub json: bool,
    /// Directory for convergence CSVs and plots (none: skip them).
    pub out: Option<std::path::PathBuf>,
    /// Only cases whose name contains this string.
    pub filter: Option<String>,
}

/// Run the suite; returns the checks (caller prints and sets the exit code).
pub fn run_suite(opts: &ValidateOptions) -> Vec<Check> {
    let mut all = Vec::new();
    for case in cases::all() {
        if opts.quick && !case.quick {
            continue;
        }
        if let Some(f) = &opts.filter {
            if !case.name.contains(f.as_str()) {
                continue;
            }
        }
        let start = Instant::now();
        let mut checks =
            (case.run)(opts.quick).unwrap_or_else(|e| vec![Check::failed(case.name, &e)]);
        let wall = start.elapsed().as_secs_f64();
        for c in &mut checks {
            c.wall_s = wall;
        }
        all.extend(checks);
    }
    if let Some(dir) = &opts.out {
        let start = Instant::now();
        match convergence::write_all(dir, opts.quick) {
            Ok(mut checks) => {
                let wall = start.elapsed().as_secs_f64();
                checks.iter_mut().for_each(|c| c.wall_s = wall);
                all.extend(checks);
            }
            Err(e) => all.push(Check::failed("convergence-studies", &e)),
        }
    }
    all
}

/// Render the checks as a Markdown table (`|` inside cells escaped), with the pass count.
pub fn markdown(checks: &[Check]) -> String {
    let esc = |t: &str| t.replace('|', "\\|");
    let mut s = String::from(
        "| case | quantity | reference | simulated | rel. error | tol. | pass | source |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    for c in checks {
        s += &format!(
            "| {} | {} | {:.6e} | {:.6e} | {:.2e} | {:.1e} | {} | {} |\n",
            c.name,
            esc(&c.quantity),
            c.reference,
            c.simulated,
            c.rel_error,
            c.tolerance,
            if c.pass { "ok" } else { "**FAIL**" },
            esc(&c.source)
        );
    }
    let failed = checks.iter().filter(|c| !c.pass).count();
    s += &format!("\n{} passed, {} failed.\n", checks.len() - failed, failed);
    s
}

/// Render the checks as a fixed-width table.
pub fn table(checks: &[Check]) -> String {
    let mut s = format!(
        "{:<28} {:<56} {:>13} {:>13} {:>9} {:>8}  {:<4}  {}\n",
        "case", "quantity", "reference", "simulated", "rel.err", "tol", "pass", "source"
    );
    for c in checks {
        s += &format!(
            "{:<28} {:<40} {:>13.6e} {:>13.6e} {:>9.2e} {:>8.1e}  {:<4}  {}\n",
            c.name,
            c.quantity,
            c.reference,
            c.simulated,
            c.rel_error,
            c.tolerance,
            if c.pass { "ok" } else { "FAIL" },
            c.source
        );
    }
    let failed = checks.iter().filter(|c| !c.pass).count();
    s += &format!("{} passed, {} failed\n", checks.len() - failed, failed);
    s
}
