//! The identity of a case's inputs, recorded in its `done.json` so that a finished case is
//! reused only for exactly the inputs it ran (docs/cli.md §study, "Skipping finished cases").
//!
//! The digest is FNV-1a (64 bit) over a canonical byte stream: a version tag, then each
//! part as `tag NUL length(u64 little-endian) bytes`. The parts are the resolved scenario
//! text ([`Scenario::to_toml`]: every `--set`, grid value and default applied, keys in a
//! fixed order, numbers in Rust's shortest round-trip form) with the mesh path left out,
//! and, for an imported canopy, the mesh file's extension and its bytes. It is stable across
//! runs and machines because it depends on those bytes alone: no seeded hasher, no pointer
//! width, no file times, no absolute path (a study directory moved or mounted elsewhere
//! stays current; an edited mesh does not). FNV-1a guards against accidental change, which
//! is all a cache of one's own runs needs; it is not a defence against crafted collisions.

use std::collections::HashMap;
use std::path::PathBuf;

use super::{Case, Study};
use crate::app::AppError;
use crate::scenario::Scenario;

/// The name of the digest, written before it (`fnv1a64:0123456789abcdef`).
pub const ALGORITHM: &str = "fnv1a64";

/// Bumped when the canonical stream changes, so older records read as "changed".
const STREAM_VERSION: &[u8] = b"chute-case-inputs-1";

/// FNV-1a, 64 bit (Fowler, Noll, Vo): offset basis and prime of the published definition.
struct Fnv1a64(u64);

impl Fnv1a64 {
    fn new() -> Self {
        Fnv1a64(0xcbf2_9ce4_8422_2325)
    }

    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 = (self.0 ^ u64::from(x)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// One part of the canonical stream: its tag, a NUL, its length and its bytes.
    fn part(&mut self, tag: &str, b: &[u8]) {
        self.bytes(tag.as_bytes());
        self.bytes(&[0]);
        self.bytes(&(b.len() as u64).to_le_bytes());
        self.bytes(b);
    }
}

/// The digest of a validated scenario's inputs, as `fnv1a64:<16 hex digits>`. Reads its input
/// files (an imported mesh, a wind table); an unreadable one is an error naming it.
pub fn digest(s: &Scenario) -> Result<String, AppError> {
    let mut h = Fnv1a64::new();
    h.bytes(STREAM_VERSION);
    let mut text = s.clone();
    // Files are identified by their contents, not by where they are.
    text.canopy.mesh_file = None;
    if let Some(w) = text.wind.as_mut() {
        w.file = None;
    }
    h.part("scenario", text.to_toml().as_bytes());
    for (key, path) in s.input_files() {
        let bytes = std::fs::read(&path).map_err(|e| AppError::io(&path, e))?;
        let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        // The mesh's tags predate other input files; they keep old records current.
        let tag = match key {
            "canopy.mesh_file" => "mesh",
            other => other,
        };
        h.part(
            &format!("{tag}-extension"),
            ext.unwrap_or_default().as_bytes(),
        );
        h.part(tag, &bytes);
    }
    Ok(format!("{ALGORITHM}:{:016x}", h.0))
}

/// The digest of one file's bytes, as `fnv1a64:<16 hex digits>`.
pub fn file_digest(path: &std::path::Path) -> std::io::Result<String> {
    // Not read into memory past the largest input chute reads (a file replaced since).
    use crate::mesh::{read_capped, too_large, ReadCapped, MAX_MESH_BYTES};
    match read_capped(path, MAX_MESH_BYTES) {
        Ok(bytes) => Ok(bytes_digest(&bytes)),
        Err(ReadCapped::TooLong(len)) => Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            too_large(len).unwrap_or_default(),
        )),
        Err(ReadCapped::Io(e)) => Err(e),
    }
}

/// The digest of `bytes`, as `fnv1a64:<16 hex digits>`.
pub fn bytes_digest(bytes: &[u8]) -> String {
    let mut h = Fnv1a64::new();
    h.bytes(bytes);
    format!("{ALGORITHM}:{:016x}", h.0)
}

/// How a finished case's recorded inputs compare with what its study would run now.
#[derive(Debug, Clone, PartialEq)]
pub enum InputsState {
    /// The same inputs: the case is what the study would run.
    Current,
    /// Other inputs (the reason says what); running the study again re-runs the case.
    Changed(String),
    /// Cannot tell (the reason says why): no record, or the study cannot be read now.
    Unknown(String),
}

impl InputsState {
    /// The table cell: `current`, `changed` or `unknown`.
    pub fn word(&self) -> &'static str {
        match self {
            InputsState::Current => "current",
            InputsState::Changed(_) => "changed",
            InputsState::Unknown(_) => "unknown",
        }
    }
}

/// Re-derives the inputs a study would give a case now: from the recipe in its `done.json`
/// (study file, base scenario, study-wide and case overrides; study files are read once), or,
/// for `chute study` itself, from the study and overrides of this invocation.
#[derive(Default)]
pub struct Checker<'a> {
    studies: HashMap<PathBuf, Result<Study, String>>,
    invocation: Option<(&'a Study, &'a [String])>,
}

