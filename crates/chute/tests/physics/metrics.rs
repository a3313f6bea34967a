//! Metrics against analytic velocity histories.

use crate::common::find_containing;
use chute::metrics::{self, compute, Metrics, MetricsError, Params, Series};

const G: f64 = 9.81;

/// Columns built from closures of t; drag_z = W·(vz/v_t)² as for quadratic drag.
struct Cols {
    t: Vec<f64>,
    vz: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
    h: Vec<f64>,
    drag: Vec<f64>,
}

impl Cols {
    fn new(t_end: f64, dt: f64, vz: impl Fn(f64) -> f64, drag: impl Fn(f64) -> f64) -> Self {
        let n = (t_end / dt).round() as usize;
        let t: Vec<f64> = (0..=n).map(|i| i as f64 * dt).collect();
        Self {
            vz: t.iter().map(|&t| vz(t)).collect(),
            vx: t.iter().map(|_| 0.3).collect(),
            vy: t.iter().map(|_| -0.1).collect(),
            h: t.iter().map(|&t| 2.0 + (t * 3.0).sin()).collect(),
            drag: t.iter().map(|&t| drag(t)).collect(),
            t,
        }
    }

    fn series(&self) -> Series<'_> {
        Series {
            t_s: &self.t,
            vz_mps: &self.vz,
            vx_mps: &self.vx,
            vy_mps: &self.vy,
            extended_height_m: &self.h,
            drag_z_n: &self.drag,
            exact_max_extended_height_m: None,
        }
    }
}

fn params(w: f64) -> Params {
    Params {
        total_weight_n: w,
        air_density_kg_m3: 1.225,
        air_viscosity_pa_s: 1.81e-5,
        reference_length_m: 2.0,
        quadratic_drag: true,
        wind_mps: [0.0; 3],
    }
}

fn run(c: &Cols, w: f64) -> Metrics {
    compute(&c.series(), &params(w)).expect("valid input")
}

/// v(t) = −v_t tanh(g t / v_t): the exact free fall with quadratic drag from rest. The time to
/// enter the ±2 % band is (v_t/g)·atanh(0.98).
/// One of `m`'s warnings contains `what`.
fn assert_warned(m: &Metrics, what: &str) {
    assert!(
        m.warnings.iter().any(|s| s.contains(what)),
        "no {what:?} in {:?}",
        m.warnings
    );
}

#[test]
fn tanh_transient_matches_closed_form() {
    let (v_t, w) = (5.0, 80.0);
    let tau = v_t / G;
    let c = Cols::new(
        10.0 * tau,
        1e-3,
        |t| -v_t * (t / tau).tanh(),
        |t| w * (t / tau).tanh().powi(2),
    );
    let m = run(&c, w);
    // Over the final window (t/τ ∈ [8, 10]) 1 − tanh ≤ 2e^{-16} ≈ 2.3e-7, and the trapezoid
    // rule on this nearly flat curve adds far less, so v_t is exact to < 1e-6 relative.
    assert!((m.terminal_velocity_mps + v_t).abs() / v_t < 1e-6, "{m:?}");
    assert!(m.terminal_velocity_std_mps < 1e-6 * v_t);
    assert!(m.reached_terminal, "{:?}", m.warnings);
    // The crossing is found by linear interpolation between samples 1 ms apart; the error is
    // ≤ dt²·|v''|/(8|v'|) ≈ (1e-3)²·(2g/v_t)/8 ≈ 5e-7 s, and the 1e-7 relative error of v_t
    // shifts the band edge by < 1e-7·v_t/|v'| ≈ 1e-7 s: 1e-5 s is a safe, still sharp bound
    // (one sample spacing would be 1e-3 s).
    let expected = tau * 0.98_f64.atanh();
    let got = m.time_to_terminal_s.expect("reached");
    eprintln!(
        "tanh: v_t rel err {:.2e}, time-to-terminal err {:.2e} s, force balance {:.2e}",
        (m.terminal_velocity_mps + v_t).abs() / v_t,
        (got - expected).abs(),
        m.force_balance_error
    );
    assert!(
        (got - expected).abs() < 1e-5,
        "got {got}, expected {expected}"
    );
    // drag = W tanh² → mean over the window = W to < 1e-6: the force balance is exact.
    assert!(m.force_balance_error < 1e-6, "{}", m.force_balance_error);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
}

