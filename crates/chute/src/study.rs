//! Studies: one base scenario run under a list (`[[case]]`), a grid (`[grid]`) or a dispersion
//! (`[dispersion]`, random draws) of overrides,
//! cases in parallel, each into `OUT/<case>/` with a `done.json` marker, then one table
//! (`study.csv`, `study.md`) with a row per case. See `docs/cli.md` §study.

mod case_run;
mod case_state;
mod collect;
mod dispersion;
pub mod dispersion_out;
pub mod draw;
mod expected;
pub mod footprint;
mod gathered;
mod grid;
pub mod inputs;
mod objective;
mod owner;
mod resumed;
mod skip;
pub(crate) use owner::{hold_out, refuse_users_tables};
pub(crate) use skip::read_other_inputs;
mod table;

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::Deserialize;

use crate::app::{self, AppError, RunOptions, RunOutcome};
use crate::scenario::source::line_col;
use crate::scenario::Scenario;
pub use collect::collect;
pub use inputs::InputsState;
pub use objective::Objective;
pub use resumed::mark_resumed;
pub use table::{gather, write_atomic, write_table, CaseState, Row, Table};

/// The summary metrics that become table columns, after the case name and its overrides.
pub const METRIC_COLUMNS: &[&str] = &[
    "terminal_velocity_mps",
    "time_to_terminal_s",
    "reached_terminal",
    "max_extended_height_m",
    "force_balance_error",
];

/// Summary fields of runs that reach the ground, shown as columns after
/// [`METRIC_COLUMNS`] when any row has a value (a table of descents without a ground keeps
/// its columns).
pub const LANDING_COLUMNS: &[&str] = &[
    "landing_velocity_mps",
    "flight_time_s",
    "peak_line_tension_n",
];

/// Name of the per-case marker written when a case has finished (whatever its outcome).
pub const DONE_FILE: &str = "done.json";

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyFile {
    name: Option<String>,
    #[serde(default)]
    description: Option<String>,
    base: String,
    /// The quantity whose smallest case the table names (`field` or `|field|`).
    minimise: Option<String>,
    #[serde(default)]
    case: Vec<CaseSpec>,
    grid: Option<toml::Table>,
    dispersion: Option<dispersion::DispersionSpec>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseSpec {
    name: String,
    #[serde(default)]
    set: Vec<String>,
}

/// One case of a study.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    /// 0-based position in the study (the shard selector uses it).
    pub index: usize,
    /// Directory-safe name; the case's output is `OUT/<name>/`.
    pub name: String,
    /// The case's own `--set` overrides, applied after the study-wide ones.
    pub set: Vec<String>,
}

/// The absolute path by which a study records `path` (its study file, or a ladder's base).
/// `/dev/stdin` redirected from a file is that file: recorded by the name it was given, it
/// would be whatever a later reader's standard input is.
pub(crate) fn recorded_path(path: &Path) -> PathBuf {
    let given = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let device = given.starts_with("/dev") || given.starts_with("/proc");
    let real = path.canonicalize().ok().filter(|p| device && p.is_file());
    real.unwrap_or(given)
}

/// A parsed study file.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// Study name (default: the file stem).
    pub name: String,
    /// Free text, shown nowhere but kept for the reader.
    pub description: Option<String>,
    /// The study file (absolute), recorded with each case so that `chute collect` can tell
    /// whether the case is still what the study would run; `None` for a study built in code
    /// (`chute converge`), whose cases are then re-derived from `base` and their own `set`.
    pub file: Option<PathBuf>,
    /// Digest of everything the study runs (every case's inputs under the study-wide
    /// overrides), recorded with each case: `chute collect` tells a copy of the study (shards
    /// run from copies elsewhere) from another study of the same file name and case names,
    /// whatever made them differ (the study file, the base, a mesh). Set when the study runs.
    pub content_digest: Option<String>,
    /// The base scenario file, resolved against the study file's directory.
    pub base: PathBuf,
    /// The cases, in file order (grid: key order, last key fastest).
    pub cases: Vec<Case>,
    /// What the table's best case minimises (`minimise`), if anything.
    pub objective: Option<objective::Objective>,
    /// The keys a `[dispersion]` draws (`key` or `key[i]`, in its order), when the cases are
    /// its samples: the study also writes their landings and footprint.
    pub dispersion: Option<Vec<String>>,
}

