//! The `chute` command line (clap derive): argument parsing and dispatch to [`crate::api`],
//! its only way into chute. Every error is printed as `error: <message>` on stderr and mapped to
//! [`AppError::exit_code`]; see `docs/cli.md`.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

use crate::api::{self, AppError, RunOptions, Scenario, Shard, StudyOptions};

mod view;
use view::cmd_view;

/// Parachute flight simulator for flexible canopies (DER rods and discrete shells).
#[derive(Debug, Parser)]
#[command(name = "chute", version, about)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate one scenario and write its output directory.
    Run(RunArgs),
    /// Continue an interrupted (or extend a finished) run from its directory alone.
    Resume(ResumeArgs),
    /// Validate a scenario without running it; print derived quantities.
    Check(CheckArgs),
    /// Run a study (a list or grid of cases) in parallel; write study.csv and study.md.
    Study(StudyArgs),
    /// Merge finished study cases (e.g. from several shards) into study.csv and study.md.
    Collect(CollectArgs),
    /// Solution verification: run mesh or time-step ladders, estimate order, extrapolation
    /// and GCI; write convergence.json, convergence.md and convergence.png.
    Converge(ConvergeArgs),
    /// The steady descent as an equilibrium, and the modes of the motion about it.
    Steady(SteadyArgs),
    /// Run the verification cases against analytic references.
    Validate(api::ValidateArgs),
    /// Time the solver on a ladder of mesh sizes.
    Bench(api::BenchArgs),
    /// Write RUN_DIR/viewer.html: the run in 3-D in a browser (one offline file).
    View(ViewArgs),
}

/// `chute view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// A run directory (as written by `chute run`).
    pub run_dir: PathBuf,
}

/// `chute run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Scenario file (TOML).
    #[arg(required_unless_present = "resume")]
    pub scenario: Option<PathBuf>,
    /// Output directory (default: `runs/<scenario name>`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Override a scenario key, e.g. `--set load.weight_n=20` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Overwrite an existing, non-empty output directory.
    #[arg(long)]
    pub force: bool,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Write a checkpoint every S simulated seconds.
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub checkpoint_every: Option<f64>,
    /// Retired: use `chute resume DIR` (kept so the old form gets a message saying so).
    #[arg(long, value_name = "DIR", hide = true)]
    pub resume: Option<PathBuf>,
    /// Do not write viewer.html.
    #[arg(long)]
    pub no_viewer: bool,
    /// Print summary.json on stdout (and nothing else there) instead of the summary for people.
    #[arg(long)]
    pub json: bool,
}

/// `chute resume`.
#[derive(Debug, Args)]
pub struct ResumeArgs {
    /// A run directory with a `checkpoint.bin` (written by `chute run`).
    pub run_dir: PathBuf,
    /// Only `--set time.duration_s=T`, T at least the recorded duration: extend the run.
    #[arg(long = "set", value_name = "time.duration_s=T")]
    pub set: Vec<String>,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Write a checkpoint every S simulated seconds [default: as the run did].
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub checkpoint_every: Option<f64>,
    /// Do not write viewer.html.
    #[arg(long)]
    pub no_viewer: bool,
    /// Print summary.json on stdout (and nothing else there) instead of the summary for people.
    #[arg(long)]
    pub json: bool,
}

/// `chute check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Scenario file (TOML).
    pub scenario: PathBuf,
    /// Override a scenario key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Print the fully resolved scenario (every default filled in) as TOML instead.
    #[arg(long)]
    pub resolved: bool,
}

