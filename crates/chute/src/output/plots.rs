//! PNG plots of a run (plotters, bitmap backend, embedded DejaVu Sans font).
//!
//! All functions take plain slices. Each PNG is rendered into a hidden temporary file in the
//! target directory and renamed into place, so a plot is either absent, the old one, or
//! complete.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use super::scene3d;
pub use super::scene3d::{ColourBy, ShapeScene, View};

/// Size of the time-series plots (pixels).
pub const PLOT_SIZE: (u32, u32) = (1024, 640);
/// Size of the shape pictures `shape.png` and `snapshot_*.png` (pixels).
pub const SHAPE_SIZE: (u32, u32) = (1400, 1300);
/// Name of the velocity plot in the output directory.
pub const VELOCITY_PNG: &str = "velocity.png";
/// Name of the extended-height plot.
pub const HEIGHT_PNG: &str = "height.png";
/// Name of the final-shape plot.
pub const SHAPE_PNG: &str = "shape.png";
/// Name of the final membrane-state picture of a no-compression fabric.
pub const WRINKLES_PNG: &str = "wrinkles.png";

pub(crate) const FONT: &str = "sans-serif";
/// Label areas and margin (pixels); also used to estimate the plotting area for equal aspect.
pub(crate) const X_LABEL_AREA: u32 = 55;
pub(crate) const Y_LABEL_AREA: u32 = 80;
pub(crate) const MARGIN: u32 = 20;
pub(crate) const CAPTION_PX: u32 = 26;

/// Failure to produce a plot.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// File system error (creating/renaming the PNG).
    #[error("plot I/O: {0}")]
    Io(#[from] std::io::Error),
    /// plotters failed to draw or encode.
    #[error("plot drawing: {0}")]
    Draw(String),
    /// The embedded font could not be registered.
    #[error("embedded font could not be registered")]
    Font,
    /// Nothing to plot.
    #[error("no data to plot: {0}")]
    NoData(&'static str),
}

pub(crate) fn de<E: std::fmt::Display>(e: E) -> PlotError {
    let text = e.to_string();
    // plotters wraps the encoder's I/O error in several layers of Debug text
    // (`ImageError(IoError(Custom { …, error: "No space left on device (os error 28)" }))`):
    // the I/O error's own sentence is what a user needs.
    let sentence = text
        .split_once("error: \"")
        .and_then(|(_, rest)| rest.split_once('"'))
        .map(|(io, _)| io.to_string());
    match sentence {
        Some(io) if text.contains("IoError") => PlotError::Io(std::io::Error::other(io)),
        _ => PlotError::Draw(text),
    }
}

/// Register the embedded DejaVu Sans as the `sans-serif` family, once per process; without it
/// the ab_glyph backend has no font and text rendering fails on machines without fonts.
fn ensure_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/DejaVuSans.ttf");
        plotters::style::register_font(FONT, FontStyle::Normal, bytes).is_ok()
    });
    ok.then_some(()).ok_or(PlotError::Font)
}

/// The PNG text keywords of chute's pictures: `Software` is `chute`, `Title` the file name
/// it was written as.
const SOFTWARE: &str = "Software";
const TITLE: &str = "Title";

/// Whether `bytes` are a picture chute wrote as a file named `name` (its text chunks, which
/// precede the image data).
pub(crate) fn written_by_chute(bytes: &[u8], name: &str) -> bool {
    let chunk = |key: &str, text: &str| {
        let mut c = b"tEXt".to_vec();
        c.extend_from_slice(key.as_bytes());
        c.push(0);
        c.extend_from_slice(text.as_bytes());
        c
    };
    let has = |c: Vec<u8>| bytes.windows(c.len()).any(|w| w == c.as_slice());
    bytes.starts_with(b"\x89PNG\r\n\x1a\n")
        && has(chunk(SOFTWARE, "chute"))
        && has(chunk(TITLE, name))
}

/// Render with `draw` into memory and write the PNG to `path` atomically (a random
/// temporary created exclusively beside it, fsynced and renamed: `write_atomic`).
pub(crate) fn render_atomic(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>) -> Result<(), PlotError>,
) -> Result<(), PlotError> {
    ensure_font()?;
    let (w, h) = size;
    let mut rgb = vec![0u8; 3 * w as usize * h as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        root.fill(&WHITE).map_err(de)?;
        draw(&root)?;
        root.present().map_err(de)?;
    }
    let mut png_bytes = Vec::new();
    let mut enc = png::Encoder::new(&mut png_bytes, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    // Which chute picture this is, for `written_by_chute`.
    let title = path.file_name().map(|n| n.to_string_lossy().into_owned());
    enc.add_text_chunk(SOFTWARE.into(), "chute".into())
        .and_then(|()| enc.add_text_chunk(TITLE.into(), title.unwrap_or_default()))
        .map_err(de)?;
    enc.write_header()
        .and_then(|mut wr| wr.write_image_data(&rgb))
        .map_err(de)?;
    Ok(super::atomic::write_atomic(path, &png_bytes)?)
}

/// (min, max) of the finite values, padded by 5 % (or a small absolute pad when flat).
fn padded_range(vals: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = vals
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return None;
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        (0.05 * hi.abs()).max(1e-3)
    };
    Some((lo - pad, hi + pad))
}