fn input(msg: impl Into<String>) -> AppError {
    AppError::Input(msg.into())
}

/// A directory-safe name: ASCII letters, digits, `-`, `_` and `.` kept, anything else `_`.
pub(crate) fn safe_name(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect()
}

impl Study {
    /// Read and check a study file (not yet its cases' scenarios: see [`Study::scenario`]).
    pub fn load(path: &Path) -> Result<Study, AppError> {
        let cannot = |why: String| {
            input(format!(
                "cannot read study file `{}`: {why}",
                path.display()
            ))
        };
        let max = crate::scenario::MAX_SCENARIO_BYTES;
        match std::fs::metadata(path) {
            Ok(m) if !m.is_file() => return Err(cannot("it is not a plain file".into())),
            Ok(m) if m.len() > max => {
                return Err(cannot(format!(
                    "it is {} bytes; a study file is at most {max}",
                    m.len()
                )))
            }
            _ => {}
        }
        let bytes = crate::mesh::read_capped(path, max).map_err(|e| match e {
            crate::mesh::ReadCapped::TooLong(len) => cannot(format!(
                "it is at least {len} bytes; a study file is at most {max}"
            )),
            crate::mesh::ReadCapped::Io(e) => cannot(e.to_string()),
        })?;
        let text = String::from_utf8(bytes).map_err(|_| cannot("it is not UTF-8 text".into()))?;
        // A relative base is next to the study file: the file `/dev/stdin` reads, not `/dev`.
        let dir = crate::scenario::source_dir(&recorded_path(path));
        let mut st = Study::from_str(&text, &path.display().to_string(), &dir)?;
        st.file = Some(recorded_path(path));
        // Read once per case: a FIFO or a device there would be waited on, or read forever.
        match crate::output::atomic::not_plain(&st.base, "base scenario") {
            Some(why) => Err(input(format!("{}: {why}", path.display()))),
            None => Ok(st),
        }
    }

    /// [`Study::load`] of a study file a case recorded (`collect` reads it back): it must be a
    /// plain file, so that one replaced by a FIFO since is named instead of waited on (a
    /// study given on the command line may be a pipe; this one has no writer).
    pub fn load_recorded(path: &Path) -> Result<Study, AppError> {
        // A study read from a pipe recorded the pipe's name: read back, it would be this
        // process's own standard input.
        let pipe = ["/dev/stdin", "/dev/fd", "/proc"];
        if pipe.iter().any(|p| path.starts_with(p)) {
            return Err(input(format!(
                "study file `{}` was a pipe, which cannot be read back",
                path.display()
            )));
        }
        match crate::output::atomic::not_plain(path, "study file") {
            Some(why) => Err(input(why)),
            None => Study::load(path),
        }
    }

