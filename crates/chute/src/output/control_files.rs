//! The outputs of a run with line pulls or guidance (docs/outputs.md): `lines.csv` (every
//! line's rest length, length and tension), `track.csv` (the payload's position) at every
//! frame time, and `track.png` (the top view of the track with target and landing point).
//!
//! Both files are streamed in whole rows and flushed at each frame; resuming cuts them back
//! to the rows at or before the checkpoint's time, so a resumed run's files equal the
//! uninterrupted run's.
use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};

use plotters::prelude::*;

use super::plots::{line_chart, render_atomic, PlotError, PLOT_SIZE};

/// `lines.csv`.
pub const LINES_CSV: &str = "lines.csv";
/// `track.csv`.
pub const TRACK_CSV: &str = "track.csv";
/// `track.png`.
pub const TRACK_PNG: &str = "track.png";
const LINES_HEADER: &str = "t_s,line,rest_length_m,length_m,tension_n";
const TRACK_HEADER: &str = "t_s,x_m,y_m,z_m";

/// One streamed CSV file of rows stamped with their time.
struct Rows {
    path: PathBuf,
    file: File,
    /// Bytes of whole rows in the file.
    len: u64,
}

impl Rows {
    /// Create `dir/name` with `header`, or, resuming at `t_resume`, keep its whole rows up to
    /// then.
    fn open(dir: &Path, name: &str, header: &str, t_resume: Option<f64>) -> io::Result<Self> {
        let path = dir.join(name);
        match t_resume {
            // A new file, never the old one truncated in place: it may be a hard link.
            None => super::write_atomic(&path, format!("{header}\n").as_bytes())?,
            Some(t) => {
                let text = super::atomic::read_own_string(&path).unwrap_or_default();
                // Only rows with their newline were written whole.
                let whole = &text[..text.rfind('\n').map_or(0, |i| i + 1)];
                let keep: Vec<&str> = whole
                    .lines()
                    .skip(1)
                    .filter(|l| {
                        let t_row = l.split(',').next().and_then(|x| x.parse::<f64>().ok());
                        t_row.is_some_and(|x| x <= t + 1e-9 * t.abs().max(1.0))
                    })
                    .collect();
                let mut out = format!("{header}\n");
                keep.iter().for_each(|l| out.extend([*l, "\n"]));
                super::write_atomic(&path, out.as_bytes())?;
            }
        }
        let (file, len) = super::atomic::open_rows(&path)?;
        Ok(Self { path, file, len })
    }

    fn write(&mut self, rows: &str) -> io::Result<()> {
        super::atomic::append_whole(&mut self.file, &mut self.len, rows.as_bytes())
    }
}

/// Why `lines.csv` and `track.csv` in `dir` cannot be continued from a checkpoint whose last
/// frame was at `last_frame` (s): missing, unreadable, or without a whole row of that time.
pub fn check_resumable(dir: &Path, last_frame: Option<f64>, lines: usize) -> Result<(), String> {
    // Rows per frame: one per line, and one of the payload's track.
    for (name, per_frame) in [(LINES_CSV, lines), (TRACK_CSV, 1)] {
        let path = dir.join(name);
        let text = super::atomic::read_own_string(&path).map_err(|e| {
            format!("`{}` of the stopped run cannot be read ({e}): its rows would be lost; run the scenario again", path.display())
        })?;
        let whole = &text[..text.rfind('\n').map_or(0, |i| i + 1)];
        let reaches = |t: f64| {
            let at_t = whole.lines().skip(1).filter(|l| {
                let row_t = l.split(',').next().and_then(|x| x.parse::<f64>().ok());
                row_t.is_some_and(|x| (x - t).abs() <= 1e-9 * t.abs().max(1.0))
            });
            at_t.count() >= per_frame
        };
        if let Some(t) = last_frame.filter(|&t| !reaches(t)) {
            return Err(format!(
                "`{}` lacks rows of the stopped run's last frame (t = {t} s): its rows were lost or cut back; run the scenario again",
                path.display()
            ));
        }
    }
    Ok(())
}