fn finite_points<'a>(t: &'a [f64], y: &'a [f64]) -> impl Iterator<Item = (f64, f64)> + 'a {
    t.iter()
        .zip(y)
        .map(|(&a, &b)| (a, b))
        .filter(|(a, b)| a.is_finite() && b.is_finite())
}

/// What `velocity.png` says about terminal velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TerminalMark<'a> {
    /// Reached: draw v_t (m/s), its ±2 % band and the time to terminal (s) when known.
    Reached {
        /// Terminal velocity v_t (m/s, signed).
        v_mps: f64,
        /// Time to terminal (s).
        time_to_terminal_s: Option<f64>,
    },
    /// Not reached (or not judged): no line or band, the reason is written on the plot.
    NotReached {
        /// Why, in a few words (e.g. "run too short to judge").
        reason: &'a str,
    },
}

/// `velocity.png`: vz(t); with [`TerminalMark::Reached`] the terminal velocity v_t, its ±2 %
/// band and the time to terminal, otherwise a note saying it was not reached and why.
/// Units: s, m/s.
pub fn velocity_plot(
    path: &Path,
    t: &[f64],
    vz: &[f64],
    mark: &TerminalMark<'_>,
) -> Result<(), PlotError> {
    let (band, time_to_terminal) = match *mark {
        TerminalMark::Reached {
            v_mps,
            time_to_terminal_s,
        } => (
            Some((v_mps, crate::metrics::TERMINAL_BAND * v_mps.abs())),
            time_to_terminal_s,
        ),
        TerminalMark::NotReached { .. } => (None, None),
    };
    let (t0, t1) = padded_range(t.iter().copied()).ok_or(PlotError::NoData("empty time"))?;
    let extra = band.into_iter().flat_map(|(v, b)| [v - b, v + b]);
    let (y0, y1) = padded_range(vz.iter().copied().chain(extra)).ok_or(PlotError::NoData("vz"))?;
    render_atomic(path, PLOT_SIZE, |root| {
        let mut chart = line_chart(
            root,
            "Canopy vertical velocity",
            ("time t (s)", "vertical velocity vz (m/s)"),
            t0..t1,
            y0..y1,
        )?;
        if let Some((v, b)) = band {
            let fill = GREEN.mix(0.2).filled();
            chart
                .draw_series([Rectangle::new([(t0, v - b), (t1, v + b)], fill)])
                .map_err(de)?
                .label("±2 % band")
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], fill));
            let style = RED.stroke_width(2);
            chart
                .draw_series(DashedLineSeries::new([(t0, v), (t1, v)], 10, 6, style))
                .map_err(de)?
                .label(format!("terminal velocity v_t = {v:.4} m/s"))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], style));
        }
        if let TerminalMark::NotReached { reason } = mark {
            draw_not_reached(root, reason)?;
        }
        if let Some(tt) = time_to_terminal {
            let style = BLACK.stroke_width(2);
            chart
                .draw_series(DashedLineSeries::new([(tt, y0), (tt, y1)], 8, 6, style))
                .map_err(de)?
                .label(format!("time to terminal = {tt:.3} s"))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], style));
        }
        let line = BLUE.stroke_width(2);
        chart
            .draw_series(LineSeries::new(finite_points(t, vz), line))
            .map_err(de)?
            .label("vz (canopy, mass-weighted)")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], line));
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    })
}

/// A linear x–y chart in the house style of every line plot: caption, label areas, mesh and
/// the axis descriptions `desc` = (x, y).
pub(super) fn line_chart<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    caption: &str,
    desc: (&str, &str),
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>, PlotError> {
    let mut chart = ChartBuilder::on(root)
        .caption(caption, (FONT, CAPTION_PX))
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x, y)
        .map_err(de)?;
    chart
        .configure_mesh()
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 18))
        .x_desc(desc.0)
        .y_desc(desc.1)
        .draw()
        .map_err(de)?;
    Ok(chart)
}

