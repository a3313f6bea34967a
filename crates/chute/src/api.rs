//! The front door: chute's commands as functions, with their options, outputs and errors.
//! A program driving chute (the Python bindings, a script's own Rust) calls only this module:
//! load a scenario, run it into a directory or step it in a loop of its own, run a study,
//! validate, write the viewer, read a run's frames. Every error is an [`AppError`], whose
//! class is the command line's exit status (docs/cli.md §Exit codes). The other modules are
//! chute's internals, public for the command line and the tests, not a stable interface
//! (docs/architecture.md §Application).

use std::path::{Path, PathBuf};

pub use crate::app::view::Viewed;
pub use crate::app::{AppError, Prepared, Resumable, RunOptions, RunOutcome, Watch};
pub use crate::bench::BenchArgs;
pub use crate::converge::{ConvergeOptions, ConvergeOutcome};
pub use crate::output::console::{pairs_text, print_run_report, stdout_error};
pub use crate::output::run_dir::{FrameMesh, FrameState, RunDirError};
pub use crate::output::run_files::SUMMARY;
pub use crate::output::viewer::ViewerReport;
pub use crate::output::viewer::VIEWER_HTML;
pub use crate::runner::Session;
pub use crate::scenario::derived::sig4;
pub use crate::scenario::{Scenario, ScenarioError};
pub use crate::steady::{ModeRecord, SteadyReport, MODES_HTML, STABILITY_JSON};
pub use crate::study::{
    mark_resumed, Case, CaseStatus, Runner, Shard, Study, StudyOptions, StudyReport, Table,
};
pub use crate::verify::{Check, ValidateArgs};

/// Read scenario `path` with `set` overrides (`KEY=VALUE`, as `chute run --set`), validated.
pub fn load(path: &Path, set: &[String]) -> Result<Scenario, AppError> {
    Ok(Scenario::load(path, set)?)
}

/// Make `out` a run's directory and hold it (its lock) until the returned guard is dropped:
/// created when missing; with `force`, an earlier chute run there may be replaced.
pub fn prepare_out_dir(out: &Path, force: bool) -> Result<Prepared, AppError> {
    crate::app::prepare_out_dir(out, force)
}

/// Run `s` into `opts.out_dir` as `chute run` does (its outputs, docs/outputs.md), watched by
/// the caller: `watch.stop` ends it at the next step (saving what it has), and
/// `watch.sim_time` follows its simulated time.
pub fn run(s: &Scenario, opts: &RunOptions, watch: Watch<'_>) -> Result<RunOutcome, AppError> {
    crate::app::run_watched(s, opts, watch)
}

/// Make run directory `dir` ready to continue (`chute resume`), holding it: only
/// `time.duration_s` may change in `set`; a checkpoint every `every` simulated seconds (`None`:
/// as the run did); the viewer when `viewer` and the run wrote one. Run it with [`run`].
pub fn prepare_resume(
    dir: &Path,
    set: &[String],
    every: Option<f64>,
    viewer: bool,
) -> Result<Resumable, AppError> {
    crate::app::resume::prepare(dir, set, every, viewer)
}

/// [`run`] watched by this process's stop requests ([`request_stop`]), as `chute run` is.
pub fn run_until_stopped(s: &Scenario, opts: &RunOptions) -> Result<RunOutcome, AppError> {
    crate::app::run(s, opts)
}

/// A run of `s` that the caller steps ([`Session::step`]), writing nothing.
pub fn session(s: &Scenario) -> Result<Session, AppError> {
    let built = crate::build::build(s)?;
    Session::new(built, crate::app::run_config(s, false))
        .map_err(|e| AppError::RunFailed(e.to_string()))
}

/// Read study file `path` (docs/cli.md §`chute study`).
pub fn load_study(path: &Path) -> Result<Study, AppError> {
    Study::load(path)
}

/// Whether `case` of `study` has a finished run of the inputs it would run now in `out`
/// (`chute study` would skip it).
pub fn case_is_current(study: &Study, case: &Case, set: &[String], out: &Path) -> bool {
    crate::study::case_is_current(study, case, set, out)
}

/// Run `study`'s cases with `runner` (usually [`run`] with the caller's watch), then write
/// its table, as `chute study` does.
pub fn study(study: &Study, opts: &StudyOptions, runner: &Runner) -> Result<StudyReport, AppError> {
    crate::study::run_study_with(study, opts, runner)
}

