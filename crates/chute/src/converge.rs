//! `chute converge`: solution verification of one scenario. Each `--vary KEY=V1,V2,…` is a
//! ladder of levels (mesh size or time step) run as the cases of one study (parallel,
//! shardable, resumable: [`crate::study`]); the headline quantities of each ladder are then
//! estimated by Celik's procedure ([`gci`]) into `convergence.json`, `convergence.md` and
//! `convergence.png`. See docs/convergence.md for the method and docs/cli.md for the command.

pub mod analyse;
pub mod gci;
pub mod plan;
pub mod plot;
pub mod report;

use std::path::{Path, PathBuf};

use crate::app::{self, AppError};
use crate::study::{self, Shard, StudyOptions};
pub use report::ConvergenceReport;

/// How to run `chute converge`.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvergeOptions {
    /// The scenario file.
    pub scenario: PathBuf,
    /// `KEY=V1,V2,…`, one ladder each.
    pub vary: Vec<String>,
    /// Overrides applied to every level, before the varied key.
    pub set: Vec<String>,
    /// Output directory: levels in `<out>/<case>/`, the reports in `<out>/`.
    pub out_dir: PathBuf,
    /// Levels run in parallel (default: one per core).
    pub jobs: Option<usize>,
    /// Run only this shard of the levels.
    pub shard: Option<Shard>,
    /// Re-run levels that are already complete.
    pub force: bool,
    /// One line per level on stderr.
    pub verbose: bool,
}

/// What `chute converge` produced.
#[derive(Debug, Clone)]
pub struct ConvergeOutcome {
    /// The report written to `convergence.json`.
    pub report: ConvergenceReport,
    /// Levels that failed or stopped early (`key=value: message`).
    pub failures: Vec<String>,
    /// Levels not run yet (other shards, or a study stopped before them).
    pub pending: usize,
    /// What was not written (a picture on a full disk), as sentences.
    pub warnings: Vec<String>,
}

/// The default output directory: `runs/<scenario name>-converge`.
pub fn default_out_dir(scenario: &Path, set: &[String]) -> Result<PathBuf, AppError> {
    let s = crate::scenario::Scenario::load(scenario, set)?;
    Ok(Path::new("runs").join(format!("{}-converge", s.name)))
}

/// Run with the real simulation.
pub fn run_converge(opts: &ConvergeOptions) -> Result<ConvergeOutcome, AppError> {
    run_converge_with(opts, &app::run)
}

/// Plan the ladders (every input error first, exit 2), run the levels as a study with
/// `runner` (a finished level is reused only for the same inputs, else re-run: the study's
/// rule), and write the reports.
pub fn run_converge_with(
    opts: &ConvergeOptions,
    runner: &study::Runner,
) -> Result<ConvergeOutcome, AppError> {
    // Read once per level: a pipe (`<(…)`) would be empty after the first, a FIFO waited on.
    if let Some(why) = crate::output::atomic::not_plain(&opts.scenario, "scenario") {
        return Err(AppError::Input(format!(
            "{why}: a ladder reads its scenario once per level; give a file"
        )));
    }
    // `/dev/stdin` redirected from a file is that file: its relative mesh is next to it.
    let scenario = &study::recorded_path(&opts.scenario);
    let name = crate::scenario::Scenario::load(scenario, &opts.set)?.name;
    let plan = plan::plan(scenario, &format!("{name}-converge"), &opts.vary, &opts.set)?;
    let study_opts = StudyOptions {
        out_dir: opts.out_dir.clone(),
        jobs: opts.jobs,
        set: opts.set.clone(),
        shard: opts.shard,
        force: opts.force,
        verbose: opts.verbose,
    };
    let ran = study::run_study_with(&plan.study, &study_opts, runner)?;
    // The inputs each level has in this ladder, to tell its recorded run from another's.
    let digest = |case: &str| {
        let c = plan.study.cases.iter().find(|c| c.name == case)?;
        let s = plan.study.scenario(c, &opts.set).ok()?;
        Some((study::inputs::digest(&s).ok()?, s.input_files()))
    };
    // Why a level this invocation selected was not run (its directory unusable, a full
    // disk), when it was not for a stop or another shard.
    let not_run = |case: &str| {
        ran.cases.iter().find_map(|(name, st)| match st {
            study::CaseStatus::Failed(m) if name == case && !m.contains("was stopped") => {
                Some(m.clone())
            }
            _ => None,
        })
    };
    // Whether this invocation ran the level (or found it finished) itself.
    let ran_here = |case: &str| {
        ran.cases.iter().any(|(name, st)| {
            name == case && matches!(st, study::CaseStatus::Complete | study::CaseStatus::Skipped)
        })
    };
    // The levels are read and the reports written under OUT's lock, as a study's table is:
    // two shards finishing together write one after the other, each from what it read.
    let held = study::hold_out(
        &opts.out_dir,
        "its levels ran, but its reports were not written: run it again (without --force its finished levels are skipped)",
    )?;
    let mut studies = Vec::new();
    let (mut failures, mut pending) = (Vec::new(), 0);
    for ladder in &plan.ladders {
        let results: Vec<analyse::LevelResult> = ladder
            .levels
            .iter()
            .map(|l| {
                let r = analyse::read_level(&opts.out_dir.join(&l.case), digest(&l.case).as_ref());
                let mut r = changed_while_running(r, ran_here(&l.case));
                // Why this invocation could not run it, in the reports as on the console.
                if r.status == "not run" && r.message.is_none() {
                    r.message = not_run(&l.case);
                }
                r
            })
            .collect();
        for (l, r) in ladder.levels.iter().zip(&results) {
            match r.status.as_str() {
                "complete" => {}
                "not run" => match not_run(&l.case) {
                    Some(m) => {
                        failures.push(format!("{}={} ({}): {m}", ladder.key, l.text, l.case))
                    }
                    None => pending += 1,
                },
                s => failures.push(format!(
                    "{}={} ({}): {s}: {}",
                    ladder.key,
                    l.text,
                    l.case,
                    r.message.as_deref().unwrap_or("no reason given")
                )),
            }
        }
        studies.push(analyse::analyse(ladder, &results));
    }
    let report = ConvergenceReport {
        written_by: self::report::WRITTEN_BY,
        scenario: opts.scenario.display().to_string(),
        set: opts.set.clone(),
        studies,
    };
    let warnings = write_reports(&opts.out_dir, &report)?;
    drop(held);
    Ok(ConvergeOutcome {
        report,
        failures,
        pending,
        warnings,
    })
}