/// The same fall sampled as an adaptive run steps it (`time.adaptive`): the step follows the
/// error controller's `h = 0.9 √(2 tol/|a|)` (tol = 1e-5 m, `a = g sech²(t/τ)`), capped at
/// 0.05 s, from 0.9 √(2 tol/g) = 1.3 ms at the start to 50 ms near terminal velocity. The
/// time-weighted window statistics and the interpolated band crossing need no uniform spacing.
#[test]
fn tanh_transient_with_adaptive_steps() {
    let (v_t, w) = (5.0, 80.0);
    let tau = v_t / G;
    let (tol, h_max) = (1e-5, 0.05);
    let mut t = vec![0.0];
    while *t.last().unwrap() < 10.0 * tau {
        let now = *t.last().unwrap();
        let a = G / (now / tau).cosh().powi(2);
        let h = (0.9 * (2.0 * tol / a).sqrt()).min(h_max);
        t.push((now + h).min(10.0 * tau));
    }
    let c = Cols {
        vz: t.iter().map(|&t| -v_t * (t / tau).tanh()).collect(),
        vx: t.iter().map(|_| 0.3).collect(),
        vy: t.iter().map(|_| -0.1).collect(),
        h: t.iter().map(|&t| 2.0 + (t * 3.0).sin()).collect(),
        drag: t.iter().map(|&t| w * (t / tau).tanh().powi(2)).collect(),
        t,
    };
    let dts: Vec<f64> = c.t.windows(2).map(|p| p[1] - p[0]).collect();
    let (lo, hi) = dts
        .iter()
        .fold((1.0f64, 0.0f64), |(a, b), &d| (a.min(d), b.max(d)));
    assert!(lo < 1.3e-3 && hi > 0.0499, "{lo} … {hi}");
    let m = run(&c, w);
    // The window [8τ, 10τ] (≈ 1 s) holds ~20 steps of 50 ms on a curve flat to 2.3e-7:
    // the trapezoid mean is exact to < 1e-6 relative, as with 1 ms samples.
    assert!(m.window_samples >= 10, "{}", m.window_samples);
    assert!((m.terminal_velocity_mps + v_t).abs() / v_t < 1e-6, "{m:?}");
    assert!(m.reached_terminal, "{:?}", m.warnings);
    assert!(m.force_balance_error < 1e-6, "{}", m.force_balance_error);
    // Band crossing at t* = τ atanh(0.98) = 1.17 s, where a = g (1 − 0.98²) = 0.388 m/s² and
    // the step is h = 0.9 √(2 tol/a) = 6.5 ms. Linear interpolation misplaces a crossing by at
    // most h² |v''| / (8 |v'|), with |v''|/|v'| = 2 tanh(t*/τ)/τ = 3.84 /s: ≤ 2.0e-5 s.
    let expected = tau * 0.98_f64.atanh();
    let got = m.time_to_terminal_s.expect("reached");
    assert!(
        (got - expected).abs() < 2.1e-5,
        "got {got}, expected {expected}"
    );
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
}

/// Constant descent: every metric has a closed form.
#[test]
fn constant_descent_exact_values() {
    let (v, w) = (-7.0, 100.0);
    let c = Cols::new(4.0, 0.01, |_| v, |_| 0.9 * w);
    let m = run(&c, w);
    let p = params(w);
    assert!((m.terminal_velocity_mps - v).abs() < 1e-12);
    assert!(m.terminal_velocity_std_mps < 1e-12);
    assert!(m.terminal_velocity_trend_mps.abs() < 1e-12);
    assert!(m.reached_terminal);
    assert_eq!(m.time_to_terminal_s, Some(0.0));
    assert!((m.force_balance_error - 0.1).abs() < 1e-12);
    let cda = 2.0 * w / (p.air_density_kg_m3 * v * v);
    assert!((m.drag_area_m2.unwrap() - cda).abs() < 1e-12 * cda);
    let re = p.air_density_kg_m3 * 7.0 * p.reference_length_m / p.air_viscosity_pa_s;
    assert!((m.reynolds_number - re).abs() < 1e-9 * re);
    assert!((m.horizontal_velocity_mps[0] - 0.3).abs() < 1e-12);
    assert!((m.horizontal_velocity_mps[1] + 0.1).abs() < 1e-12);
    assert!((m.window_start_s - 3.2).abs() < 1e-12 && (m.window_end_s - 4.0).abs() < 1e-12);
    // 10 % force imbalance in a steady descent is worth a warning.
    assert_warned(&m, "drag_z differs");
    // Extended height 2 + sin 3t on [0, 4]: max 3 at t = π/6 (a sample within 0.005 s).
    assert!((m.max_extended_height_m - 3.0).abs() < 1e-3);
    assert!((m.final_extended_height_m - (2.0 + 12.0_f64.sin())).abs() < 1e-12);
}

