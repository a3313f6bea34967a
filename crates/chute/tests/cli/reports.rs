//! A ladder's reports (`convergence.json`, `.md`, `.png`) carry chute's mark, by which a
//! ladder tells them from a user's files of those names (docs/reliability.md §5): a user's
//! file is refused (status 2) and kept, chute's own are replaced by the next run.

use crate::common::*;
use crate::converge::short_ladder;

/// Each report name in turn holds a user's file that looks like chute's (a PNG chute drew
/// under another name, notes under the report's title, JSON with the report's keys).
#[test]
fn a_users_file_named_like_a_ladders_report_is_refused_and_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let o = short_ladder(tmp.path(), "11,21", &[]);
    assert_exit(&o, 0);
    // chute's own reports are its own: the ladder runs again into the same directory.
    let o = short_ladder(tmp.path(), "11,21", &["--force"]);
    assert_exit(&o, 0);
    // A picture chute drew, of another name (a level's velocity plot).
    let level_png = std::fs::read_dir(tmp.path().join("cv"))
        .unwrap()
        .filter_map(|e| std::fs::read(e.unwrap().path().join("velocity.png")).ok())
        .next()
        .expect("a level's velocity.png");
    let users: [(&str, Vec<u8>); 4] = [
        // chute writes whole files: an empty one is a user's.
        ("convergence.md", Vec::new()),
        ("convergence.png", level_png),
        (
            "convergence.md",
            b"# Convergence of `x`: my notes\n".to_vec(),
        ),
        (
            "convergence.json",
            br#"{"scenario": "mine", "set": [], "studies": []}"#.to_vec(),
        ),
    ];
    for (name, bytes) in users {
        let dir = tmp.path().join("u");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("cv")).unwrap();
        let file = dir.join("cv").join(name);
        std::fs::write(&file, &bytes).unwrap();
        let o = short_ladder(&dir, "11,21", &[]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.contains("is not a table or report chute wrote"),
            "{name}: {err}"
        );
        assert_eq!(std::fs::read(&file).unwrap(), bytes, "{name} changed");
    }
}

/// `validate --out` keeps a user's `validation_table.md` (refused, status 2) and never writes
/// its report into a run directory.
#[test]
fn validate_never_replaces_a_users_report_nor_writes_into_a_run() {
    let tmp = tempfile::tempdir().unwrap();
    let mine = tmp.path().join("v/validation_table.md");
    std::fs::create_dir(tmp.path().join("v")).unwrap();
    std::fs::write(&mine, "my notes\n").unwrap();
    let args = ["validate", "--quick", "--case", "elastica", "--out"];
    let o = crate::common::chute(tmp.path(), &[&args[..], &["v"]].concat());
    assert_exit(&o, 2);
    assert_eq!(std::fs::read_to_string(&mine).unwrap(), "my notes\n");
    std::fs::create_dir(tmp.path().join("r")).unwrap();
    let record = r#"{"status": "complete", "reason": null, "inputs": [], "viewer": true}"#;
    std::fs::write(tmp.path().join("r/run.json"), record).unwrap();
    let o = crate::common::chute(tmp.path(), &[&args[..], &["r"]].concat());
    assert_exit(&o, 2);
    assert!(!tmp.path().join("r/validation_table.md").exists());
}