/// The "terminal velocity not reached" note, lower left on a white box: a falling vz(t)
/// leaves that corner empty. Dark orange, not the red of the v_t line, so it cannot pass for
/// one.
fn draw_not_reached<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    reason: &str,
) -> Result<(), PlotError> {
    let font = (FONT, 18).into_font().color(&RGBColor(150, 40, 0));
    let x = (Y_LABEL_AREA + MARGIN + 16) as i32;
    let y = (PLOT_SIZE.1 - X_LABEL_AREA - MARGIN - 64) as i32;
    let width = 18 * reason.chars().count().max(30) as i32 / 2 + 16;
    let background = WHITE.mix(0.9).filled();
    root.draw(&Rectangle::new(
        [(x - 8, y - 8), (x + width, y + 48)],
        background,
    ))
    .map_err(de)?;
    root.draw(&Text::new(
        "terminal velocity not reached:",
        (x, y),
        font.clone(),
    ))
    .map_err(de)?;
    root.draw(&Text::new(reason.to_string(), (x, y + 24), font))
        .map_err(de)
}

/// The series' legend in the chart's corner `at`.
fn draw_legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    at: SeriesLabelPosition,
) -> Result<(), PlotError> {
    chart
        .configure_series_labels()
        .position(at)
        .label_font((FONT, 18))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(de)
}

/// `height.png`: extended height (max z − min z over canopy nodes) against time. Units: s, m.
pub fn height_plot(path: &Path, t: &[f64], height: &[f64]) -> Result<(), PlotError> {
    let (t0, t1) = padded_range(t.iter().copied()).ok_or(PlotError::NoData("empty time"))?;
    let (y0, y1) = padded_range(height.iter().copied()).ok_or(PlotError::NoData("height"))?;
    render_atomic(path, PLOT_SIZE, |root| {
        let mut chart = line_chart(
            root,
            "Canopy extended height",
            ("time t (s)", "extended height, max z − min z (m)"),
            t0..t1,
            y0.min(0.0)..y1,
        )?;
        chart
            .draw_series(LineSeries::new(
                finite_points(t, height),
                BLUE.stroke_width(2),
            ))
            .map_err(de)?;
        Ok(())
    })
}

/// The shape of a state: an oblique shaded 3-D view (with a colour bar and axis triad) and,
/// for shells, a top view on the upper row; the side views x–z and y–z, shaded too, with
/// axes in metres on the lower row. Load sites and the payload are marked when the scene has
/// roles. Every panel has an equal aspect ratio. Units: m.
pub fn shape_plot(path: &Path, title: &str, scene: &ShapeScene<'_>) -> Result<(), PlotError> {
    scene.check().map_err(PlotError::NoData)?;
    render_atomic(path, SHAPE_SIZE, |root| {
        let root = root.titled(title, (FONT, CAPTION_PX + 4)).map_err(de)?;
        let (w, h) = root.dim_in_pixel();
        let (upper, lower) = root.split_vertically(h * 11 / 20);
        let shell = !scene.triangles.is_empty();
        let (oblique, top) = if shell {
            let (a, b) = upper.split_horizontally(w * 11 / 20);
            (a, Some(b))
        } else {
            (upper, None)
        };
        let what = match scene.colour_by {
            ColourBy::Height => "height",
            ColourBy::Speed => "speed",
            ColourBy::MembraneState => "membrane state",
        };
        let panel = caption(&oblique, &format!("3-D view (coloured by {what})"))?;
        scene3d::draw_view(&panel, scene, &View::oblique(), None).map_err(PlotError::Draw)?;
        let (pw, ph) = panel.dim_in_pixel();
        let bar_h = (ph as i32 / 3).max(40);
        scene3d::draw_colour_bar(&panel, scene, (pw as i32 - 180, 40, bar_h))
            .map_err(PlotError::Draw)?;
        scene3d::draw_triad(&panel, &View::oblique(), (50, ph as i32 - 50))
            .map_err(PlotError::Draw)?;
        if let Some(top) = top {
            let panel = caption(&top, "top view (looking down)")?;
            scene3d::draw_view(&panel, scene, &View::top(), Some(("x (m)", "y (m)")))
                .map_err(PlotError::Draw)?;
        }
        let sides = lower.split_evenly((1, 2));
        let views = [
            (View::side_xz(), "side view x–z", "x (m)"),
            (View::side_yz(), "side view y–z", "y (m)"),
        ];
        for (area, (view, name, x_desc)) in sides.iter().zip(views) {
            let panel = caption(area, name)?;
            scene3d::draw_view(&panel, scene, &view, Some((x_desc, "z (m)")))
                .map_err(PlotError::Draw)?;
        }
        Ok(())
    })
}