/// A 10 % oscillation that never decays is not terminal, whatever the mean.
#[test]
fn oscillation_is_not_terminal() {
    let c = Cols::new(
        20.0,
        0.005,
        |t| -5.0 * (1.0 + 0.1 * (2.0 * t).sin()),
        |_| 50.0,
    );
    let m = run(&c, 50.0);
    // Over the final 4 s (1.27 periods) the mean is within a few % of −5.
    assert!((m.terminal_velocity_mps + 5.0).abs() < 0.1);
    // std of 0.5 sin over ≈ a period ≈ 0.5/√2 ≈ 0.35 m/s ≫ 1 % of 5 m/s.
    assert!(m.terminal_velocity_std_mps > 0.2);
    assert!(!m.reached_terminal);
    assert_eq!(m.time_to_terminal_s, None);
    assert_warned(&m, "not reached");
}

/// A slow ramp with std below 1 % but a 2 % change across the window: the trend test alone
/// must reject it (std of a ramp = range/√12 ≈ 0.58 %; the ±2 % band holds).
#[test]
fn slow_drift_is_rejected_by_trend() {
    let (t_end, v0) = (10.0, -5.0);
    // 2 % of |v| over the 2 s window ⇒ slope 0.01·|v0| per second.
    let c = Cols::new(t_end, 0.01, |t| v0 * (1.0 + 0.01 * (t - 9.0)), |_| 50.0);
    let m = run(&c, 50.0);
    let v_t = m.terminal_velocity_mps.abs();
    assert!(m.terminal_velocity_std_mps < 0.01 * v_t);
    assert!((m.terminal_velocity_trend_mps.abs() / v_t - 0.02).abs() < 1e-3);
    assert!(!m.reached_terminal);
    assert_warned(&m, "not reached");
}

#[test]
fn too_short_and_low_reynolds_are_flagged() {
    let c = Cols::new(0.04, 0.01, |_| -1e-3, |_| 1.0);
    let m = run(&c, 1.0);
    assert!(m.window_samples < metrics::MIN_WINDOW_SAMPLES);
    assert!(!m.reached_terminal);
    assert_warned(&m, "too short");
    // Re = 1.225 · 1e-3 · 2 / 1.81e-5 ≈ 135 < 1000 with quadratic drag.
    assert_warned(&m, "Reynolds");
}

#[test]
fn ascending_is_not_terminal() {
    let c = Cols::new(2.0, 0.01, |_| 3.0, |_| -1.0);
    let m = run(&c, 1.0);
    assert!(!m.reached_terminal);
    assert_warned(&m, "not descending");
}

/// The window statistics are time-weighted: non-uniform sampling of the same signal (as after
/// step-size changes or decimation) gives the same mean. For vz linear in t the trapezoid mean
/// is exact: vz = −5 − 0.1 t has mean −5.9 over the window [8, 10].
#[test]
fn window_mean_is_time_weighted() {
    let f = |t: f64| -5.0 - 0.1 * t;
    let mut c = Cols::new(10.0, 0.5, f, |_| 1.0);
    // Cluster 99 samples in (9, 9.1): an unweighted mean would move by ≈ 5e-3 m/s.
    let pos = c.t.iter().position(|&t| t > 9.0).unwrap();
    for k in 0..99 {
        let t = 9.0 + (k + 1) as f64 * 1e-3;
        c.t.insert(pos + k, t);
        c.vz.insert(pos + k, f(t));
        for col in [&mut c.vx, &mut c.vy, &mut c.h, &mut c.drag] {
            col.insert(pos + k, col[pos - 1]);
        }
    }
    let m = run(&c, 1.0);
    assert!(
        (m.terminal_velocity_mps + 5.9).abs() < 1e-12,
        "{}",
        m.terminal_velocity_mps
    );
    // The trend of a linear signal is exact too: −0.1 m/s² over 2 s.
    assert!((m.terminal_velocity_trend_mps + 0.2).abs() < 1e-12);
}

#[test]
fn invalid_input_is_rejected() {
    let c = Cols::new(1.0, 0.1, |_| -1.0, |_| 1.0);
    let mut p = params(1.0);
    p.air_density_kg_m3 = 0.0;
    assert_eq!(
        compute(&c.series(), &p),
        Err(MetricsError::BadParameter("air_density_kg_m3"))
    );
    let mut s = c.series();
    s.vz_mps = &c.vz[1..];
    assert_eq!(compute(&s, &params(1.0)), Err(MetricsError::LengthMismatch));
    let nan = vec![f64::NAN; c.t.len()];
    let mut s = c.series();
    s.drag_z_n = &nan;
    assert_eq!(compute(&s, &params(1.0)), Err(MetricsError::NonFinite(0)));
    let empty: [f64; 0] = [];
    let s = Series {
        t_s: &empty,
        vz_mps: &empty,
        vx_mps: &empty,
        vy_mps: &empty,
        extended_height_m: &empty,
        drag_z_n: &empty,
        exact_max_extended_height_m: None,
    };
    assert_eq!(compute(&s, &params(1.0)), Err(MetricsError::Empty));
    // One sample (a run that stopped at its first step): nothing measured, so no v_t of 0
    // and no force balance of 1 pretending to be results.
    let one = [0.0];
    let s = Series {
        t_s: &one,
        vz_mps: &one,
        vx_mps: &one,
        vy_mps: &one,
        extended_height_m: &one,
        drag_z_n: &one,
        exact_max_extended_height_m: None,
    };
    assert_eq!(
        compute(&s, &params(1.0)),
        Err(MetricsError::NoTimeElapsed(0.0))
    );
}