    /// Parse study text; `base` resolves against `dir`.
    pub fn from_str(text: &str, file: &str, dir: &Path) -> Result<Study, AppError> {
        let f: StudyFile = toml::from_str(text).map_err(|e| {
            let (line, col) = e.span().map_or((1, 1), |s| line_col(text, s.start));
            input(format!("{file}:{line}:{col}: {}", e.message().trim()))
        })?;
        // Its name is a directory name (`runs/<name>` by default): given, it must be one as
        // it is; taken from the file's name, it is made one.
        let dir_name = |n: &str| !n.is_empty() && safe_name(n) == n && !n.starts_with('.');
        let name = match f.name {
            Some(n) if !dir_name(&n) => {
                return Err(input(format!(
                    "{file}: study name `{n}` is not a directory name (it names the output directory runs/<name>): use letters, digits, '-', '_' or '.', not starting with '.'"
                )))
            }
            Some(n) => n,
            None => Path::new(file)
                .file_stem()
                .map(|s| safe_name(&s.to_string_lossy()))
                .filter(|n| dir_name(n))
                .unwrap_or_else(|| "study".into()),
        };
        let objective = f
            .minimise
            .as_deref()
            .map(objective::Objective::parse)
            .transpose()
            .map_err(|e| input(format!("{file}: {e}")))?;
        let kinds = [f.grid.is_some(), !f.case.is_empty(), f.dispersion.is_some()];
        let mut cases = match (&f.grid, &f.dispersion, f.case.is_empty()) {
            _ if kinds.iter().filter(|&&k| k).count() > 1 => {
                return Err(input(format!(
                    "{file}: give one of `[[case]]` tables, a `[grid]` or a `[dispersion]`"
                )))
            }
            (None, None, true) => {
                return Err(input(format!(
                    "{file}: no cases: add `[[case]]` tables, a `[grid]` or a `[dispersion]`"
                )))
            }
            (Some(g), _, _) => grid::cases(g).map_err(|e| input(format!("{file}: {e}")))?,
            (_, Some(d), _) => d
                .cases(&dir.join(&f.base))
                .map_err(|e| input(format!("{file}: {e}")))?,
            (None, None, false) => f
                .case
                .into_iter()
                .enumerate()
                .map(|(index, c)| Case {
                    index,
                    name: c.name,
                    set: c.set,
                })
                .collect(),
        };
        let mut seen = std::collections::HashSet::new();
        for c in &mut cases {
            let ok = !c.name.is_empty() && safe_name(&c.name) == c.name && !c.name.starts_with('.');
            if !ok {
                // Each case is run in `OUT/<name>`: a name that is not one plain directory
                // name (empty, a path, hidden) would write elsewhere.
                let what = match c.name.is_empty() {
                    true => "a case name is empty".to_string(),
                    false => format!("case name `{}` is not a plain directory name", c.name),
                };
                return Err(input(format!(
                    "{file}: {what}: use letters, digits, '-', '_' or '.', not starting with '.'"
                )));
            }
            if ["study.csv", "study.md"].contains(&c.name.as_str()) {
                return Err(input(format!(
                    "{file}: case name `{}` is the name of the study's table, which goes beside the cases",
                    c.name
                )));
            }
            if !seen.insert(c.name.clone()) {
                return Err(input(format!("{file}: two cases are named `{}`", c.name)));
            }
        }
        Ok(Study {
            name,
            description: f.description,
            file: None,
            content_digest: None,
            base: dir.join(&f.base),
            cases,
            objective,
            dispersion: f.dispersion.as_ref().map(|d| d.varied_keys()),
        })
    }

    /// The validated scenario of one case: the base file with the study-wide overrides, then
    /// the case's own, and the name `<study>-<case>`.
    pub fn scenario(&self, case: &Case, global_set: &[String]) -> Result<Scenario, AppError> {
        if let Some(drawn) = &self.dispersion {
            dispersion::refuse_drawn_overrides(drawn, global_set, "--set", true)?;
        }
        let mut set: Vec<String> = global_set.to_vec();
        set.extend(case.set.iter().cloned());
        set.push(format!("name={}-{}", self.name, case.name));
        Scenario::load(&self.base, &set)
            .map_err(|e| input(format!("study `{}`, case `{}`: {e}", self.name, case.name)))
    }
}