/// `chute steady`.
#[derive(Debug, Args)]
pub struct SteadyArgs {
    /// Scenario file (TOML); it is flown for `time.duration_s` first.
    pub scenario: PathBuf,
    /// Override a scenario key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Write `stability.json` into this directory.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print `stability.json` on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// `chute study`.
#[derive(Debug, Args)]
pub struct StudyArgs {
    /// Study file (TOML).
    pub study: PathBuf,
    /// Output directory (default: `runs/<study name>`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Cases run in parallel [default: one per core].
    #[arg(long, short, value_name = "N")]
    pub jobs: Option<usize>,
    /// Override a key in every case, before the case's own overrides (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Run only cases with index % N == I (0-based) [default: from SLURM_ARRAY_TASK_ID and
    /// SLURM_ARRAY_TASK_COUNT when set].
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Re-run cases that are already complete.
    #[arg(long)]
    pub force: bool,
}

/// `chute collect`.
#[derive(Debug, Args)]
pub struct CollectArgs {
    /// Study output directories (e.g. one per shard).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Where to write study.csv and study.md [default: the first DIR].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `chute converge`.
#[derive(Debug, Args)]
pub struct ConvergeArgs {
    /// Scenario file (TOML).
    pub scenario: PathBuf,
    /// A ladder: KEY=V1,V2,V3[,…] with KEY one of canopy.edge_length_m, canopy.nodes,
    /// time.dt_s, time.error_tolerance_m (adaptive) (repeatable: one ladder each).
    #[arg(long, value_name = "KEY=V1,V2,…", required = true)]
    pub vary: Vec<String>,
    /// Override a scenario key on every level (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output directory (default: `runs/<scenario name>-converge`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Levels run in parallel [default: one per core].
    #[arg(long, short, value_name = "N")]
    pub jobs: Option<usize>,
    /// Run only levels with index % N == I (0-based) [default: from SLURM array variables].
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Re-run levels that are already complete.
    #[arg(long)]
    pub force: bool,
}

/// Entry point of the binary: parse `std::env::args`, dispatch, print any error.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            // clap prints help/version (exit 0) and usage errors (exit 2) itself.
            let _ = e.print();
            return ExitCode::from(e.exit_code().clamp(0, 255) as u8);
        }
    };
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| dispatch(cli)));
    let code = match result {
        // The work is done, but its results did not all reach stdout (a full disk behind it).
        Ok(Ok(())) if api::stdout_error().is_some() => {
            let why = api::stdout_error().unwrap_or_default();
            crate::err_line!("error: the results could not be written to stdout: {why}");
            1
        }
        Ok(Ok(())) => 0,
        Ok(Err(e)) => {
            crate::err_line!("error: {e}");
            e.exit_code()
        }
        Err(_) => {
            crate::err_line!(
                "error: internal error (a bug in chute; please report it with the input)"
            );
            1
        }
    };
    ExitCode::from(code.clamp(0, 255) as u8)
}

/// Run one parsed command.
pub fn dispatch(cli: Cli) -> Result<(), AppError> {
    match cli.command {
        Command::Run(a) => cmd_run(&a),
        Command::Resume(a) => cmd_resume(&a),
        Command::Check(a) => cmd_check(&a),
        Command::Study(a) => cmd_study(&a),
        Command::Collect(a) => cmd_collect(&a),
        Command::Converge(a) => cmd_converge(&a),
        Command::Steady(a) => cmd_steady(&a),
        Command::Validate(a) => api::validate_command(&a),
        Command::Bench(a) => api::bench_command(&a),
        Command::View(a) => cmd_view(&a),
    }
}

fn cmd_check(a: &CheckArgs) -> Result<(), AppError> {
    let s = api::load(&a.scenario, &a.set)?;
    if a.resolved {
        crate::out_text!("{}", s.to_toml());
        return Ok(());
    }
    let derived = api::check(&s)?;
    crate::out_line!("scenario `{}` ({}) is valid", s.name, a.scenario.display());
    crate::out_text!("{}", api::pairs_text(&derived));
    print_plausibility(&s);
    Ok(())
}

/// The scenario's plausibility warnings, on stderr.
fn print_plausibility(s: &Scenario) {
    for w in api::plausibility_warnings(s) {
        crate::err_line!("warning: {w}");
    }
}

/// How long after the first signal another one counts as a second (abort at once): a
/// terminal's Ctrl-C or a batch system's SIGTERM reaches every process of the group, so a
/// parent that forwards its copy (`timeout`, `srun`) delivers two within microseconds.
const SECOND_SIGNAL_AFTER: std::time::Duration = std::time::Duration::from_millis(500);

