//! `convergence.png`: one panel per varied key (row) and quantity (column): the values
//! against h (filled: used in the fit; hollow: left out), the Richardson extrapolation at
//! h = 0 (dashed line and cross) and the fine-level GCI band φ₁ ± GCI |φ₁| (shaded).

use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::analyse::{QuantityReport, StudyReport};
use super::plan::Axis;
use crate::output::plots::{render_atomic, PlotError};

const PANEL: (u32, u32) = (430, 330);

fn de(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw(e.to_string())
}

/// Draw `path` (PNG) for the studies.
pub fn convergence_plot(path: &Path, studies: &[StudyReport]) -> Result<(), PlotError> {
    if studies.is_empty() {
        return Err(PlotError::NoData("no convergence studies"));
    }
    // One column per quantity any study reports (the drop quantities only with a ground).
    let cols = studies
        .iter()
        .map(|st| st.reported().count())
        .max()
        .unwrap_or(0);
    let size = (
        PANEL.0 * cols as u32,
        PANEL.1 * studies.len() as u32 + LEGEND_HEIGHT,
    );
    render_atomic(path, size, |root| {
        let (root, strip) = root.split_vertically(size.1 - LEGEND_HEIGHT);
        draw_legend(&strip)?;
        let panels = root.split_evenly((studies.len(), cols));
        for (r, st) in studies.iter().enumerate() {
            for (c, q) in st.reported().enumerate() {
                if let Some(rep) = st.quantities.get(q.name) {
                    panel(&panels[r * cols + c], st, rep, q.label)?;
                }
            }
        }
        Ok(())
    })
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Height of the legend strip under the panels (px).
const LEGEND_HEIGHT: u32 = 28;

/// What the marks of every panel mean, once, in a strip under them.
fn draw_legend(strip: &Area<'_>) -> Result<(), PlotError> {
    let font = ("sans-serif", 14).into_font().color(&BLACK);
    let y = LEGEND_HEIGHT as i32 / 2;
    let mut x = 20;
    let text = |x: &mut i32, t: &str| -> Result<(), PlotError> {
        strip
            .draw(&Text::new(t.to_string(), (*x + 16, y - 7), font.clone()))
            .map_err(de)?;
        *x += 16 + 8 * t.chars().count() as i32 + 30;
        Ok(())
    };
    strip
        .draw(&Circle::new((x + 5, y), 5, BLUE.filled()))
        .map_err(de)?;
    text(&mut x, "a level in the fit")?;
    strip
        .draw(&Circle::new((x + 5, y), 5, BLUE.stroke_width(2)))
        .map_err(de)?;
    text(&mut x, "a level left out of the fit")?;
    strip
        .draw(&Cross::new((x + 5, y), 6, RED.stroke_width(2)))
        .map_err(de)?;
    text(&mut x, "Richardson extrapolation to h → 0 (dashed)")?;
    strip
        .draw(&Rectangle::new(
            [(x, y - 6), (x + 12, y + 6)],
            RED.mix(0.15).filled(),
        ))
        .map_err(de)?;
    text(&mut x, "GCI band of the finest level in the fit")?;
    Ok(())
}

fn panel(
    area: &Area<'_>,
    st: &StudyReport,
    q: &QuantityReport,
    label: &str,
) -> Result<(), PlotError> {
    let pts: Vec<(f64, f64, bool)> = q
        .results
        .iter()
        .zip(&q.h)
        .enumerate()
        .filter_map(|(i, (v, &h))| v.map(|v| (h, v, q.levels_used.contains(&i))))
        .collect();
    if pts.is_empty() {
        return Ok(());
    }
    let band = match (q.levels_used.first().and_then(|&i| q.results[i]), q.gci) {
        (Some(f), Some(g)) => Some((f - g * f.abs(), f + g * f.abs())),
        _ => None,
    };
    let (lo, hi) = y_range(&pts, q.extrapolated, band);
    let h_max = pts.iter().map(|p| p.0).fold(0.0, f64::max) * 1.1;
    let unit = match st.axis {
        Axis::Time => "dt (s)",
        Axis::Tolerance => "√tol (m^½)",
        Axis::Space => "h (m)",
    };
    // Enough decimals that neighbouring tick labels differ, however tight the range.
    let decimals = ((-(hi - lo).log10()).ceil() + 2.0).clamp(0.0, 15.0) as usize;
    let y_fmt = move |y: &f64| format!("{y:.decimals$}");
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{label}: {}", q.verdict.unwrap_or("—")),
            ("sans-serif", 17),
        )
        .margin(10)
        .x_label_area_size(38)
        .y_label_area_size(90)
        .build_cartesian_2d(0.0..h_max, lo..hi)
        .map_err(de)?;
    chart
        .configure_mesh()
        .x_desc(format!("{} {unit}", st.key))
        .label_style(("sans-serif", 13))
        .x_labels(5)
        .y_labels(10)
        .y_label_formatter(&y_fmt)
        .draw()
        .map_err(de)?;
    if let Some(b) = band {
        draw_band(&mut chart, b, h_max)?;
    }
    if let Some(x) = q.extrapolated {
        draw_extrapolation(&mut chart, x, h_max)?;
    }
    let mut line: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.1)).collect();
    line.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(line, BLUE.mix(0.5)))
        .map_err(de)?;
    chart
        .draw_series(pts.iter().map(|&(h, v, used)| {
            let style = if used {
                BLUE.filled()
            } else {
                BLUE.stroke_width(2)
            };
            Circle::new((h, v), 5, style)
        }))
        .map_err(de)?;
    Ok(())
}

type Chart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// The y range of the panel: values, extrapolation and band, padded by 8 % (5 % of the
/// value, or 1e-6, when flat).
fn y_range(pts: &[(f64, f64, bool)], ext: Option<f64>, band: Option<(f64, f64)>) -> (f64, f64) {
    let ys = pts
        .iter()
        .map(|p| p.1)
        .chain(ext)
        .chain(band.into_iter().flat_map(|b| [b.0, b.1]));
    let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |a, y| {
        (a.0.min(y), a.1.max(y))
    });
    let pad = if hi > lo {
        0.08 * (hi - lo)
    } else {
        0.05 * hi.abs().max(1e-6)
    };
    (lo - pad, hi + pad)
}

fn draw_band(chart: &mut Chart<'_, '_>, (b0, b1): (f64, f64), h_max: f64) -> Result<(), PlotError> {
    chart
        .draw_series([Rectangle::new(
            [(0.0, b0), (h_max, b1)],
            RED.mix(0.15).filled(),
        )])
        .map_err(de)?;
    Ok(())
}

fn draw_extrapolation(chart: &mut Chart<'_, '_>, x: f64, h_max: f64) -> Result<(), PlotError> {
    chart
        .draw_series(DashedLineSeries::new(
            [(0.0, x), (h_max, x)],
            6,
            4,
            RED.stroke_width(1),
        ))
        .map_err(de)?;
    chart
        .draw_series([Cross::new((0.0, x), 7, RED.stroke_width(2))])
        .map_err(de)?;
    Ok(())
}
