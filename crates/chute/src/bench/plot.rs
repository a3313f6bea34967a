//! The scaling plot of `chute bench`: wall time per Newton iteration against the number of
//! DOFs, log–log, with the least-squares exponent of the shell cases from 1k DOFs up.

use std::path::Path;

use plotters::prelude::*;

use crate::bench::CaseResult;
use crate::output::plots::{render_atomic, PlotError};

/// Refuse `--plot FILE` before the benchmark runs (status 2) when FILE cannot be written: its
/// directory missing or taking no files, a directory of its name, or a place inside a run
/// directory (the plot would replace a run's file without holding it).
pub fn refuse_path(path: &Path) -> Result<(), crate::app::AppError> {
    use crate::app::AppError;
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let bad = |why: String| AppError::Input(format!("--plot `{}`: {why}", path.display()));
    if path.is_dir() {
        return Err(bad("is a directory".into()));
    }
    if !parent.is_dir() {
        return Err(bad(format!("`{}` is not a directory", parent.display())));
    }
    crate::app::out_dir::refuse_inside_run(path)?;
    tempfile::Builder::new()
        .prefix(crate::output::run_files::PROBE_PREFIX)
        .tempfile_in(parent)
        .map(drop)
        .map_err(crate::output::atomic::without_temporary_name)
        .map_err(|e| bad(format!("its directory takes no files: {e}")))
}

/// Least-squares slope and intercept of `log10 y = p log10 x + c` over `(x, y)`.
pub fn fit_power(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|p| (p.0.log10(), p.1.log10())).unzip();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    (sxx > 0.0).then(|| (sxy / sxx, my - sxy / sxx * mx))
}

/// Points used for the fitted exponent: shell canopies (`shell-*`) with ≥ 1000 DOFs.
pub fn fit_points(results: &[CaseResult]) -> Vec<(f64, f64)> {
    results
        .iter()
        .filter(|r| r.name.starts_with("shell-") && r.dofs >= 1000)
        .map(|r| (r.dofs as f64, r.ms_per_newton))
        .collect()
}

/// Draw `path` (PNG).
pub fn scaling_plot(path: &Path, results: &[CaseResult]) -> Result<(), PlotError> {
    if results.is_empty() {
        return Err(PlotError::NoData("no bench results"));
    }
    let de = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
    let fit = fit_power(&fit_points(results));
    let xs = results.iter().map(|r| r.dofs as f64);
    let ys = results.iter().map(|r| r.ms_per_newton);
    let (x0, x1) = xs.fold((f64::MAX, 0.0f64), |a, x| (a.0.min(x), a.1.max(x)));
    let (y0, y1) = ys.fold((f64::MAX, 0.0f64), |a, y| (a.0.min(y), a.1.max(y)));
    render_atomic(path, (1024, 640), |root| {
        root.fill(&WHITE).map_err(|e| de(&e))?;
        let caption = match fit {
            Some((p, _)) => format!("cost per Newton iteration (shell fit: ∝ DOFs^{p:.2})"),
            None => "cost per Newton iteration".to_string(),
        };
        let mut chart = ChartBuilder::on(root)
            .caption(caption, ("sans-serif", 26))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(80)
            .build_cartesian_2d(
                (x0 / 1.5..x1 * 1.5).log_scale(),
                (y0 / 1.5..y1 * 1.5).log_scale(),
            )
            .map_err(|e| de(&e))?;
        chart
            .configure_mesh()
            .x_desc("DOFs")
            .y_desc("ms per Newton iteration")
            .label_style(("sans-serif", 18))
            .draw()
            .map_err(|e| de(&e))?;
        for (prefix, color) in [("rod-", BLUE), ("shell-", RED), ("dismech", GREEN)] {
            let pts: Vec<(f64, f64)> = results
                .iter()
                .filter(|r| r.name.starts_with(prefix))
                .map(|r| (r.dofs as f64, r.ms_per_newton))
                .collect();
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 6, color.filled())))
                .map_err(|e| de(&e))?
                .label(prefix.trim_end_matches('-'))
                .legend(move |(x, y)| Circle::new((x, y), 6, color.filled()));
        }
        if let Some((p, c)) = fit {
            let line = [x0, x1].map(|x| (x, 10f64.powf(c) * x.powf(p)));
            chart
                .draw_series(LineSeries::new(line, BLACK.stroke_width(2)))
                .map_err(|e| de(&e))?
                .label(format!("fit ∝ DOFs^{p:.2}"))
                .legend(|(x, y)| PathElement::new([(x - 10, y), (x + 10, y)], BLACK));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE)
            .border_style(BLACK)
            .label_font(("sans-serif", 18))
            .draw()
            .map_err(|e| de(&e))?;
        Ok(())
    })
}
