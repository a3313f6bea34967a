//! The case directories `collect` and a study's table gather: one row per case name, and
//! what the table must say about the rest (a case found in several places, cases of other
//! studies or study-wide overrides).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::inputs::InputsState;
use super::table::Row;
use crate::app::AppError;

/// The case directories found so far: the row of each case name (its last complete
/// occurrence, or its last one), its recipe, and every place it was found.
#[derive(Default)]
pub(super) struct Gathered {
    pub by_name: BTreeMap<String, Row>,
    pub recipes: BTreeMap<String, serde_json::Value>,
    pub found: BTreeMap<String, Found>,
    /// Directories left out of the table, and why (a copy of a case under another name).
    pub left_out: Vec<String>,
    /// The first case recorded with a recipe: where, and the study it names (kept by
    /// `collect`, which refuses cases of another study; a study's own table keeps its cases).
    pub first: Option<Option<(PathBuf, StudyOf)>>,
}

/// The study a recipe names: its study file (a ladder's base) and its case names. Shards of
/// one study may run from copies in other places (same names) and a study edited in place
/// keeps its file; a study whose file and case names both differ is another one.
#[derive(PartialEq)]
pub(super) struct StudyOf {
    file: Option<String>,
    names: Option<Vec<serde_json::Value>>,
    digest: Option<String>,
}

impl StudyOf {
    fn of(recipe: &serde_json::Value) -> StudyOf {
        let file = recipe["study_file"].as_str().or(recipe["base"].as_str());
        StudyOf {
            file: file.map(str::to_string),
            names: recipe["case_names"].as_array().cloned(),
            digest: recipe["content"].as_str().map(str::to_string),
        }
    }

    /// Another study: from another file running other inputs (a copy running the same
    /// inputs is the same study, the same file edited in place too), or, for records
    /// without the content digest (an older chute), from another file with other case names.
    fn another(&self, other: &StudyOf) -> bool {
        if let (Some(a), Some(b)) = (&self.digest, &other.digest) {
            return a != b && self.file != other.file;
        }
        let known = |a: &StudyOf| a.file.is_some() && a.names.is_some();
        known(self) && known(other) && self.file != other.file && self.names != other.names
    }
}

