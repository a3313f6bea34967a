//! The arithmetic of `chute converge` (Celik et al. 2008) and its verdicts on synthetic
//! sequences.

use chute::converge::gci::{apparent_order, estimate, three_levels, two_levels, Verdict};

/// Celik et al., J. Fluids Eng. 130 (2008) 078001, Table 1, first case: grids of 18,000,
/// 8,000 and 4,500 cells (2-D, h = (A/N)^½) with φ = 6.063, 5.972, 5.863. Published:
/// r₂₁ = 1.5, r₃₂ = 1.333, p = 1.53, φ_ext = 6.1685, e_a = 1.5 %, e_ext = 1.7 %,
/// GCI_fine = 2.2 %. The tolerances are half a unit of the published last digit.
#[test]
fn celik_worked_example() {
    let h: [f64; 3] = [18_000.0, 8_000.0, 4_500.0].map(|n: f64| (1.0 / n).sqrt());
    assert!((h[1] / h[0] - 1.5).abs() < 5e-4);
    assert!((h[2] / h[1] - 1.333).abs() < 5e-4);
    let e = three_levels(h, [6.063, 5.972, 5.863], 1e-9);
    assert_eq!(e.verdict, Verdict::Monotone);
    let p = e.observed_order.unwrap();
    assert!((p - 1.53).abs() < 5e-3, "p = {p}");
    let ext = e.extrapolated.unwrap();
    assert!((ext - 6.1685).abs() < 5e-5, "φ_ext = {ext}");
    assert!((100.0 * e.approximate_error - 1.5).abs() < 0.05);
    assert!((100.0 * e.extrapolated_error.unwrap() - 1.7).abs() < 0.05);
    assert!(
        (100.0 * e.gci.unwrap() - 2.2).abs() < 0.05,
        "GCI = {:?}",
        e.gci
    );
    assert_eq!(e.safety_factor, 1.25);
}

/// φ(h) = φ₀ + c h² on non-uniform levels: p = 2 and φ_ext = φ₀ to round-off, and the
/// GCI brackets the true error of the finest level.
#[test]
fn monotone_second_order_sequence() {
    let (phi0, c) = (-9.8, 0.6);
    let h = [0.1, 0.13, 0.2];
    let phi = h.map(|h| phi0 + c * h * h);
    let e = three_levels(h, phi, 1e-9);
    assert_eq!(e.verdict, Verdict::Monotone);
    assert!((e.observed_order.unwrap() - 2.0).abs() < 1e-9);
    assert!((e.extrapolated.unwrap() - phi0).abs() < 1e-12);
    let true_error = ((phi[0] - phi0) / phi[0]).abs();
    assert!(e.gci.unwrap() >= true_error);
}

/// Non-uniform refinement: with r₂₁ = 1.5 after r₃₂ = 1.333 a first-order (or slower)
/// sequence has |ε₂₁| ≥ |ε₃₂| and still converges; the order is recovered.
#[test]
fn larger_finer_difference_can_still_converge() {
    let h = [0.0625, 0.09375, 0.125];
    for p in [0.5, 1.0] {
        let phi = h.map(|h: f64| -9.9 + 2.0 * h.powf(p));
        assert!((phi[1] - phi[0]).abs() >= (phi[2] - phi[1]).abs() * 0.999);
        let e = three_levels(h, phi, 1e-9);
        assert_eq!(e.verdict, Verdict::Monotone, "p = {p}");
        assert!(
            (e.observed_order.unwrap() - p).abs() < 1e-8,
            "{:?}",
            e.observed_order
        );
        assert!((e.extrapolated.unwrap() + 9.9).abs() < 1e-10);
    }
}

/// |ε₂₁/ε₃₂| below R_max = ln r₂₁/ln r₃₂ (1 for uniform refinement) and negative:
/// oscillatory; at or above it: divergent (no order, a range band only).
#[test]
fn oscillatory_and_divergent_sequences() {
    let h = [0.125, 0.18, 0.25];
    let e = three_levels(h, [-9.60, -9.58, -9.64], 1e-9);
    assert_eq!(e.verdict, Verdict::Oscillatory);
    assert!(e.observed_order.is_some() && e.gci.is_some());
    // The report's 6-site numbers at 0.25 / 0.18 / 0.125 m: −9.591 / −9.625 / −9.583.
    let e = three_levels(h, [-9.583, -9.625, -9.591], 1e-9);
    assert_eq!(e.verdict, Verdict::Divergent);
    assert_eq!((e.observed_order, e.extrapolated), (None, None));
    // No GCI, only the range band: 3 × the largest spread from the finest value.
    let band = 3.0 * (0.042f64 / 9.583);
    assert!((e.gci.unwrap() - band).abs() < 1e-12, "{:?}", e.gci);
    let e = three_levels(h, [1.0, 1.2, 1.3], 1e-9);
    assert_eq!(e.verdict, Verdict::Divergent);
}

/// Differences below the resolution: round-off, no order, the finest value as the answer
/// and the resolution as its uncertainty.
#[test]
fn round_off_sequence() {
    let v = -6.0604;
    let e = three_levels(
        [0.05, 0.1, 0.2],
        [v, v * (1.0 + 3e-12), v * (1.0 - 2e-12)],
        1e-8,
    );
    assert_eq!(e.verdict, Verdict::RoundOff);
    assert_eq!(e.observed_order, None);
    assert_eq!(e.extrapolated, Some(v));
    assert_eq!(e.gci, Some(1e-8));
    // The same sequence at a tighter resolution is resolved (and here divergent: noise).
    let e = three_levels(
        [0.05, 0.1, 0.2],
        [v, v * (1.0 + 3e-12), v * (1.0 - 2e-12)],
        1e-13,
    );
    assert_ne!(e.verdict, Verdict::RoundOff);
}

