//! File modes: every file chute writes (atomically or streamed) honours the umask, like any
//! other file the user creates — not tempfile's private 0600.
#![cfg(unix)]

use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::Command;

use crate::common::repo;

/// Every file under `dir` with its permission bits.
fn modes(dir: &Path) -> Vec<(String, u32)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(modes(&p));
        } else {
            let m = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
            out.push((p.display().to_string(), m));
        }
    }
    out
}

/// `chute ARGS` under `umask MASK`, in `cwd` (a shell sets the mask, so the test process's
/// own umask, shared by every test thread, is left alone).
fn chute_with_umask(cwd: &Path, mask: &str, args: &[&str]) {
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!("umask {mask} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_chute"))
        .args(args)
        .current_dir(cwd)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn written_files_honour_the_umask() {
    let rod = repo().join("scenarios/report-rod-200n.toml");
    let study = repo().join("studies/table1.toml");
    let short = [
        "--set",
        "canopy.nodes=11",
        "--set",
        "time.duration_s=0.15",
        "--set",
        "output.snapshots_s=[0.05]",
    ];
    // Two masks, so the modes follow the mask rather than being fixed at 0644.
    for (mask, want) in [("022", 0o644), ("027", 0o640)] {
        let tmp = tempfile::tempdir().unwrap();
        let mut run = vec![
            "run",
            rod.to_str().unwrap(),
            "-q",
            "--out",
            "r",
            "--checkpoint-every",
            "0.05",
        ];
        run.extend(short);
        chute_with_umask(tmp.path(), mask, &run);
        let mut st = vec!["study", study.to_str().unwrap(), "--out", "s", "-j", "1"];
        st.extend(short);
        chute_with_umask(tmp.path(), mask, &st);
        let all = modes(tmp.path());
        for name in [
            "summary.json",
            "canopy.pvd",
            "frame_000000.vtu",
            "scenario.resolved.toml",
            "checkpoint.bin",
            "timeseries.csv",
            "velocity.png",
            "viewer.html",
            "done.json",
            "study.csv",
            "study.md",
        ] {
            assert!(
                all.iter().any(|(p, _)| p.ends_with(name)),
                "no {name} written: {all:?}"
            );
        }
        for (path, mode) in &all {
            assert_eq!(*mode, want, "{path}: mode {mode:o} under umask {mask}");
        }
    }
}