/// Where one case name was found: each directory with its study, state and study-wide
/// overrides, and the one the table shows.
#[derive(Default)]
pub(super) struct Found {
    places: Vec<(PathBuf, Option<String>, [&'static str; 2], String)>,
    shown: usize,
}

impl Found {
    /// A note when the places disagree (other states, inputs or overrides): which one the table
    /// shows, so that a newer attempt is never dropped without a word.
    pub fn note(&self) -> Option<String> {
        let first = self.places.first()?;
        let differ = self
            .places
            .iter()
            .any(|(_, _, word, set)| (*word, set) != (first.2, &first.3));
        differ.then(|| {
            let all: Vec<String> = self
                .places
                .iter()
                .map(|(p, _, [state, inputs], set)| {
                    format!("`{}` ({state}, inputs {inputs}, --set {set})", p.display())
                })
                .collect();
            format!(
                "case found in {}: the table shows `{}`",
                all.join(" and "),
                self.places[self.shown].0.display()
            )
        })
    }
}

impl Gathered {
    /// Take the case in `p`: refused when its name is already a case of another study.
    pub fn add(
        &mut self,
        p: PathBuf,
        row: Row,
        recipe: Option<serde_json::Value>,
    ) -> Result<(), AppError> {
        // A case's directory is named after it: a record of case `a` in `a.old` is a copy
        // (a backup), which must not stand for the case.
        let named = p.file_name().map(|n| n.to_string_lossy().into_owned());
        if recipe.is_some() && named.as_deref() != Some(row.case.as_str()) {
            self.left_out.push(format!(
                "`{}` holds a record of case `{}` but is not named after it (a copy?): left out of the table",
                p.display(),
                row.case
            ));
            return Ok(());
        }
        let study = recipe.as_ref().and_then(study_of);
        let found = self.found.entry(row.case.clone()).or_default();
        if let (Some(now), Some((other, Some(was), ..))) = (&study, found.places.first()) {
            if was != now {
                return Err(AppError::Input(format!(
                    "case `{}` is in `{}` as a case of {was} and in `{}` as a case of {now}: one table holds one study's cases; collect the two studies separately",
                    row.case,
                    other.display(),
                    p.display()
                )));
            }
        }
        refuse_another_study(&mut self.first, &p, recipe.as_ref())?;
        let set = recipe
            .as_ref()
            .map_or("(unrecorded)".to_string(), |r| r["set"].to_string());
        found
            .places
            .push((p, study, [row.state.word(), row.inputs.word()], set));
        // The table shows the last complete and current occurrence, else the last complete.
        let rank = |r: &Row| (r.complete, r.inputs == InputsState::Current);
        if self
            .by_name
            .get(&row.case)
            .is_some_and(|r| rank(r) > rank(&row))
        {
            return Ok(());
        }
        found.shown = found.places.len() - 1;
        // A directory without a readable `done.json` (missing, running, unreadable)
        // records no recipe but says nothing about the study's case list either.
        if let Some(recipe) = recipe {
            self.recipes.insert(row.case.clone(), recipe);
        }
        self.by_name.insert(row.case.clone(), row);
        Ok(())
    }
}

/// For `collect` (`first` is `Some`): refuse the case in `p` when its recipe names another
/// study than the first case's ([`StudyOf::another`]).
fn refuse_another_study(
    first: &mut Option<Option<(PathBuf, StudyOf)>>,
    p: &Path,
    recipe: Option<&serde_json::Value>,
) -> Result<(), AppError> {
    let (Some(recipe), Some(first)) = (recipe, first) else {
        return Ok(());
    };
    let now = StudyOf::of(recipe);
    match first {
            Some((dir, was)) if was.another(&now) => Err(AppError::Input(format!(
                "`{}` is a case of the study of `{}` and `{}` one of the study of `{}`: one table holds one study's cases; collect the two studies separately",
                dir.display(),
                was.file.as_deref().unwrap_or_default(),
                p.display(),
                now.file.as_deref().unwrap_or_default(),
            ))),
            Some(_) => Ok(()),
            None => {
                *first = Some((p.to_path_buf(), now));
                Ok(())
            }
        }
}

/// The study a case's recipe names, by its file's name and its case names (not the file's
/// full path: shards of one study may run from copies of it in different places); `None`
/// for a recipe that names neither (an older chute's).
fn study_of(recipe: &serde_json::Value) -> Option<String> {
    let file = recipe["study_file"].as_str().map(|f| {
        let name = Path::new(f)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned());
        name.unwrap_or_else(|| f.to_string())
    });
    let names = recipe["case_names"].as_array().map(|names| {
        let names: Vec<&str> = names.iter().filter_map(|n| n.as_str()).collect();
        names.join(", ")
    });
    match (file, names) {
        (Some(f), Some(n)) => Some(format!("study `{f}` (cases {n})")),
        (Some(f), None) => Some(format!("study `{f}`")),
        (None, Some(n)) => Some(format!("the study of cases {n}")),
        (None, None) => None,
    }
}

/// A note when the cases were recorded under different studies or study-wide overrides
/// (cases named in the order of `rows`).
pub(super) fn mixed_recipes(
    rows: &[Row],
    recipes: &BTreeMap<String, serde_json::Value>,
) -> Option<String> {
    let mut groups: BTreeMap<String, Vec<&str>> = BTreeMap::new();
    for r in rows {
        let (case, Some(recipe)) = (&r.case, recipes.get(&r.case).filter(|r| !r.is_null())) else {
            continue;
        };
        let text = format!(
            "{}, --set {}",
            study_of(recipe).unwrap_or_else(|| "no recorded study".into()),
            recipe["set"]
        );
        groups.entry(text).or_default().push(case);
    }
    (groups.len() > 1).then(|| {
        let parts: Vec<String> = groups
            .iter()
            .map(|(recipe, cases)| format!("{} with {recipe}", cases.join(", ")))
            .collect();
        format!(
            "the table mixes cases run under different studies or study-wide --set overrides: {}",
            parts.join("; ")
        )
    })
}