/// Route Ctrl-C / SIGTERM / SIGHUP to [`api::request_stop`]: runs stop at their next step
/// with a checkpoint and valid partial outputs. A second signal, at least
/// [`SECOND_SIGNAL_AFTER`] after the first, exits at once (status 130).
fn install_stop_handler() {
    static INSTALLED: std::sync::Once = std::sync::Once::new();
    static FIRST: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    INSTALLED.call_once(|| {
        let r = ctrlc::set_handler(|| {
            let first = *FIRST.get_or_init(std::time::Instant::now);
            if api::request_stop() {
                if first.elapsed() < SECOND_SIGNAL_AFTER {
                    return;
                }
                std::process::exit(130);
            }
            crate::err_line!("\nstopping: a run in progress writes a checkpoint and partial outputs (signal again to abort)");
        });
        if let Err(e) = r {
            crate::err_line!("warning: cannot catch Ctrl-C/SIGTERM ({e}); an interrupted run keeps only its last checkpoint");
        }
    });
}

/// A `--checkpoint-every` value, checked.
fn checkpoint_interval(c: Option<f64>) -> Result<Option<f64>, AppError> {
    match c {
        Some(c) if !(c.is_finite() && c > 0.0) => Err(AppError::Input(format!(
            "--checkpoint-every {c}: must be a positive number of simulated seconds"
        ))),
        c => Ok(c),
    }
}

fn cmd_run(a: &RunArgs) -> Result<(), AppError> {
    if let Some(r) = &a.resume {
        return Err(AppError::Input(format!(
            "`chute run --resume` is retired: continue the run with `chute resume {}` (it reads the scenario and every override from the run directory; `--set time.duration_s=T` extends it)",
            r.display()
        )));
    }
    // clap requires the scenario unless `--resume` is given, which returned above.
    let scenario = a.scenario.as_deref().unwrap_or(Path::new(""));
    let s = api::load(scenario, &a.set)?;
    let checkpoint_every_s = checkpoint_interval(a.checkpoint_every)?;
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| Path::new("runs").join(&s.name));
    let prepared = api::prepare_out_dir(&out, a.force)?;
    let opts = RunOptions {
        out_dir: out.clone(),
        force: a.force,
        progress: !a.quiet && std::io::stderr().is_terminal(),
        checkpoint_every_s,
        resume: None,
        viewer: !a.no_viewer,
        case_of: None,
    };
    let report = Report {
        json: a.json,
        quiet: a.quiet,
    };
    let result = run_and_report(&s, &opts, &report);
    prepared.release();
    result.map(drop)
}

/// How `run` and `resume` report a finished run.
struct Report {
    json: bool,
    quiet: bool,
}

/// Run, write the viewer (unless `opts.viewer` is off), print the summary; an incomplete
/// run is an error saying what to do next. The outcome is returned for a resumed study case.
fn run_and_report(
    s: &Scenario,
    opts: &RunOptions,
    r: &Report,
) -> Result<api::RunOutcome, AppError> {
    let out = &opts.out_dir;
    print_plausibility(s);
    install_stop_handler();
    let outcome = api::run_until_stopped(s, opts)?;
    if opts.viewer {
        if let Err(e) = api::write_viewer(out) {
            crate::err_line!("warning: viewer.html not written: {e}");
        }
    } else if opts.resume.is_some() {
        // The viewer of the run before it stopped would show a partial run as this one.
        let stale = out.join(api::VIEWER_HTML);
        if std::fs::symlink_metadata(&stale).is_ok_and(|m| m.is_file()) {
            let _ = std::fs::remove_file(&stale);
        }
    }
    let summary_path = out.join(api::SUMMARY);
    api::print_run_report(out, &outcome.summary, r.json, r.quiet)
        .map_err(|e| AppError::io(summary_path, e))?;
    match (outcome.complete, &outcome.message) {
        (true, Some(m)) => crate::err_line!("warning: {m}"),
        (true, None) => {}
        (false, m) => {
            return Err(AppError::RunFailed(format!(
                "stopped before time.duration_s: {}; partial outputs are in `{}`; {}",
                m.as_deref().unwrap_or("no reason given"),
                out.display(),
                next_step(out)
            )))
        }
    }
    Ok(outcome)
}