/// Which part of a study this process runs: cases with `index % count == index_of_shard`.
/// Shards are 0-based, like SLURM array task ids by default.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, 0-based, `< count`.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// Parse `I/N` (0 ≤ I < N).
    pub fn parse(s: &str) -> Result<Shard, AppError> {
        let bad = || {
            input(format!(
                "invalid shard `{s}`: expected I/N with 0 ≤ I < N, e.g. `--shard 0/4`"
            ))
        };
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The shard of a SLURM array task: `SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN` (MIN
    /// defaults to 0) of `SLURM_ARRAY_TASK_COUNT`; `None` outside an array job. `var` reads
    /// an environment variable (a parameter so tests need not touch the environment).
    ///
    /// Only an array of consecutive ids makes every shard run: one with a step
    /// (`--array=1-5:2`: ids 1, 3, 5, `SLURM_ARRAY_TASK_STEP` = 2) or a list with gaps
    /// (`--array=0,2,5`: MAX − MIN + 1 ≠ COUNT) would leave shards unrun, so it is refused in
    /// every task, naming the array.
    pub fn from_slurm(var: impl Fn(&str) -> Option<String>) -> Option<Result<Shard, AppError>> {
        let id = var("SLURM_ARRAY_TASK_ID")?;
        // A task id without the array's size cannot say which shard this is: running every
        // case in every task would repeat them all.
        let Some(count) = var("SLURM_ARRAY_TASK_COUNT") else {
            return Some(Err(input(
                "SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not, so this task's shard is unknown; pass --shard I/N",
            )));
        };
        let min = var("SLURM_ARRAY_TASK_MIN").unwrap_or_else(|| "0".into());
        let parse = |name: &str, v: &str| {
            v.trim().parse::<usize>().map_err(|_| {
                input(format!(
                    "environment variable {name}=`{v}` is not a non-negative integer"
                ))
            })
        };
        let optional = |name: &str| var(name).map(|v| parse(name, &v)).transpose();
        Some((|| {
            let (id, count, min) = (
                parse("SLURM_ARRAY_TASK_ID", &id)?,
                parse("SLURM_ARRAY_TASK_COUNT", &count)?,
                parse("SLURM_ARRAY_TASK_MIN", &min)?,
            );
            let step = optional("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1);
            let max = optional("SLURM_ARRAY_TASK_MAX")?;
            let gaps = max.is_some_and(|max| max.checked_sub(min).map(|d| d + 1) != Some(count));
            if step != 1 || gaps {
                return Err(input(format!(
                    "this SLURM array's task ids are not consecutive (min {min}, max {}, step {step}, {count} tasks), so some of its {count} shards would never run; use an array without a step or gaps (`--array=0-{}`), or pass --shard I/N",
                    max.map_or("?".to_string(), |m| m.to_string()),
                    count.saturating_sub(1)
                )));
            }
            let index = id
                .checked_sub(min)
                .ok_or_else(|| input("SLURM_ARRAY_TASK_ID is below SLURM_ARRAY_TASK_MIN"))?;
            Shard::parse(&format!("{index}/{count}")).map_err(|_| {
                input(format!(
                    "SLURM array task {id} (min {min}) is not one of {count} consecutive tasks; use an array without a step, or pass --shard I/N"
                ))
            })
        })())
    }

    /// Whether this shard runs the case with this 0-based index.
    pub fn contains(&self, index: usize) -> bool {
        index % self.count == self.index
    }
}

/// How to run a study.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyOptions {
    /// Output directory; cases go to `out_dir/<case>/`.
    pub out_dir: PathBuf,
    /// Parallel cases (default: one per core).
    pub jobs: Option<usize>,
    /// Overrides applied to every case, before the case's own.
    pub set: Vec<String>,
    /// Run only this shard of the cases.
    pub shard: Option<Shard>,
    /// Re-run cases whose `done.json` says complete (otherwise they are skipped).
    pub force: bool,
    /// Print one line per case on stderr.
    pub verbose: bool,
}

/// What happened to one case in this invocation.
#[derive(Debug, Clone, PartialEq)]
pub enum CaseStatus {
    /// Ran to the end.
    Complete,
    /// Stopped early (the message says why); outputs may be partial.
    Incomplete(String),
    /// The runner returned an error.
    Failed(String),
    /// Already complete from an earlier invocation.
    Skipped,
}

/// The result of [`run_study_with`].
#[derive(Debug, Clone, PartialEq)]
pub struct StudyReport {
    /// Each selected case and what happened to it.
    pub cases: Vec<(String, CaseStatus)>,
    /// The collected table (all finished cases found in the output directory).
    pub table: Table,
}

impl StudyReport {
    /// Cases of this invocation that failed or stopped early.
    pub fn failures(&self) -> usize {
        self.cases
            .iter()
            .filter(|(_, s)| matches!(s, CaseStatus::Failed(_) | CaseStatus::Incomplete(_)))
            .count()
    }
}

/// The signature of a case runner ([`app::run`] in production, a fake in tests).
pub type Runner<'a> = dyn Fn(&Scenario, &RunOptions) -> Result<RunOutcome, AppError> + Sync + 'a;

/// Run a study with the real simulation.
pub fn run_study(study: &Study, opts: &StudyOptions) -> Result<StudyReport, AppError> {
    run_study_with(study, opts, &app::run)
}

/// Run a study with the given case runner: validate every selected case's scenario first
/// (so an input error stops the study before anything runs), run them in parallel, then
/// write `study.csv` and `study.md` from every finished case in the output directory.
pub fn run_study_with(
    study: &Study,
    opts: &StudyOptions,
    runner: &Runner,
) -> Result<StudyReport, AppError> {
    let selected: Vec<&Case> = study
        .cases
        .iter()
        .filter(|c| opts.shard.is_none_or(|s| s.contains(c.index)))
        .collect();
    let scenarios = selected
        .iter()
        .map(|c| {
            let s = study.scenario(c, &opts.set)?;
            let digest = inputs::digest(&s)
                .map_err(|e| input(format!("study `{}`, case `{}`: {e}", study.name, c.name)))?;
            Ok((s, digest))
        })
        .collect::<Result<Vec<_>, AppError>>()?;
    table::refuse_run_dir_out(&opts.out_dir)?;
    owner::refuse_other_studys_out(&opts.out_dir, study)?;
    app::ensure_dir(&opts.out_dir)?;
    let held = owner::hold_out(&opts.out_dir, "nothing was run")?;
    table::refuse_run_dir_out(&opts.out_dir)?;
    owner::refuse_users_tables(&opts.out_dir, study.file.is_none())?;
    let study = &Study {
        content_digest: owner::content_digest(study, &opts.set),
        ..study.clone()
    };
    owner::claim(&opts.out_dir, study)?;
    // The table is written again when the cases have run. Until then an earlier one would
    // call complete a case whose directory this run may be replacing; a study killed
    // meanwhile leaves none, and `chute collect` tells the cases' state.
    // A ladder's reports likewise (`chute converge` runs its levels as a study made in code).
    let reports: &[&str] = match study.file {
        None => &crate::converge::REPORT_FILES,
        Some(_) => &[],
    };
    for f in table::TABLE_FILES.iter().chain(reports) {
        let p = opts.out_dir.join(f);
        if std::fs::symlink_metadata(&p).is_ok_and(|m| m.is_file()) {
            let _ = std::fs::remove_file(p);
        }
    }
    drop(held);
    let jobs = opts
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        // More workers than cases would only be threads with nothing to do.
        .min(selected.len())
        .max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| AppError::RunFailed(format!("cannot start {jobs} worker threads: {e}")))?;
    let statuses: Vec<Result<CaseStatus, AppError>> = pool.install(|| {
        selected
            .par_iter()
            .zip(scenarios.par_iter())
            .map(|(case, (scenario, digest))| {
                case_run::run_case(study, case, scenario, digest, opts, runner)
            })
            .collect()
    });
    let mut cases = Vec::new();
    for (case, status) in selected.iter().zip(statuses) {
        cases.push((case.name.clone(), status?));
    }
    let held = owner::hold_out(
        &opts.out_dir,
        "its cases ran, but its table was not written: run it again (without --force its finished cases are skipped)",
    )?;
    let mut table = table::gather(
        std::slice::from_ref(&opts.out_dir),
        Some((study, opts.set.as_slice())),
    )?;
    if study.dispersion.is_some() {
        let missing = dispersion_out::write(study, &opts.out_dir)?;
        if !missing.is_empty() {
            table.notes.push(format!(
                "{} not written: {} of {} samples have not landed ({})",
                dispersion_out::FOOTPRINT_JSON,
                missing.len(),
                study.cases.len(),
                missing
                    .iter()
                    .take(10)
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
    }
    table::write_table(&table, &opts.out_dir)?;
    drop(held);
    Ok(StudyReport { cases, table })
}

/// Whether `chute study` would skip `case` of `study` under the study-wide `set` in
/// `out_dir`: its `done.json` says complete for exactly the inputs it would run now (for a
/// progress total; a case whose scenario cannot be built counts as to be run).
pub fn case_is_current(study: &Study, case: &Case, set: &[String], out_dir: &Path) -> bool {
    let Ok(s) = study.scenario(case, set) else {
        return false;
    };
    let Ok(digest) = inputs::digest(&s) else {
        return false;
    };
    let done = out_dir.join(&case.name).join(DONE_FILE);
    skip::recorded_run(&done, &digest, &s.input_files()).0
}

/// The digest of the `summary.json` a case's run wrote, so that one replaced later (another
/// case's copied in) is not read as this case's; null when there is none.
pub(crate) fn summary_digest(case_dir: &Path) -> Option<String> {
    let bytes =
        crate::output::atomic::read_own(&case_dir.join(crate::output::run_files::SUMMARY)).ok()?;
    Some(inputs::bytes_digest(&bytes))
}

pub(crate) fn split_override(s: &str) -> Option<[String; 2]> {
    let (k, v) = s.split_once('=')?;
    let v = v.trim();
    // Show strings unquoted in the table.
    let v = v
        .strip_prefix('"')
        .and_then(|x| x.strip_suffix('"'))
        .unwrap_or(v);
    Some([k.trim().to_string(), v.to_string()])
}