/// The verification suite (`chute validate`): every check with its reference and verdict.
pub fn validate(args: &ValidateArgs) -> Vec<Check> {
    crate::verify::run_suite(args)
}

/// Write (or rewrite) the run directory's `viewer.html`, as a run does at its end.
pub fn write_viewer(dir: &Path) -> Result<ViewerReport, RunDirError> {
    crate::output::viewer::write_viewer(dir)
}

/// `chute view`: [`write_viewer`] while holding the directory like any writer, with why its run
/// did not finish when it did not.
pub fn view(dir: &Path) -> Result<Viewed, AppError> {
    crate::app::view::view(dir)
}

/// The frames `dir`'s `canopy.pvd` lists: `(time, frame file)` in order.
pub fn frame_list(dir: &Path) -> Result<Vec<(f64, PathBuf)>, RunDirError> {
    crate::output::run_dir::read_pvd(dir)
}

/// One frame file: its mesh (nodes, triangles, segments) and state (positions, velocities).
pub fn read_frame(path: &Path) -> Result<(FrameMesh, FrameState), RunDirError> {
    crate::output::run_dir::read_frame(path)
}

/// What `chute check` prints of a valid scenario: its derived quantities as (label, value).
pub fn check(s: &Scenario) -> Result<Vec<(String, String)>, AppError> {
    crate::app::check(s)
}

/// Warnings about a valid scenario that is probably not what its author meant.
pub fn plausibility_warnings(s: &Scenario) -> Vec<String> {
    crate::scenario::plausibility::warnings(s)
}

/// Ask every run of this process to stop at its next step, writing a checkpoint and partial
/// outputs (what Ctrl-C does); `true` when a stop had already been asked for.
pub fn request_stop() -> bool {
    crate::runner::STOP.swap(true, std::sync::atomic::Ordering::SeqCst)
}

/// The time (s) of `dir`'s checkpoint and whether it is a sync point (a resume continues
/// from it); `None` without a readable checkpoint.
pub fn checkpoint_at(dir: &Path) -> Option<(f64, bool)> {
    crate::checkpoint::Checkpoint::read(dir)
        .ok()
        .map(|c| (c.t, c.synced))
}

/// Run `study` with the real simulation and write its table (`chute study`).
pub fn run_study(study: &Study, opts: &StudyOptions) -> Result<StudyReport, AppError> {
    crate::study::run_study(study, opts)
}

/// Gather the cases of `dirs` into one table written into `out` (`chute collect`).
pub fn collect(dirs: &[PathBuf], out: &Path) -> Result<Table, AppError> {
    crate::study::collect(dirs, out)
}

/// Run a convergence ladder and write its reports (`chute converge`).
pub fn converge(opts: &ConvergeOptions) -> Result<ConvergeOutcome, AppError> {
    crate::converge::run_converge(opts)
}

/// Where `chute converge` writes a ladder of `scenario` by default.
pub fn converge_out_dir(scenario: &Path, set: &[String]) -> Result<PathBuf, AppError> {
    crate::converge::default_out_dir(scenario, set)
}

/// `chute validate`: run the suite, print its table (or JSON) and write its reports;
/// `Err(ValidationFailed)` when a check fails.
pub fn validate_command(args: &ValidateArgs) -> Result<(), AppError> {
    crate::verify::main(args)
}

/// `chute bench`: the benchmark ladder, or with `--case` one case in this process.
pub fn bench_command(args: &BenchArgs) -> Result<(), AppError> {
    crate::bench::main(args)
}

/// `chute steady`: fly `s` for `time.duration_s`, then solve its steady descent and the modes
/// about it (docs/cli.md §`chute steady`).
pub fn steady(s: &Scenario) -> Result<SteadyReport, AppError> {
    crate::steady::steady(s)
}

/// The console table of a [`steady`] report.
pub fn stability_table(r: &SteadyReport) -> String {
    crate::steady::table(r)
}

/// Refuse `dir` as [`write_stability`]'s directory when it holds anything else.
pub fn check_stability_out(dir: &Path) -> Result<(), AppError> {
    crate::steady::check_out(dir)
}

/// Write a [`steady`] report as `dir/stability.json`.
pub fn write_stability(r: &SteadyReport, dir: &Path) -> Result<(), AppError> {
    crate::steady::write(r, dir)
}