/// The writers of `lines.csv` and `track.csv`.
pub struct ControlFiles {
    lines: Rows,
    track: Rows,
}

impl ControlFiles {
    /// Create both files in `dir` (`t_resume`: cut them back to that time instead).
    pub fn open(dir: &Path, t_resume: Option<f64>) -> io::Result<Self> {
        Ok(Self {
            lines: Rows::open(dir, LINES_CSV, LINES_HEADER, t_resume)?,
            track: Rows::open(dir, TRACK_CSV, TRACK_HEADER, t_resume)?,
        })
    }

    /// Append the rows of time `t`: `[rest length, length, tension]` of every line and the
    /// payload position.
    pub fn push(&mut self, t: f64, lines: &[[f64; 3]], payload: [f64; 3]) -> io::Result<()> {
        let mut text = String::new();
        for (i, [r, l, f]) in lines.iter().enumerate() {
            text.push_str(&format!("{t},{i},{r},{l},{f}\n"));
        }
        self.lines.write(&text)?;
        let [x, y, z] = payload;
        self.track.write(&format!("{t},{x},{y},{z}\n"))
    }

    /// The track so far, read back from `track.csv`: `[x, y]` per row.
    pub fn track(&self) -> io::Result<Vec<[f64; 2]>> {
        let text = super::atomic::read_own_string(&self.track.path)?;
        Ok(text
            .lines()
            .skip(1)
            .filter_map(|l| {
                let v: Vec<f64> = l.split(',').filter_map(|x| x.parse().ok()).collect();
                (v.len() == 4).then(|| [v[1], v[2]])
            })
            .collect())
    }
}

/// Top view of the payload's `track` (m), with the `target` and `landing` points when known;
/// equal scales on both axes.
pub fn track_plot(
    path: &Path,
    track: &[[f64; 2]],
    target: Option<[f64; 2]>,
    landing: Option<[f64; 2]>,
) -> Result<(), PlotError> {
    let pts: Vec<[f64; 2]> = track
        .iter()
        .chain(&target)
        .chain(&landing)
        .copied()
        .collect();
    if pts.is_empty() {
        return Err(PlotError::NoData("track"));
    }
    let range = |k: usize| {
        let lo = pts.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
        let hi = pts.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let ((x0, x1), (y0, y1)) = (range(0), range(1));
    // Equal scales: the larger span (and at least 1 m) on both axes, padded by 10 %.
    let span = (x1 - x0).max(y1 - y0).max(1.0) * 1.1;
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let aspect = PLOT_SIZE.0 as f64 / PLOT_SIZE.1 as f64;
    let (hx, hy) = (0.5 * span * aspect.max(1.0), 0.5 * span);
    let de = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
    render_atomic(path, PLOT_SIZE, |root| {
        let mut chart = line_chart(
            root,
            "Payload track, top view",
            ("x (m)", "y (m)"),
            cx - hx..cx + hx,
            cy - hy..cy + hy,
        )?;
        chart
            .draw_series(LineSeries::new(
                track.iter().map(|p| (p[0], p[1])),
                BLUE.stroke_width(2),
            ))
            .map_err(|e| de(&e))?
            .label("track")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLUE.stroke_width(2)));
        if let Some([x, y]) = target {
            chart
                .draw_series([Cross::new((x, y), 10, RED.stroke_width(3))])
                .map_err(|e| de(&e))?
                .label("target")
                .legend(|(x, y)| Cross::new((x + 10, y), 6, RED.stroke_width(3)));
        }
        if let Some([x, y]) = landing {
            chart
                .draw_series([Circle::new((x, y), 7, BLACK.filled())])
                .map_err(|e| de(&e))?
                .label("landing")
                .legend(|(x, y)| Circle::new((x + 10, y), 5, BLACK.filled()));
        }
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 16))
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| de(&e))?;
        Ok(())
    })
}