impl<'a> Checker<'a> {
    /// A checker that compares every case with what `study` under the study-wide `set` runs.
    pub fn for_invocation(study: &'a Study, set: &'a [String]) -> Self {
        Checker {
            studies: HashMap::new(),
            invocation: Some((study, set)),
        }
    }

    /// Compare a case's `done.json` (in its directory `dir`) with what its study would run
    /// now, and the files its run read with the files it would read now.
    pub fn state(&mut self, done: &serde_json::Value, dir: &std::path::Path) -> InputsState {
        let Some(recorded) = done["inputs"].as_str() else {
            return InputsState::Unknown("its done.json records no inputs (an older chute)".into());
        };
        match self.current(done) {
            Ok((now, files)) if now == recorded => super::skip::read_other_inputs(dir, &files)
                .map_or(InputsState::Current, InputsState::Changed),
            Ok(_) => InputsState::Changed(
                "its recorded inputs differ from what the study would run now".into(),
            ),
            Err(Stale::Changed(why)) => InputsState::Changed(why),
            Err(Stale::Unknown(why)) => InputsState::Unknown(why),
        }
    }

    /// The inputs digest of what the case's study would run now, and the files it reads.
    fn current(&mut self, done: &serde_json::Value) -> Result<(String, InputFiles), Stale> {
        let recipe = &done["recipe"];
        let strings = |v: &serde_json::Value| -> Vec<String> {
            let items = v.as_array().map(Vec::as_slice).unwrap_or_default();
            items
                .iter()
                .filter_map(|x| Some(x.as_str()?.to_string()))
                .collect()
        };
        let name = done["case"].as_str().unwrap_or_default();
        let set = strings(&recipe["set"]);
        let unknown = |why: String| Stale::Unknown(why);
        let scenario = match (self.invocation, recipe["study_file"].as_str()) {
            (Some((st, set)), _) => {
                let case = st.cases.iter().find(|c| c.name == name).ok_or_else(|| {
                    Stale::Changed(format!("study `{}` has no case `{name}`", st.name))
                })?;
                st.scenario(case, set)
            }
            (None, Some(file)) => {
                let st = self.studies.entry(PathBuf::from(file)).or_insert_with(|| {
                    Study::load_recorded(file.as_ref()).map_err(|e| e.to_string())
                });
                let st = st.as_ref().map_err(|e| unknown(e.clone()))?;
                let case = st.cases.iter().find(|c| c.name == name).ok_or_else(|| {
                    Stale::Changed(format!("study file `{file}` no longer has this case"))
                })?;
                st.scenario(case, &set)
            }
            (None, None) => {
                let base = recipe["base"]
                    .as_str()
                    .ok_or_else(|| unknown("its done.json records no base scenario".into()))?;
                // A FIFO put there since has no writer: named, not waited on.
                if let Some(why) = crate::output::atomic::not_plain(base.as_ref(), "base scenario")
                {
                    return Err(unknown(why));
                }
                let st = Study {
                    name: done["study"].as_str().unwrap_or_default().to_string(),
                    description: None,
                    file: None,
                    content_digest: None,
                    base: PathBuf::from(base),
                    cases: Vec::new(),
                    objective: None,
                    dispersion: None,
                };
                let case = Case {
                    index: 0,
                    name: name.to_string(),
                    set: strings(&recipe["case_set"]),
                };
                st.scenario(&case, &set)
            }
        };
        // A base scenario that no longer loads is other inputs than the ones recorded.
        let scenario = scenario.map_err(|e| Stale::Changed(e.to_string()))?;
        // An input file that cannot be read says nothing about whether it changed.
        let d = digest(&scenario).map_err(|e| Stale::Unknown(e.to_string()))?;
        Ok((d, scenario.input_files()))
    }
}

/// The input files (key, path) a scenario reads.
type InputFiles = Vec<(&'static str, PathBuf)>;

enum Stale {
    Changed(String),
    Unknown(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a64_matches_the_published_test_vectors() {
        // From the FNV reference test suite (Landon Curt Noll): "", "a", "foobar".
        for (input, want) in [
            ("", 0xcbf2_9ce4_8422_2325_u64),
            ("a", 0xaf63_dc4c_8601_ec8c),
            ("foobar", 0x8594_4171_f739_67e8),
        ] {
            let mut h = Fnv1a64::new();
            h.bytes(input.as_bytes());
            assert_eq!(h.0, want, "{input:?}");
        }
    }

    #[test]
    fn digest_follows_the_resolved_values_not_their_spelling() {
        let load = |text: &str, set: &[&str]| {
            let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
            Scenario::from_str_with_name(text, "s.toml", &set).unwrap()
        };
        let base = "[model]\nkind = \"rod\"\n[load]\nweight_n = 200\n";
        let a = digest(&load(base, &[])).unwrap();
        assert!(a.starts_with("fnv1a64:") && a.len() == 8 + 16, "{a}");
        let same = digest(&load(base, &["load.weight_n=200.0"])).unwrap();
        assert_eq!(a, same, "the same value written differently");
        let other = digest(&load(base, &["time.duration_s=0.4"])).unwrap();
        assert_ne!(a, other);
    }
}