/// `area` with a panel caption `t` above it.
fn caption<DB: DrawingBackend>(
    a: &DrawingArea<DB, plotters::coord::Shift>,
    t: &str,
) -> Result<DrawingArea<DB, plotters::coord::Shift>, PlotError> {
    a.titled(t, (FONT, CAPTION_PX - 4)).map_err(de)
}

/// `shape.png` in `out_dir`: the final shape at time `t_s`.
pub fn final_shape_plot(
    out_dir: &Path,
    t_s: f64,
    scene: &ShapeScene<'_>,
) -> Result<PathBuf, PlotError> {
    let title = format!("Final canopy shape (t = {t_s:.3} s)");
    shape_file(out_dir.join(SHAPE_PNG), &title, scene)
}

/// [`shape_plot`] into `path`, which is returned.
fn shape_file(path: PathBuf, title: &str, scene: &ShapeScene<'_>) -> Result<PathBuf, PlotError> {
    shape_plot(&path, title, scene)?;
    Ok(path)
}

/// `wrinkles.png` in `out_dir`: the state at time `t_s` coloured by each triangle's membrane
/// state (taut, wrinkled, slack; `scene.cell_state`), for a membrane that cannot carry
/// compression.
pub fn wrinkle_plot(
    out_dir: &Path,
    t_s: f64,
    scene: &ShapeScene<'_>,
) -> Result<PathBuf, PlotError> {
    let title = format!("Where the fabric wrinkles (t = {t_s:.3} s)");
    let by_state = ShapeScene {
        colour_by: ColourBy::MembraneState,
        ..*scene
    };
    shape_file(out_dir.join(WRINKLES_PNG), &title, &by_state)
}

/// File name of a snapshot: `snapshot_<t>s.png`, t rounded to the millisecond with trailing
/// zeros removed (`snapshot_2.5s.png`, `snapshot_10s.png`).
pub fn snapshot_file_name(t_s: f64) -> String {
    let s = format!("{t_s:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    format!("snapshot_{s}s.png")
}

/// `snapshot_<t>s.png` in `out_dir`: the shape at time `t_s` (the caller passes the state at
/// that time).
pub fn snapshot_plot(
    out_dir: &Path,
    t_s: f64,
    scene: &ShapeScene<'_>,
) -> Result<PathBuf, PlotError> {
    let title = format!("Canopy shape at t = {t_s:.3} s");
    shape_file(out_dir.join(snapshot_file_name(t_s)), &title, scene)
}

/// One curve of a [`loglog_plot`]: legend label and `(x, y)` points (positive values).
pub struct LogLogSeries<'a> {
    /// Legend label.
    pub label: String,
    /// Points `(x, y)`; non-positive or non-finite points are skipped.
    pub points: &'a [(f64, f64)],
    /// Draw dashed (e.g. a reference slope) instead of solid with markers.
    pub dashed: bool,
}

/// A log–log plot (e.g. error against step size for a convergence study). Units are those
/// of the caller's axis descriptions.
pub fn loglog_plot(
    path: &Path,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[LogLogSeries<'_>],
) -> Result<(), PlotError> {
    let ok = |&(x, y): &(f64, f64)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite();
    let all: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(ok)
        .collect();
    let range = |f: fn(&(f64, f64)) -> f64| {
        let (lo, hi) = all
            .iter()
            .map(f)
            .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
        (lo / 1.5, hi * 1.5)
    };
    if all.is_empty() {
        return Err(PlotError::NoData("no positive points"));
    }
    let ((x0, x1), (y0, y1)) = (range(|p| p.0), range(|p| p.1));
    render_atomic(path, PLOT_SIZE, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(title, (FONT, CAPTION_PX))
            .margin(MARGIN)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(de)?;
        chart
            .configure_mesh()
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 18))
            .x_desc(x_desc)
            .y_desc(y_desc)
            // Few labels: log axes otherwise label every minor tick and the labels overlap.
            .x_labels(6)
            .y_labels(6)
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(de)?;
        let colours = [BLUE, RED, GREEN, MAGENTA, BLACK];
        for (i, s) in series.iter().enumerate() {
            let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(ok).collect();
            let style = colours[i % colours.len()].stroke_width(2);
            if s.dashed {
                chart
                    .draw_series(DashedLineSeries::new(pts, 10, 6, style))
                    .map_err(de)?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], style));
            } else {
                chart
                    .draw_series(LineSeries::new(pts.iter().copied(), style))
                    .map_err(de)?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], style));
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 4, style.filled())))
                    .map_err(de)?;
            }
        }
        draw_legend(&mut chart, SeriesLabelPosition::LowerRight)
    })
}
