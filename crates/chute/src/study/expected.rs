//! The full case list of a study, as its cases record it: so that a table gathered from
//! some of its directories (one shard's, a case deleted, a case whose directory was never
//! made) shows every case it lacks instead of silently leaving it out (docs/cli.md
//! §`chute collect`).
//!
//! Every `done.json` records its recipe: the study file, the base scenario, the study-wide
//! and the case's overrides, and the number and names of the cases of the study. The names
//! give the list when the study file cannot be read back (moved, deleted, a path that is not
//! UTF-8) or when there is none (`chute converge` makes its study in code).

use std::collections::BTreeMap;
use std::path::PathBuf;

use super::{Case, Study};

/// A recipe of `case` of `study` run under the study-wide `set`, for its `done.json`.
pub(super) fn recipe(study: &Study, set: &[String], case: &Case) -> serde_json::Value {
    // Paths as text (a path that is not UTF-8 is recorded lossily; the case names still
    // give the list).
    let text = |p: &std::path::Path| p.to_string_lossy().into_owned();
    let names: Vec<&str> = study.cases.iter().map(|c| c.name.as_str()).collect();
    serde_json::json!({
        "study_file": study.file.as_deref().map(text),
        "content": study.content_digest,
        "base": text(&study.base),
        "set": set,
        "case_set": case.set,
        "case_count": study.cases.len(),
        "case_names": names,
    })
}

/// The cases a table must have, as (index, name, the case's own overrides), and the studies
/// whose full list could not be known (so the table cannot be called complete).
#[derive(Debug, Default)]
pub(super) struct CaseList {
    pub cases: Vec<(usize, String, Vec<String>)>,
    pub unknown: Vec<String>,
}

/// Every case of `invocation`, or of the studies `recipes` (the cases' recorded recipes;
/// null for a case without one) name.
pub(super) fn cases<'a>(
    invocation: Option<&Study>,
    recipes: impl Iterator<Item = &'a serde_json::Value>,
) -> CaseList {
    let mut list = CaseList::default();
    if let Some(st) = invocation {
        list.cases = entries(st);
        return list;
    }
    // Per study file, the smallest and the largest case count its cases recorded, and every
    // case name any of them recorded (in the order first seen).
    let mut files: BTreeMap<PathBuf, (usize, usize, Vec<String>)> = BTreeMap::new();
    let mut named: BTreeMap<Vec<String>, ()> = BTreeMap::new();
    let mut without = 0;
    let mut any = false;
    for r in recipes {
        any = true;
        let count = r["case_count"].as_u64().map_or(0, |n| n as usize);
        let names = r["case_names"].as_array().map(|names| {
            names
                .iter()
                .filter_map(|n| Some(n.as_str()?.to_string()))
                .collect::<Vec<String>>()
        });
        match (r["study_file"].as_str(), names) {
            (Some(f), names) => {
                let n = files
                    .entry(PathBuf::from(f))
                    .or_insert((count, count, Vec::new()));
                (n.0, n.1) = (n.0.min(count), n.1.max(count));
                for name in names.into_iter().flatten() {
                    if !n.2.contains(&name) {
                        n.2.push(name);
                    }
                }
            }
            (None, Some(names)) => {
                if names.len() != count {
                    list.unknown.push(format!(
                        "a case records {} case name(s) but a case count of {count}: its `done.json` was edited, so the study's full case list is uncertain",
                        names.len()
                    ));
                }
                named.insert(names, ());
            }
            // Recorded before the case list was (or no recipe at all): nothing to compare
            // with, so the table cannot be called complete.
            (None, None) => without += 1,
        }
    }
    if !any {
        // Only directories without a readable record (killed, running): nothing says how
        // many cases their study has.
        list.unknown.push(
            "no case found records its study's case list (none has a readable done.json): the full list is unknown, and the table shows only the directories found".into(),
        );
    }
    if without > 0 {
        list.unknown.push(format!(
            "{without} case(s) record no recipe (a `done.json` of an older chute, or none readable): the full case list of their study is unknown, and the table shows only the cases found"
        ));
    }
    for (file, (least, count, names)) in files {
        match Study::load_recorded(&file) {
            Ok(st) => {
                if (least, count) != (st.cases.len(), st.cases.len()) {
                    let recorded = match least == count {
                        true => format!("{count}"),
                        false => format!("{least} to {count}"),
                    };
                    list.unknown.push(format!(
                        "study file `{}` has {} case(s) now, but its cases recorded {recorded}: the file changed since they ran (or a `done.json` was edited), so its full case list is uncertain",
                        file.display(),
                        st.cases.len()
                    ));
                }
                list.cases.extend(entries(&st));
            }
            // The study file is gone (or its recorded path is not the real one): the names
            // its cases recorded are the list, when they agree with the recorded count.
            Err(_) if least == count && names.len() == count => {
                named.insert(names, ());
            }
            // Cases of two versions of the file (its case list edited between shards): every
            // name any of them recorded has a row, and the list is uncertain.
            Err(e) if names.is_empty() => list.unknown.push(format!(
                "the full case list of study file `{}` is unknown ({e}): it has {count} case(s), and the table shows only those found",
                file.display()
            )),
            Err(e) => {
                list.unknown.push(format!(
                    "the full case list of study file `{}` is uncertain ({e}): its cases recorded {least} to {count} case(s) and {} name(s) in all, each of which the table lists",
                    file.display(),
                    names.len()
                ));
                named.insert(names, ());
            }
        }
    }
    for names in named.into_keys() {
        let cases = names
            .into_iter()
            .enumerate()
            .map(|(i, n)| (i, n, Vec::new()));
        list.cases.extend(cases);
    }
    list
}

fn entries(st: &Study) -> Vec<(usize, String, Vec<String>)> {
    st.cases
        .iter()
        .map(|c| (c.index, c.name.clone(), c.set.clone()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recipe_of(file: &str, names: &[&str]) -> serde_json::Value {
        serde_json::json!({
            "study_file": file,
            "case_count": names.len(),
            "case_names": names,
        })
    }

    /// Shards run under two versions of a study file that is gone now: every case name either
    /// version recorded gets a row (a case only the newer list has is not dropped), and the
    /// list is called uncertain.
    #[test]
    fn cases_of_two_versions_of_a_gone_study_file_are_all_listed() {
        let gone = "/nonexistent/chute-study-that-is-gone.toml";
        let recipes = [
            recipe_of(gone, &["20N", "200N", "2000N"]),
            recipe_of(gone, &["20N", "200N", "5N", "50N"]),
        ];
        let list = cases(None, recipes.iter());
        let names: Vec<&str> = list.cases.iter().map(|(_, n, _)| n.as_str()).collect();
        assert_eq!(names, ["20N", "200N", "2000N", "5N", "50N"]);
        assert_eq!(list.unknown.len(), 1, "{:?}", list.unknown);
        assert!(list.unknown[0].contains("uncertain"), "{:?}", list.unknown);
        // One version only: its names are the list, and it is certain.
        let one = [recipe_of(gone, &["a", "b"]), recipe_of(gone, &["a", "b"])];
        let list = cases(None, one.iter());
        assert_eq!(list.cases.len(), 2);
        assert!(list.unknown.is_empty(), "{:?}", list.unknown);
    }
}