/// Two levels: the formal order, safety factor 3.
#[test]
fn two_levels_assume_the_formal_order() {
    let e = two_levels([0.125, 0.18], [-9.802, -9.854], 1e-9, 2.0);
    assert_eq!(e.verdict, Verdict::Monotone);
    assert_eq!((e.observed_order, e.order_used), (None, Some(2.0)));
    assert_eq!(e.safety_factor, 3.0);
    let r: f64 = 0.18 / 0.125;
    let e_a = (0.052f64 / 9.802).abs();
    assert!((e.gci.unwrap() - 3.0 * e_a / (r * r - 1.0)).abs() < 1e-12);
    assert!(estimate(&[0.1], &[1.0], 1e-9, 2.0).is_none());
    assert!(apparent_order(1.0, 2.0, 0.1, 0.2).is_none());
}

mod levels {
    use chute::converge::analyse::{analyse, LevelResult, DT_NOTE};
    use chute::converge::plan::{Axis, Ladder, Level, Resolution};

    fn level(text: &str, h: f64) -> Level {
        Level {
            text: text.into(),
            value: text.parse().unwrap(),
            case: format!("edge_length_m-{text}"),
            h,
            nodes: 100,
            resolution: Resolution {
                force_tolerance_n: 5e-7,
                free_z_dofs: 1000,
                max_node_mass_kg: 0.05,
                weight_n: 708.6,
                dt_s: 1e-3,
                duration_s: 10.0,
                reference_length_m: 6.0,
            },
        }
    }

    fn done(vt: f64, height: f64) -> LevelResult {
        LevelResult {
            status: "complete".into(),
            message: None,
            values: vec![
                Some(vt),
                Some(1.5),
                Some(height),
                Some(2.0 * 708.6 / (1.225 * vt * vt)),
            ],
            wall_time_s: Some(1.0),
        }
    }

    /// A measured 4-site ladder: the 0.25 m level folds shallow (1.34 m against 2.37 m):
    /// a branch change, left out; the other two give a two-level estimate.
    #[test]
    fn a_branch_change_is_left_out_of_the_fit() {
        let ladder = Ladder {
            key: "canopy.edge_length_m".into(),
            axis: Axis::Space,
            levels: vec![
                level("0.25", 0.177),
                level("0.18", 0.127),
                level("0.125", 0.088),
            ],
        };
        let r = analyse(
            &ladder,
            &[done(-7.137, 1.34), done(-9.854, 2.39), done(-9.802, 2.37)],
        );
        assert!(!r.levels[0].used && r.levels[1].used && r.levels[2].used);
        assert!(r
            .notes
            .iter()
            .any(|n| n.contains("branch change") && n.contains("0.25")));
        let vt = &r.quantities["terminal_velocity_mps"];
        assert_eq!(vt.levels_used, vec![2, 1]);
        assert_eq!((vt.order_used, vt.safety_factor), (Some(2.0), Some(3.0)));
        assert_eq!(vt.results[0], Some(-7.137));
        // ε_F = N τ / W; the round-off floor 16 ε m |q|/dt² adds 2 %.
        assert!((r.relative_force_resolution / (1000.0 * 5e-7 / 708.6) - 1.0).abs() < 0.05);
    }

    /// Every level of the estimate but the coarsest gets its GCI from the next coarser one at
    /// the observed order: the medium level's is Fs e_a³² / (r₃₂^p − 1).
    #[test]
    fn medium_level_gets_its_own_gci() {
        let h = [0.2, 0.13, 0.1];
        let ladder = Ladder {
            key: "canopy.edge_length_m".into(),
            axis: Axis::Space,
            levels: h.iter().map(|&h| level(&h.to_string(), h)).collect(),
        };
        let vt = |h: f64| -9.8 + 0.6 * h * h;
        let r = analyse(&ladder, &h.map(|h| done(vt(h), 2.4)));
        let q = &r.quantities["terminal_velocity_mps"];
        assert_eq!(q.levels_used, vec![2, 1, 0]);
        assert_eq!(q.gci_by_level[2], q.gci);
        let p = q.observed_order.unwrap();
        assert!((p - 2.0).abs() < 1e-6, "p = {p}");
        let e32 = ((vt(0.13) - vt(0.2)) / vt(0.13)).abs();
        let want = 1.25 * e32 / ((0.2f64 / 0.13).powf(p) - 1.0);
        assert!((q.gci_by_level[1].unwrap() - want).abs() < 1e-12);
        assert_eq!(q.gci_by_level[0], None);
    }

    /// A failed level is reported and the others still estimated; a dt ladder carries its note.
    #[test]
    fn a_failed_level_is_reported_and_the_rest_estimated() {
        let ladder = Ladder {
            key: "time.dt_s".into(),
            axis: Axis::Time,
            levels: vec![
                level("0.004", 4e-3),
                level("0.002", 2e-3),
                level("0.001", 1e-3),
            ],
        };
        let failed = LevelResult {
            status: "failed".into(),
            message: Some("step failed at t = 0.1 s".into()),
            values: vec![None; 4],
            wall_time_s: None,
        };
        let r = analyse(&ladder, &[failed, done(-9.80, 2.37), done(-9.80, 2.37)]);
        assert_eq!(r.levels[0].status, "failed");
        assert!(r
            .notes
            .iter()
            .any(|n| n.contains("0.004") && n.contains("step failed")));
        assert!(r.notes.iter().any(|n| n == DT_NOTE));
        assert_eq!(
            r.quantities["terminal_velocity_mps"].verdict,
            Some("round-off")
        );
    }
}
