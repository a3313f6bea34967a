//! The registry of run files (`chute::output::run_files::RUN_FILES`) and the table of
//! docs/outputs.md §Output directory name the same files: the one list used for writing,
//! clearing and documenting.

use std::collections::BTreeSet;

use chute::output::run_files::RUN_FILES;

use crate::common::repo;

/// The first cell of every row of the table under `## Output directory`.
fn documented() -> BTreeSet<String> {
    let text = std::fs::read_to_string(repo().join("docs/outputs.md")).unwrap();
    let section = text
        .split("\n## ")
        .find(|s| s.starts_with("Output directory"))
        .expect("docs/outputs.md has an Output directory section");
    section
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .map(str::to_string)
        .collect()
}

#[test]
fn the_registry_is_the_documented_table() {
    let registry: BTreeSet<String> = RUN_FILES.iter().map(|f| f.shown.to_string()).collect();
    let docs = documented();
    assert!(docs.len() > 15, "{docs:?}");
    assert_eq!(
        registry.difference(&docs).collect::<Vec<_>>(),
        Vec::<&String>::new(),
        "registered but not in docs/outputs.md"
    );
    assert_eq!(
        docs.difference(&registry).collect::<Vec<_>>(),
        Vec::<&String>::new(),
        "in docs/outputs.md but not registered"
    );
}

#[test]
fn a_partial_last_row_is_not_read_as_data() {
    // What a reader sees while the writer is between two writes, or after it was killed.
    let dir = tempfile::tempdir().unwrap();
    let header = chute::output::timeseries::HEADER;
    let row = "0.5,1,2,3,4,5,6,7,8,9,10,11,0.001,0,0,0,3\n";
    let text = format!("{header}\n{row}{row}0.502,1,2,3,");
    std::fs::write(dir.path().join("timeseries.csv"), text).unwrap();
    let s = chute::output::run_dir::read_series(dir.path(), 100)
        .unwrap()
        .unwrap();
    assert_eq!(s.rows, 2);
}