/// What to do after a run in `dir` stopped early: resume it when its checkpoint is a sync
/// point (a signal); a failed step's checkpoint holds the last good state, from which a
/// resume fails the same way.
fn next_step(dir: &Path) -> String {
    match api::checkpoint_at(dir) {
        Some((_, true)) => format!("continue with `chute resume {}`", dir.display()),
        Some((t, false)) => format!(
            "its checkpoint holds the last good state (t = {} s) for inspection; resuming would repeat the failure: change the scenario (e.g. a smaller time.dt_s, or time.adaptive = true) and run it again",
            api::sig4(t)
        ),
        None => "it has no checkpoint to resume from: run it again".into(),
    }
}

fn cmd_resume(a: &ResumeArgs) -> Result<(), AppError> {
    let dir = &a.run_dir;
    let every = checkpoint_interval(a.checkpoint_every)?;
    let crate::api::Resumable {
        scenario: s,
        mut opts,
        stopped_at,
        unrecorded,
        lock,
    } = crate::api::prepare_resume(dir, &a.set, every, !a.no_viewer)?;
    if unrecorded {
        crate::err_line!(
            "warning: `{}` has no run.json (an older chute wrote it): its input files cannot be checked against the run's",
            dir.display()
        );
    }
    opts.progress = !a.quiet && std::io::stderr().is_terminal();
    let report = Report {
        json: a.json,
        quiet: a.quiet,
    };
    let started = std::time::Instant::now();
    let result = run_and_report(&s, &opts, &report);
    // A study case says how it ended in its marker too, and no longer matches its study's
    // inputs once the resume extended it.
    let extended = (stopped_at != Some(s.time.duration_s)).then_some(s.time.duration_s);
    let marked = api::mark_resumed(dir, &result, started.elapsed().as_secs_f64(), extended);
    drop(lock);
    result?;
    marked
}

fn cmd_study(a: &StudyArgs) -> Result<(), AppError> {
    let st = api::load_study(&a.study)?;
    let shard = match &a.shard {
        Some(s) => Some(Shard::parse(s)?),
        None => Shard::from_slurm(slurm_var).transpose()?,
    };
    if a.jobs == Some(0) {
        return Err(AppError::Input("--jobs must be at least 1".into()));
    }
    let opts = StudyOptions {
        out_dir: a
            .out
            .clone()
            .unwrap_or_else(|| Path::new("runs").join(&st.name)),
        jobs: a.jobs,
        set: a.set.clone(),
        shard,
        force: a.force,
        verbose: true,
    };
    install_stop_handler();
    let report = api::run_study(&st, &opts)?;
    crate::out_text!("{}", report.table.to_markdown());
    warn_stale(&report.table);
    let failed = report.failures();
    if failed > 0 {
        return Err(AppError::RunFailed(format!(
            "{failed} of {} case(s) failed, stopped early or were not run; see the lines above (and `{}/<case>/done.json` of a case that ran)",
            report.cases.len(),
            opts.out_dir.display()
        )));
    }
    Ok(())
}