/// A level this invocation ran whose record is of other inputs than the ladder's now: its
/// inputs (a mesh) changed while the ladder ran, not an earlier ladder's level.
fn changed_while_running(r: analyse::LevelResult, ran_here: bool) -> analyse::LevelResult {
    match r.status.as_str() {
        "not run" if ran_here => analyse::LevelResult {
            status: "failed".into(),
            message: Some(
                "its inputs changed while the ladder ran (an input file was edited): run the ladder again".into(),
            ),
            ..r
        },
        _ => r,
    }
}

/// A ladder's reports in its output directory (taken down with the table while the ladder
/// runs: `study::run_study_with`).
pub(crate) const REPORT_FILES: [&str; 3] =
    ["convergence.json", "convergence.md", "convergence.png"];

/// Write the JSON and Markdown reports (an error when they cannot be), and the picture (a
/// warning when it cannot be, as a run's pictures: the numbers are in the reports).
fn write_reports(out: &Path, report: &ConvergenceReport) -> Result<Vec<String>, AppError> {
    // A file of the user's put there while the levels ran is not replaced.
    crate::study::refuse_users_tables(out, true)?;
    let [json, md, png] = REPORT_FILES.map(|f| out.join(f));
    study::write_atomic(&json, report.to_json().as_bytes())?;
    // Both or neither: a JSON report beside no Markdown (a full disk) is half a report.
    let text = format!("{}{}", report.to_markdown(), self::report::MD_MARK);
    study::write_atomic(&md, text.as_bytes()).inspect_err(|_| {
        let _ = std::fs::remove_file(&json);
    })?;
    Ok(match plot::convergence_plot(&png, &report.studies) {
        Ok(()) => Vec::new(),
        Err(e) => {
            // An earlier ladder's picture must not stand beside these reports.
            let gone = std::fs::symlink_metadata(&png).is_ok_and(|m| m.is_file())
                && std::fs::remove_file(&png).is_ok();
            let earlier = match gone {
                true => " (the earlier picture was removed)",
                false => "",
            };
            vec![format!("{} was not written: {e}{earlier}", png.display())]
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A level that this invocation ran but whose record is of other inputs than the
    /// ladder's now (a mesh edited while it ran, and left so) is failed, not "not run" (which
    /// a shard's or an earlier ladder's level is, and which exits 0).
    #[test]
    fn a_level_run_here_with_other_inputs_is_failed() {
        let not_run = || analyse::LevelResult {
            status: "not run".into(),
            message: Some("its directory holds a run of other inputs".into()),
            values: Vec::new(),
            wall_time_s: None,
        };
        let r = changed_while_running(not_run(), true);
        assert_eq!(r.status, "failed");
        assert!(r.message.unwrap().contains("changed while the ladder ran"));
        assert_eq!(changed_while_running(not_run(), false).status, "not run");
    }
}
