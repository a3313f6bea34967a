//! The verification suite, run by `chute validate`: the cases against analytic references.
//!
//! Every case returns one or more [`Check`]s: a quantity, its reference value and source,
//! the simulated value and a tolerance set from physics and discretisation error. The table
//! (or JSON) lists them all; the command exits non-zero when any check fails.
//!
//! A hidden option for the tests, `--break-reference <case>`, scales the references of the
//! checks whose name starts with it by 1.5, so they can prove that a wrong reference makes the
//! command fail.

mod cases;
pub mod convergence;
pub mod membrane_cases;
pub mod midedge_cases;
mod real;
pub mod scordelis_lo;
pub mod shell_cases;
mod stability;
mod stability_report;
mod system;

use serde::Serialize;
use std::time::Instant;

use crate::app::AppError;

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
        let rel_error = ((simulated - reference) / reference).abs();
        Self::judged(
            [name, quantity, source],
            reference,
            simulated,
            rel_error,
            tolerance,
        )
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
        let rel_error = (simulated - 0.0).abs();
        Self::judged(
            [name, quantity, source],
            0.0,
            simulated,
            rel_error,
            tolerance,
        )
    }
    /// `[name, quantity, source]` and the numbers; it passes when the error is within the
    /// tolerance and the simulated value is finite.
    fn judged(
        [name, quantity, source]: [&str; 3],
        reference: f64,
        simulated: f64,
        rel_error: f64,
        tolerance: f64,
    ) -> Self {
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
    /// An information row (the report's model measured on a test, not judged): tolerance
    /// `f64::MAX`, so it always passes; the tables show `info` for its tolerance.
    pub fn info(name: &str, quantity: &str, reference: f64, source: &str, simulated: f64) -> Self {
        Self::new(name, quantity, reference, source, simulated, f64::MAX)
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

    /// The check against a wrong reference (1.5 × the true one, 1 for a zero reference):
    /// the test of `--break-reference`.
    fn break_reference(&mut self) {
        self.reference = match self.reference {
            0.0 => 1.0,
            r => 1.5 * r,
        };
        self.rel_error = ((self.simulated - self.reference) / self.reference).abs();
        self.pass = self.rel_error <= self.tolerance && self.simulated.is_finite();
    }
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

/// `chute validate`.
#[derive(Debug, Clone, Default, PartialEq, clap::Args)]
pub struct ValidateArgs {
    /// Short versions of the cases (under a minute on 2 cores).
    #[arg(long)]
    pub quick: bool,
    /// Where to write the report (validation_table.md) and the convergence studies.
    #[arg(long, value_name = "DIR")]
    pub out: Option<std::path::PathBuf>,
    /// Print the results as JSON.
    #[arg(long)]
    pub json: bool,
    /// Only the cases whose name contains this text (e.g. `elastica`).
    #[arg(long, value_name = "TEXT")]
    pub case: Option<String>,
    /// Scale the references of the checks whose name starts with this by 1.5 (to prove in
    /// tests that a wrong reference fails).
    #[arg(long, value_name = "CASE", hide = true)]
    pub break_reference: Option<String>,
}

/// Run the verification suite, print the table (or JSON) on stdout and write the report
/// and convergence studies when `out` is given; `Err(ValidationFailed)` when any check fails.
pub fn main(args: &ValidateArgs) -> Result<(), AppError> {
    refuse_empty_selection(args)?;
    if let Some(dir) = &args.out {
        refuse_out(dir)?;
        crate::app::ensure_dir(dir)?;
    }
    let checks = run_suite_with(args, |name, i, n| {
        crate::err_line!("validate: case {name} ({i} of {n}) …")
    });
    if let Some(dir) = &args.out {
        let path = dir.join("validation_table.md");
        crate::output::atomic::write_atomic(&path, markdown(&checks).as_bytes())
            .map_err(|e| AppError::io(&path, e))?;
    }
    if args.json {
        let text = serde_json::to_string_pretty(&checks)
            .map_err(|e| AppError::RunFailed(format!("JSON: {e}")))?;
        crate::out_line!("{text}");
    } else {
        crate::out_text!("{}", table(&checks));
    }
    match checks.iter().filter(|c| !c.pass).count() {
        0 => Ok(()),
        failed => Err(AppError::ValidationFailed { failed }),
    }
}

/// The header line of `validation_table.md`, by which chute tells its own from a user's file
/// of that name.
const TABLE_HEADER: &str =
    "| case | quantity | reference | simulated | rel. error | tol. | pass | source |";

/// Refuse a `--out` that is, or lies inside, a run directory (the report would sit among a
/// run's files), or whose `validation_table.md` is a user's file (not chute's header).
fn refuse_out(dir: &std::path::Path) -> Result<(), AppError> {
    if crate::output::run_files::is_run_dir(dir) {
        return Err(AppError::Input(format!(
            "`{}` is a run directory: `validate --out` writes its report in a directory of its own",
            dir.display()
        )));
    }
    crate::app::out_dir::refuse_inside_run(dir)?;
    let path = dir.join("validation_table.md");
    let Ok(meta) = std::fs::symlink_metadata(&path) else {
        return Ok(());
    };
    let text = match meta.is_file() {
        true => crate::output::atomic::read_own_string(&path).unwrap_or_default(),
        false => String::new(),
    };
    match text.lines().next() == Some(TABLE_HEADER) {
        true => Ok(()),
        false => Err(AppError::Input(format!(
            "`{}` is not a report chute wrote, and chute would replace it: move it, or choose another --out",
            path.display()
        ))),
    }
}

/// A `--case TEXT` that selects no case is a mistake (bad input), not "0 passed".
fn refuse_empty_selection(args: &ValidateArgs) -> Result<(), AppError> {
    let Some(text) = &args.case else {
        return Ok(());
    };
    let available: Vec<&str> = cases::all()
        .into_iter()
        .filter(|c| !args.quick || c.quick)
        .map(|c| c.name)
        .collect();
    if available.iter().any(|n| n.contains(text.as_str())) {
        return Ok(());
    }
    let quick = if args.quick { " with --quick" } else { "" };
    Err(AppError::Input(format!(
        "--case `{text}` matches no verification case{quick}; the cases are: {}",
        available.join(", ")
    )))
}

/// Run the suite; returns the checks (caller prints and sets the exit code).
pub fn run_suite(opts: &ValidateArgs) -> Vec<Check> {
    run_suite_with(opts, |_, _, _| {})
}

/// [`run_suite`], calling `announce(case, i, n)` as the `i`-th of `n` cases starts (the
/// command line's progress on stderr: its table comes only at the end).
fn run_suite_with(opts: &ValidateArgs, announce: impl Fn(&str, usize, usize)) -> Vec<Check> {
    let mut all = Vec::new();
    let selected: Vec<_> = cases::all()
        .into_iter()
        .filter(|c| !opts.quick || c.quick)
        .filter(|c| {
            opts.case
                .as_ref()
                .is_none_or(|f| c.name.contains(f.as_str()))
        })
        .collect();
    for (i, case) in selected.iter().enumerate() {
        announce(case.name, i + 1, selected.len());
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
    if let Some(prefix) = opts.break_reference.as_deref().filter(|p| !p.is_empty()) {
        all.iter_mut()
            .filter(|c| c.name.starts_with(prefix))
            .for_each(Check::break_reference);
    }
    all
}

/// Render the checks as a Markdown table (`|` inside cells escaped), with the pass count.
pub fn markdown(checks: &[Check]) -> String {
    let esc = |t: &str| t.replace('|', "\\|");
    let mut s = format!("{TABLE_HEADER}\n|---|---|---|---|---|---|---|---|\n");
    for c in checks {
        s += &format!(
            "| {} | {} | {:.6e} | {:.6e} | {:.2e} | {} | {} | {} |\n",
            c.name,
            esc(&c.quantity),
            c.reference,
            c.simulated,
            c.rel_error,
            tolerance_text(c.tolerance),
            if c.pass { "ok" } else { "**FAIL**" },
            esc(&c.source)
        );
    }
    let failed = checks.iter().filter(|c| !c.pass).count();
    s += &format!("\n{} passed, {} failed.\n", checks.len() - failed, failed);
    s
}

/// A tolerance as the tables show it: `info` for an information row ([`Check::info`]).
fn tolerance_text(tol: f64) -> String {
    if tol == f64::MAX {
        "info".into()
    } else {
        format!("{tol:.1e}")
    }
}

/// Render the checks as a table whose columns are as wide as their widest cell. The
/// references' sources are long citations: they are in `--out`'s `validation_table.md` and
/// `--json`, not in the console's table, which stays within a terminal's width.
pub fn table(checks: &[Check]) -> String {
    let width = |head: &str, cell: &dyn Fn(&Check) -> &str| {
        checks
            .iter()
            .map(|c| cell(c).chars().count())
            .chain([head.chars().count()])
            .max()
            .unwrap_or(0)
    };
    let (wc, wq) = (
        width("case", &|c| c.name.as_str()),
        width("quantity", &|c| c.quantity.as_str()),
    );
    let mut s = format!(
        "{:<wc$}  {:<wq$}  {:>13} {:>13} {:>9} {:>8}  pass\n",
        "case", "quantity", "reference", "simulated", "rel.err", "tol"
    );
    for c in checks {
        s += &format!(
            "{:<wc$}  {:<wq$}  {:>13.6e} {:>13.6e} {:>9.2e} {:>8}  {}\n",
            c.name,
            c.quantity,
            c.reference,
            c.simulated,
            c.rel_error,
            tolerance_text(c.tolerance),
            if c.pass { "ok" } else { "FAIL" },
        );
    }
    let failed = checks.iter().filter(|c| !c.pass).count();
    s += &format!("{} passed, {} failed\n", checks.len() - failed, failed);
    s += "(the references' sources: --out DIR's validation_table.md, or --json)\n";
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every row's columns start where the header's do, whatever the lengths of the case
    /// names and quantities (Unicode included).
    #[test]
    fn the_table_columns_line_up() {
        let checks = [
            Check::new("a", "short", 1.0, "src", 1.0, 1e-6),
            Check::new(
                "a-much-longer-case",
                "a quantity, ω dt = 0.2 (m)",
                2.0,
                "s",
                2.1,
                1e-2,
            ),
        ];
        let text = table(&checks);
        let lines: Vec<&str> = text.lines().collect();
        let at = |l: &str, word: &str| l.find(word).map(|b| l[..b].chars().count());
        let pass = at(lines[0], "pass").unwrap();
        assert_eq!(at(lines[1], "ok"), Some(pass), "{text}");
        assert_eq!(at(lines[2], "FAIL"), Some(pass), "{text}");
        assert_eq!(lines[3], "1 passed, 1 failed");
        assert!(
            !text.contains("src"),
            "sources stay out of the console: {text}"
        );
    }
}