fn cmd_collect(a: &CollectArgs) -> Result<(), AppError> {
    for d in &a.dirs {
        if !d.is_dir() {
            return Err(AppError::Input(format!(
                "`{}` is not a directory",
                d.display()
            )));
        }
    }
    let out = a.out.clone().unwrap_or_else(|| a.dirs[0].clone());
    let table = api::collect(&a.dirs, &out)?;
    crate::out_text!("{}", table.to_markdown());
    warn_stale(&table);
    crate::err_line!(
        "wrote {} and {}",
        out.join("study.csv").display(),
        out.join("study.md").display()
    );
    // A table that lacks a case, or holds one that did not finish, is not the study's
    // result: it is written (to see what is there) but the command fails.
    let unfinished = table.unfinished();
    for line in &unfinished {
        crate::err_line!("warning: {line}");
    }
    if !unfinished.is_empty() {
        let complete = table.rows.iter().filter(|r| r.complete).count();
        let n = table.rows.len();
        // Every row complete, and still not the study's result: its case list is uncertain
        // (or a row is stale), as the warnings above say.
        let why = match complete == n {
            true => "but the table cannot be called the whole study: see the warnings above",
            false => "each other one is named above, and has its status in the table",
        };
        return Err(AppError::RunFailed(format!(
            "the study is not complete: {complete} of {n} case(s) found complete ({why})"
        )));
    }
    Ok(())
}

/// A warning per table row whose inputs are not what its study would run now (the row's
/// `inputs` cell says `changed` or `unknown`).
fn warn_stale(table: &api::Table) {
    for w in table.input_warnings() {
        crate::err_line!("warning: {w}");
    }
}

fn cmd_converge(a: &ConvergeArgs) -> Result<(), AppError> {
    let shard = match &a.shard {
        Some(s) => Some(Shard::parse(s)?),
        None => Shard::from_slurm(slurm_var).transpose()?,
    };
    if a.jobs == Some(0) {
        return Err(AppError::Input("--jobs must be at least 1".into()));
    }
    let out_dir = match &a.out {
        Some(d) => d.clone(),
        None => api::converge_out_dir(&a.scenario, &a.set)?,
    };
    let opts = api::ConvergeOptions {
        scenario: a.scenario.clone(),
        vary: a.vary.clone(),
        set: a.set.clone(),
        out_dir,
        jobs: a.jobs,
        shard,
        force: a.force,
        verbose: true,
    };
    install_stop_handler();
    let outcome = api::converge(&opts)?;
    crate::out_text!("{}", outcome.report.to_markdown());
    let dir = opts.out_dir.display();
    for w in &outcome.warnings {
        crate::err_line!("warning: {w}");
    }
    let png = match outcome.warnings.is_empty() {
        true => " and convergence.png",
        false => "",
    };
    crate::err_line!("wrote {dir}/convergence.json, convergence.md{png}");
    if outcome.pending > 0 {
        let why = match opts.shard {
            Some(_) => "other shards); re-run without --shard to complete the estimates",
            None => "the run was stopped first); run the same command again to complete them",
        };
        crate::err_line!("note: {} level(s) not run yet ({why}", outcome.pending);
    }
    if !outcome.failures.is_empty() {
        return Err(AppError::RunFailed(format!(
            "{} level(s) failed or stopped early; the others are summarised in {dir}/convergence.md:\n  {}",
            outcome.failures.len(),
            outcome.failures.join("\n  ")
        )));
    }
    Ok(())
}

/// A SLURM variable as text: unset is `None`; a value that is not UTF-8 is kept (lossily) so
/// that it is refused as a bad value, not taken as unset (which would run every case).
fn slurm_var(key: &str) -> Option<String> {
    std::env::var_os(key).map(|v| v.to_string_lossy().into_owned())
}

fn cmd_steady(a: &SteadyArgs) -> Result<(), AppError> {
    let s = api::load(&a.scenario, &a.set)?;
    if let Some(dir) = &a.out {
        api::check_stability_out(dir)?;
    }
    print_plausibility(&s);
    crate::err_line!(
        "steady: flying `{}` for {} s first (no outputs; longer if no equilibrium is near), then its equilibrium and modes",
        s.name,
        s.time.duration_s
    );
    let r = api::steady(&s)?;
    if let Some(dir) = &a.out {
        api::write_stability(&r, dir)?;
    }
    if a.json {
        let text = serde_json::to_string_pretty(&r).map_err(|e| AppError::Input(e.to_string()))?;
        crate::out_line!("{text}");
    } else {
        crate::out_text!("{}", api::stability_table(&r));
    }
    Ok(())
}
