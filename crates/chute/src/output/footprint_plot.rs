//! `footprint.png`: a dispersion study's landing points over the ground (m), the mean point,
//! the 1σ/2σ/3σ covariance ellipses, the release point and the wind's direction, at an equal
//! aspect ratio.

use std::path::Path;

use plotters::prelude::*;

use super::plots::{
    de, render_atomic, PlotError, CAPTION_PX, FONT, MARGIN, X_LABEL_AREA, Y_LABEL_AREA,
};
use crate::study::footprint::{Ellipse, Footprint};

/// The picture's size (pixels): square, so that metres are equal on both axes.
const SIZE: (u32, u32) = (900, 900);

/// Points of the ellipse `e` about `centre` (a closed polygon).
pub(crate) fn outline(e: &Ellipse, centre: [f64; 2]) -> Vec<(f64, f64)> {
    let th = e.angle_deg.to_radians();
    (0..=72)
        .map(|k| {
            let a = k as f64 * 5f64.to_radians();
            let (u, v) = (e.semi_major_m * a.cos(), e.semi_minor_m * a.sin());
            (
                centre[0] + u * th.cos() - v * th.sin(),
                centre[1] + u * th.sin() + v * th.cos(),
            )
        })
        .collect()
}

/// Where the samples start and the wind they meet, for the pictures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Marks {
    /// The samples' mean release point `[x, y]` (m).
    pub release: [f64; 2],
    /// The samples' mean horizontal wind `[x, y]` (m/s), drawn as an arrow from the release
    /// point.
    pub wind: Option<[f64; 2]>,
}

/// Draw `footprint.png` at `path`: the landings `points`, `fp`'s ellipses and mean, and the
/// release point and wind direction of `marks`.
pub fn footprint_plot(
    path: &Path,
    points: &[[f64; 2]],
    fp: &Footprint,
    marks: &Marks,
) -> Result<(), PlotError> {
    let rings: Vec<Vec<(f64, f64)>> = fp.ellipses.iter().map(|e| outline(e, fp.mean_m)).collect();
    let [rx, ry] = marks.release;
    let all = points
        .iter()
        .map(|p| (p[0], p[1]))
        .chain(rings.iter().flatten().copied())
        .chain([(rx, ry)]);
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for (x, y) in all {
        lo = [lo[0].min(x), lo[1].min(y)];
        hi = [hi[0].max(x), hi[1].max(y)];
    }
    // A square window around everything, 10 % wider.
    let half = 0.55 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1.0);
    let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let (x0, x1, y0, y1) = (mid[0] - half, mid[0] + half, mid[1] - half, mid[1] + half);
    render_atomic(path, SIZE, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("Landing footprint, {} samples", fp.samples),
                (FONT, CAPTION_PX),
            )
            .margin(MARGIN)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(de)?;
        chart
            .configure_mesh()
            .x_desc("x (m)")
            .y_desc("y (m)")
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 18))
            .draw()
            .map_err(de)?;
        let shades = [
            RGBColor(200, 30, 30),
            RGBColor(230, 120, 30),
            RGBColor(200, 170, 40),
        ];
        for ((ring, e), colour) in rings.iter().zip(&fp.ellipses).zip(shades) {
            chart
                .draw_series(LineSeries::new(
                    ring.iter().copied(),
                    colour.stroke_width(2),
                ))
                .map_err(de)?
                .label(format!("{}σ ellipse", e.sigma))
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        chart
            .draw_series(
                points
                    .iter()
                    .map(|p| Circle::new((p[0], p[1]), 3, BLUE.filled())),
            )
            .map_err(de)?
            .label("landing points")
            .legend(|(x, y)| Circle::new((x + 10, y), 3, BLUE.filled()));
        let mean = (fp.mean_m[0], fp.mean_m[1]);
        chart
            .draw_series([Cross::new(mean, 8, BLACK.stroke_width(2))])
            .map_err(de)?
            .label("mean landing point")
            .legend(|(x, y)| Cross::new((x + 10, y), 6, BLACK.stroke_width(2)));
        chart
            .draw_series([TriangleMarker::new((rx, ry), 8, GREEN.filled())])
            .map_err(de)?
            .label("release point")
            .legend(|(x, y)| TriangleMarker::new((x + 10, y), 6, GREEN.filled()));
        if let Some(w) = marks.wind.filter(|w| w[0].hypot(w[1]) > 0.0) {
            let len = 0.25 * half / w[0].hypot(w[1]);
            let tip = (rx + w[0] * len, ry + w[1] * len);
            chart
                .draw_series([PathElement::new([(rx, ry), tip], GREEN.stroke_width(3))])
                .map_err(de)?
                .label("wind direction")
                .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], GREEN.stroke_width(3)));
        }
        chart
            .configure_series_labels()
            .label_font((FONT, 15))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(de)
    })
}
