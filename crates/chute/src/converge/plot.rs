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
    let width = PANEL.0 * cols as u32;
    let legend = LEGEND_ROW * legend_rows(width);
    let size = (width, PANEL.1 * studies.len() as u32 + legend);
    render_atomic(path, size, |root| {
        let (root, strip) = root.split_vertically(size.1 - legend);
        draw_legend(&strip, width)?;
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

/// Height of one row of the legend strip under the panels (px).
const LEGEND_ROW: u32 = 28;

/// The legend's entries: the mark's kind and its text.
const LEGEND: [(Mark, &str); 4] = [
    (Mark::Used, "a level in the fit"),
    (Mark::Left, "a level left out of the fit"),
    (
        Mark::Extrapolated,
        "Richardson extrapolation to h → 0 (dashed)",
    ),
    (Mark::Band, "GCI band of the finest level in the fit"),
];

/// A mark of the legend.
#[derive(Clone, Copy)]
enum Mark {
    Used,
    Left,
    Extrapolated,
    Band,
}

/// Width of one legend entry (px): the mark, its text at about 8 px a character, a gap.
fn entry_width(text: &str) -> i32 {
    16 + 8 * text.chars().count() as i32 + 30
}

/// Where each legend entry goes in a strip `width` px wide: `(x, row)`, a new row where
/// the next entry would not fit (a figure with one or two quantity columns is narrower than
/// the four entries).
fn legend_layout(width: u32) -> [(i32, u32); 4] {
    let mut out = [(0, 0); 4];
    let (mut x, mut row) = (20, 0);
    for (slot, (_, text)) in out.iter_mut().zip(LEGEND) {
        if x > 20 && x + entry_width(text) > width as i32 {
            (x, row) = (20, row + 1);
        }
        *slot = (x, row);
        x += entry_width(text);
    }
    out
}

/// Rows the legend needs in a strip `width` px wide.
fn legend_rows(width: u32) -> u32 {
    legend_layout(width)
        .iter()
        .map(|&(_, r)| r)
        .max()
        .unwrap_or(0)
        + 1
}

/// What the marks of every panel mean, once, in a strip under them.
fn draw_legend(strip: &Area<'_>, width: u32) -> Result<(), PlotError> {
    let font = ("sans-serif", 14).into_font().color(&BLACK);
    for ((mark, text), (x, row)) in LEGEND.into_iter().zip(legend_layout(width)) {
        let y = (LEGEND_ROW * row + LEGEND_ROW / 2) as i32;
        let c = (x + 5, y);
        match mark {
            Mark::Used => strip.draw(&Circle::new(c, 5, BLUE.filled())),
            Mark::Left => strip.draw(&Circle::new(c, 5, BLUE.stroke_width(2))),
            Mark::Extrapolated => strip.draw(&Cross::new(c, 6, RED.stroke_width(2))),
            Mark::Band => strip.draw(&Rectangle::new(
                [(x, y - 6), (x + 12, y + 6)],
                RED.mix(0.15).filled(),
            )),
        }
        .map_err(de)?;
        strip
            .draw(&Text::new(text.to_string(), (x + 16, y - 7), font.clone()))
            .map_err(de)?;
    }
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

#[cfg(test)]
mod legend_tests {
    use super::*;

    /// Every entry ends inside the figure, on one row when there is room and on more when
    /// the figure has one quantity column.
    #[test]
    fn the_legend_fits_the_figure() {
        for cols in 1..=4 {
            let width = PANEL.0 * cols;
            for ((_, text), (x, _)) in LEGEND.into_iter().zip(legend_layout(width)) {
                assert!(
                    x + entry_width(text) <= width as i32 + 30,
                    "{cols} columns: {text}"
                );
            }
        }
        assert_eq!(legend_rows(PANEL.0 * 4), 1);
        assert!(legend_rows(PANEL.0) >= 3);
    }
}
