//! Convergence studies, written as CSV and log–log PNG plots, with the observed orders
//! returned as checks: the falling sheet's error against the time step (backward Euler:
//! first order), and the simply supported plate's and the elastica's error against the
//! mesh size.
use super::shell_cases::{ss_plate_deflection, ss_plate_load};
use super::Check;
use crate::output::atomic::write_atomic;
use crate::output::plots::{loglog_plot, LogLogSeries};
use engine::reference::cantilever::{elastica, elastica_exact};
use engine::reference::falling::{fall, Body};
use std::path::Path;

/// One study: `(x, error)` points, finest last.
struct Study {
    /// File stem of the CSV and PNG.
    stem: &'static str,
    title: &'static str,
    /// CSV header (`x,error` plus extra columns).
    header: &'static str,
    x_desc: &'static str,
    points: Vec<(f64, f64)>,
    /// Extra CSV columns per point (already formatted, comma-separated).
    extra: Vec<String>,
    /// Raw simulated values when the order is measured by self-convergence (successive
    /// differences), which cancels an error floor that does not depend on the mesh.
    values: Option<Vec<f64>>,
}

/// Observed order `log(e₁/e₂)/log(x₁/x₂)` between two points.
pub fn order(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.1 / b.1).ln() / (a.0 / b.0).ln()
}

fn falling_dt(quick: bool) -> Result<Study, String> {
    let dts: &[f64] = if quick {
        &[4e-3, 2e-3, 1e-3]
    } else {
        &[8e-3, 4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]
    };
    let mut points = Vec::new();
    for &dt in dts {
        let r = fall(Body::SheetTriangle, dt, 2.0).map_err(|e| e.to_string())?;
        points.push((dt, r.max_rel_error));
    }
    Ok(Study {
        stem: "convergence_falling_dt",
        title: "Falling sheet: max |v − v_t tanh(gt/v_t)| / v_t against dt",
        header: "dt_s,max_rel_error",
        x_desc: "time step dt (s)",
        extra: vec![String::new(); points.len()],
        points,
        values: None,
    })
}

fn plate_mesh(quick: bool) -> Result<Study, String> {
    let ns: &[usize] = if quick {
        &[10, 20, 40]
    } else {
        &[10, 20, 40, 80]
    };
    let a = 1.0;
    let (p, reference) = ss_plate_load(a);
    let mut points = Vec::new();
    let mut extra = Vec::new();
    for &n in ns {
        let w = ss_plate_deflection(a, n, p)?;
        points.push((a / n as f64, (w / reference - 1.0).abs()));
        extra.push(format!(",{n},{w:.9e},{reference:.9e}"));
    }
    Ok(Study {
        stem: "convergence_plate",
        title: "Simply supported plate: centre deflection error against cell size",
        header: "cell_m,rel_error,cells_per_side,w_center_m,w_navier_m",
        x_desc: "cell size a/n (m)",
        points,
        extra,
        values: None,
    })
}

fn elastica_mesh(quick: bool) -> Result<Study, String> {
    let ns: &[usize] = if quick {
        &[11, 21, 41]
    } else {
        &[11, 21, 41, 81, 161]
    };
    // The shooting solution (1e-10): the table's 5 digits would floor the error at 7e-6.
    let alpha = 5.0;
    let (w_ref, _) = elastica_exact(alpha);
    let mut points = Vec::new();
    let mut extra = Vec::new();
    let mut values = Vec::new();
    for &n in ns {
        let (w, _) = elastica(n, 1.0, 0.005, alpha).map_err(|e| e.to_string())?;
        values.push(w);
        let h = 1.0 / (n as f64 - 1.5);
        points.push((h, (w / w_ref - 1.0).abs()));
        extra.push(format!(",{n},{w:.9e},{w_ref:.9e}"));
    }
    Ok(Study {
        stem: "convergence_elastica",
        title: "Elastica α = 5: tip deflection error against edge length",
        header: "edge_m,rel_error,nodes,w_over_L,w_over_L_exact",
        x_desc: "edge length L/(n − 1.5) (m)",
        points,
        extra,
        values: Some(values),
    })
}

fn write(dir: &Path, s: &Study, slope: f64) -> Result<(), String> {
    let mut csv = format!("{}\n", s.header);
    for (p, e) in s.points.iter().zip(&s.extra) {
        csv += &format!("{:.6e},{:.6e}{e}\n", p.0, p.1);
    }
    let path = dir.join(format!("{}.csv", s.stem));
    write_atomic(&path, csv.as_bytes()).map_err(|e| format!("{}: {e}", path.display()))?;
    // A reference line of the expected slope through the finest point.
    let &(xf, ef) = s.points.last().ok_or("empty study")?;
    let guide: Vec<(f64, f64)> = s
        .points
        .iter()
        .map(|&(x, _)| (x, ef * (x / xf).powf(slope)))
        .collect();
    let png = dir.join(format!("{}.png", s.stem));
    loglog_plot(
        &png,
        s.title,
        s.x_desc,
        "relative error",
        &[
            LogLogSeries {
                label: "measured".into(),
                points: &s.points,
                dashed: false,
            },
            LogLogSeries {
                label: format!("slope {slope}"),
                points: &guide,
                dashed: true,
            },
        ],
    )
    .map_err(|e| format!("{}: {e}", png.display()))
}

/// The observed order of `s` and how it was measured: from the errors of the finest pair,
/// or, for self-convergence studies, from the successive differences of the three finest
/// values, `log(|u₁ − u₂| / |u₂ − u₃|) / log(h₂/h₃)`.
fn observed_order(s: &Study) -> Result<(f64, &'static str), String> {
    let k = s.points.len();
    if k < 3 {
        return Err(format!("{}: need 3 meshes", s.stem));
    }
    match &s.values {
        None => Ok((order(s.points[k - 2], s.points[k - 1]), "finest pair")),
        Some(u) => {
            let d1 = (u[k - 3] - u[k - 2]).abs();
            let d2 = (u[k - 2] - u[k - 1]).abs();
            let p = (d1 / d2).ln() / (s.points[k - 2].0 / s.points[k - 1].0).ln();
            Ok((p, "self-convergence, 3 finest"))
        }
    }
}

/// Run the studies, write `<stem>.csv` and `<stem>.png` into `dir`, and return the observed
/// orders (finest pair) as checks against the expected ones.
pub fn write_all(dir: &Path, quick: bool) -> Result<Vec<Check>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let tag = if quick { " (quick)" } else { "" };
    let mut checks = Vec::new();
    // Tolerances on the order: backward Euler's next term is O(g dt/v_t) relative to the
    // leading one (≤ 1.3 % at dt = 4 ms), which moves the order by about that: 0.05. The
    // mesh studies' finest pairs carry the next term O(h) relative plus solver round-off
    // (1e-9 of errors ~1e-4): 0.2 still separates second from first order.
    for (study, expected, tol, src) in [
        (
            falling_dt(quick)?,
            1.0,
            0.05,
            "backward Euler is first order",
        ),
        (
            plate_mesh(quick)?,
            2.0,
            0.2,
            "hinge bending: second order in ℓ",
        ),
        (
            elastica_mesh(quick)?,
            2.0,
            0.2,
            "DER: second order in edge length",
        ),
    ] {
        write(dir, &study, expected)?;
        let (observed, how) = observed_order(&study)?;
        checks.push(Check::new(
            &format!("order-{}", study.stem.trim_start_matches("convergence_")),
            &format!("observed order, {how}{tag}"),
            expected,
            src,
            observed,
            tol,
        ));
    }
    Ok(checks)
}