#[test]
fn band_entry_interpolates_crossing() {
    // vz goes −4 → −5 linearly over [0, 1]; band around −5 is [−5.1, −4.9]; crossing at 0.9.
    let t = [0.0, 1.0, 2.0];
    let vz = [-4.0, -5.0, -5.0];
    let got = metrics::band_entry_time(&t, &vz, -5.0).unwrap();
    assert!((got - 0.9).abs() < 1e-12);
    assert_eq!(
        metrics::band_entry_time(&t, &[-5.0, -5.0, -4.0], -5.0),
        None
    );
}

/// Above Mach 0.3 (340.3 m/s sound speed) the incompressible drag law does not hold: a steady
/// fall at Mach 0.303 is warned about, one at Mach 0.297 is not, and so is a transient peak.
#[test]
fn mach_above_0_3_is_warned() {
    let mach = |m: &Metrics| m.warnings.iter().any(|w| w.contains("Mach"));
    let a = metrics::SPEED_OF_SOUND_MPS;
    let slow = run(&Cols::new(4.0, 0.01, |_| -0.297 * a, |_| 100.0), 100.0);
    assert!(!mach(&slow), "{:?}", slow.warnings);
    let fast = run(&Cols::new(4.0, 0.01, |_| -0.303 * a, |_| 100.0), 100.0);
    assert!(fast.reached_terminal && mach(&fast), "{:?}", fast.warnings);
    // Mach 0.5 at t = 0.5 s, settled to 30 m/s long before the final window.
    let peak = |t: f64| -30.0 - (0.5 * a - 30.0) * (-((t - 0.5) / 0.1).powi(2)).exp();
    let m = run(&Cols::new(10.0, 0.01, peak, |_| 100.0), 100.0);
    let w = find_containing(&m.warnings, "Mach");
    assert!(w.contains("Mach 0.50"), "{w}");
    assert_eq!(metrics::mach_warning(0.3 * a), None);
}

/// The drag laws see the velocity through the air, `v − U∞`: a canopy carried by a jet stream
/// at Mach 0.4 over the ground while falling at 30 m/s through the air is not warned about,
/// and the same ground velocity in still air (|(0.3, 136.1, −30)| = 139.4 m/s, Mach 0.41) is.
#[test]
fn mach_is_judged_through_the_air() {
    let a = metrics::SPEED_OF_SOUND_MPS;
    let mut c = Cols::new(4.0, 0.01, |_| -30.0, |_| 100.0);
    c.vy = vec![0.4 * a; c.t.len()];
    let wind = [0.3, 0.4 * a, 0.0];
    let with_wind = compute(
        &c.series(),
        &Params {
            wind_mps: wind,
            ..params(100.0)
        },
    )
    .unwrap();
    assert!(
        !with_wind.warnings.iter().any(|w| w.contains("Mach")),
        "{:?}",
        with_wind.warnings
    );
    let still = run(&c, 100.0);
    let w = find_containing(&still.warnings, "Mach");
    assert!(w.contains("Mach 0.41"), "{w}");
}

/// A canopy at rest in a 150 m/s wind is fastest through the air at the start (Mach 0.44),
/// which `chute check` warns about; while it is carried off with the wind the summary adds no
/// second warning. A gust that makes the airspeed peak later is warned about.
#[test]
fn a_start_at_rest_in_a_fast_wind_is_not_warned_twice() {
    let wind = [150.0, 0.0, 0.0];
    let mut c = Cols::new(4.0, 0.01, |_| -5.0, |_| 100.0);
    c.vx =
        c.t.iter()
            .map(|&t| 150.0 * (1.0 - (-t / 0.3).exp()))
            .collect();
    c.vy = vec![0.0; c.t.len()];
    let p = Params {
        wind_mps: wind,
        ..params(100.0)
    };
    let m = compute(&c.series(), &p).unwrap();
    assert!(
        !m.warnings.iter().any(|w| w.contains("Mach")),
        "{:?}",
        m.warnings
    );
    // The same start, and at t = 2 s the canopy is flung upwind at 20 m/s over the ground.
    c.vx[200] = -20.0;
    let m = compute(&c.series(), &p).unwrap();
    let w = find_containing(&m.warnings, "Mach");
    assert!(w.contains("170.1 m/s"), "{w}");
}
