//! Adaptive steps on a shell canopy with the filtered, mass-RMS local error (the default):
//! a run stopped part-way and resumed from its checkpoint equals the uninterrupted run, bit
//! for bit (the filter uses the step's held factors, which a sync point drops in both runs).
use crate::common::*;

use chute::scenario::Scenario;

/// The report's 4-site shell (springs + hinges) on a 1 m mesh, adaptive, for `duration` s.
fn adaptive_shell(duration: f64) -> Scenario {
    let sets: Vec<String> = [
        "canopy.edge_length_m=1",
        "shell.membrane=springs",
        "shell.bending=hinge",
        "time.dt_s=0.001",
        "time.adaptive=true",
        "output.snapshots_s=[0.05]",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([format!("time.duration_s={duration}")])
    .collect();
    Scenario::load(&repo().join("scenarios/report-shell-4-sites.toml"), &sets).unwrap()
}

#[test]
fn adaptive_shell_resumed_after_stop_equals_uninterrupted() {
    // Sync points every 0.1 s (2 frames); stop at 0.23 s → checkpoint at 0.2 s.
    crate::resume::stop_and_resume(&adaptive_shell(0.3), 0.23, Some(0.1));
}
