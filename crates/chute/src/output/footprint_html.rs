//! `footprint.html`: the footprint of `footprint.png` as a self-contained page a browser opens
//! offline (inline SVG, no script): landings (each with its sample and point as a tooltip), the
//! 1σ/2σ/3σ ellipses, the mean point, the release point and the wind's direction over a grid
//! in metres, then the statistics, how they settle with N, and the sensitivity ranking.

use std::fmt::Write as _;

use crate::study::footprint::{Footprint, Sensitivity, Settling};

/// The page's parts: the landings `(sample, [x, y])`, their footprint, how it settles with N,
/// the inputs ranked, the release point and the wind.
pub struct Page<'a> {
    /// The study's name.
    pub study: &'a str,
    /// Every landing with its sample's name.
    pub landings: &'a [(String, [f64; 2])],
    /// Their footprint.
    pub footprint: &'a Footprint,
    /// The footprint of the first N/4, N/2 and N landings.
    pub settling: &'a [Settling],
    /// The inputs ranked by their share in the spread.
    pub sensitivity: &'a [Sensitivity],
    /// The release point and the wind's direction.
    pub marks: super::footprint_plot::Marks,
}

/// Drawing size of the square plot (CSS pixels).
const PX: f64 = 640.0;

/// A round grid step near a fifth of `span`: 1, 2 or 5 × 10^k.
fn grid_step(span: f64) -> f64 {
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag)
}

/// The square window `[x0, y0, side]` (m) around the landings, the ellipses and the origin.
fn window(p: &Page) -> [f64; 3] {
    let f = p.footprint;
    let r = f.ellipses[2].semi_major_m;
    let pts = p.landings.iter().map(|l| l.1).chain([
        p.marks.release,
        [f.mean_m[0] - r, f.mean_m[1] - r],
        [f.mean_m[0] + r, f.mean_m[1] + r],
    ]);
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for q in pts {
        lo = [lo[0].min(q[0]), lo[1].min(q[1])];
        hi = [hi[0].max(q[0]), hi[1].max(q[1])];
    }
    let side = 1.1 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1.0);
    let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    [mid[0] - side / 2.0, mid[1] - side / 2.0, side]
}

/// The grid's ticks in `[lo, lo + side]`: whole multiples of `step` (no accumulated round-off,
/// and 0 printed as 0, not −0).
fn ticks(lo: f64, side: f64, step: f64) -> Vec<f64> {
    let (k0, k1) = (
        (lo / step).ceil() as i64,
        ((lo + side) / step).floor() as i64,
    );
    (k0..=k1).map(|k| k as f64 * step + 0.0).collect()
}

/// The grid lines (in the flipped group) and their labels (outside it, so the text is upright)
/// of the window `[x0, y0, side]`; `font` in metres.
fn grid([x0, y0, side]: [f64; 3], font: f64) -> (String, String) {
    let step = grid_step(side);
    let (mut lines, mut labels) = (String::new(), String::new());
    for g in ticks(x0, side, step) {
        let (y1, yl) = (y0 + side, -y0 - 0.5 * font);
        let _ = writeln!(
            lines,
            "<line class=\"grid\" x1=\"{g}\" y1=\"{y0}\" x2=\"{g}\" y2=\"{y1}\"/>"
        );
        let _ = writeln!(
            labels,
            "<text class=\"label\" x=\"{g}\" y=\"{yl}\" font-size=\"{font}\">{g}</text>"
        );
    }
    for g in ticks(y0, side, step) {
        let (x1, xl) = (x0 + side, x0 + 0.5 * font);
        let _ = writeln!(
            lines,
            "<line class=\"grid\" x1=\"{x0}\" y1=\"{g}\" x2=\"{x1}\" y2=\"{g}\"/>"
        );
        let _ = writeln!(
            labels,
            "<text class=\"label\" x=\"{xl}\" y=\"{}\" font-size=\"{font}\">{g}</text>",
            -g
        );
    }
    (lines, labels)
}

/// The mean point's cross, the release point's triangle and the wind's direction, `c` metres
/// across, the arrow `len` metres long.
fn markers(p: &Page, c: f64, len: f64) -> String {
    let [mx, my] = p.footprint.mean_m;
    let mut s = format!(
        "<path class=\"mean\" d=\"M{} {} L{} {} M{} {} L{} {}\"><title>mean landing point</title></path>\n",
        mx - c, my - c, mx + c, my + c, mx - c, my + c, mx + c, my - c
    );
    let [rx, ry] = p.marks.release;
    let _ = writeln!(
        s,
        "<path class=\"release\" d=\"M{rx} {} L{} {} L{} {} Z\"><title>release point</title></path>",
        ry + c, rx - c, ry - c, rx + c, ry - c
    );
    if let Some(w) = p.marks.wind.filter(|w| w[0].hypot(w[1]) > 0.0) {
        let k = len / w[0].hypot(w[1]);
        let _ = writeln!(
            s,
            "<line class=\"wind\" x1=\"{rx}\" y1=\"{ry}\" x2=\"{}\" y2=\"{}\"><title>wind direction</title></line>",
            rx + w[0] * k, ry + w[1] * k
        );
    }
    s
}

/// The SVG plot: metres in, y up (the group flips the page's downward y).
fn svg(p: &Page) -> String {
    let [x0, y0, side] = window(p);
    let m = side / PX; // metres per pixel
    let (lines, labels) = grid([x0, y0, side], 11.0 * m);
    let mut s = format!(
        "<svg id=\"footprint\" width=\"{PX}\" height=\"{PX}\" viewBox=\"{x0} {} {side} {side}\" \
         xmlns=\"http://www.w3.org/2000/svg\">\n<g transform=\"scale(1,-1)\">\n{lines}",
        -(y0 + side)
    );
    let f = p.footprint;
    // Outlines rather than <ellipse>: a footprint along a line (a zero minor axis) is drawn
    // too; the outer first, so that the 1σ one stays visible where they overlap.
    for e in f.ellipses.iter().rev() {
        let ring = super::footprint_plot::outline(e, f.mean_m);
        let d: Vec<String> = ring.iter().map(|(x, y)| format!("{x} {y}")).collect();
        let _ = writeln!(
            s,
            "<path class=\"sigma-{}\" data-semi-major-m=\"{}\" data-semi-minor-m=\"{}\" d=\"M{}Z\"/>",
            e.sigma,
            e.semi_major_m,
            e.semi_minor_m,
            d.join(" L")
        );
    }
    for (name, q) in p.landings {
        let _ = writeln!(
            s,
            "<circle class=\"landing\" cx=\"{}\" cy=\"{}\" r=\"{}\"><title>{}: ({:.1}, {:.1}) m</title></circle>",
            q[0], q[1], 3.5 * m, super::viewer::html_escape(name), q[0], q[1]
        );
    }
    s += &markers(p, 7.0 * m, 0.15 * side);
    s += "</g>\n";
    s += &labels;
    s += "</svg>\n";
    s
}

/// The statistics under the plot.
fn tables(p: &Page) -> String {
    let f = p.footprint;
    // Four significant figures: a footprint may be kilometres or centimetres across.
    let g = crate::scenario::derived::sig4;
    let mut s = format!(
        "<table><tr><th>samples</th><td>{}</td></tr>\n<tr><th>mean landing point (m)</th><td>({}, {})</td></tr>\n",
        f.samples, g(f.mean_m[0]), g(f.mean_m[1])
    );
    for e in &f.ellipses {
        let _ = writeln!(
            s,
            "<tr><th>{}σ ellipse (m)</th><td>{} × {} at {:.1}°</td></tr>",
            e.sigma,
            g(e.semi_major_m),
            g(e.semi_minor_m),
            e.angle_deg
        );
    }
    let _ = writeln!(
        s,
        "<tr><th>CEP50, CEP90 (m)</th><td>{}, {}</td></tr></table>",
        g(f.cep50_m),
        g(f.cep90_m)
    );
    s.push_str("<h2>With the number of samples</h2>\n<table id=\"settling\"><tr><th>N</th><th>mean (m) ± s.e.</th><th>1σ semi-axes (m) ± s.e.</th><th>CEP50 (m)</th></tr>\n");
    for t in p.settling {
        let pm = |x: f64, e: f64| format!("{} ± {}", g(x), g(e));
        let _ = writeln!(
            s,
            "<tr><td>{}</td><td>({}, {})</td><td>{}, {}</td><td>{}</td></tr>",
            t.samples,
            pm(t.mean_m[0], t.mean_standard_error_m[0]),
            pm(t.mean_m[1], t.mean_standard_error_m[1]),
            pm(t.semi_axes_m[0], t.semi_axes_standard_error_m[0]),
            pm(t.semi_axes_m[1], t.semi_axes_standard_error_m[1]),
            g(t.cep50_m)
        );
    }
    s.push_str("</table>\n<h2>What drives the spread</h2>\n<p>Pearson correlation of each input with the landing's x and y, ranked by r_x² + r_y².</p>\n<table id=\"sensitivity\"><tr><th>input</th><th>r_x</th><th>r_y</th></tr>\n");
    for r in p.sensitivity {
        let _ = writeln!(
            s,
            "<tr><td>{}</td><td>{:.3}</td><td>{:.3}</td></tr>",
            super::viewer::html_escape(&r.key),
            r.r_x,
            r.r_y
        );
    }
    s.push_str("</table>\n");
    s
}

/// The whole page.
pub fn page(p: &Page) -> String {
    let title = super::viewer::html_escape(p.study);
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>{title}: landing footprint</title>\n<style>\n\
         body {{ font-family: sans-serif; margin: 1.5em; }}\n\
         svg {{ border: 1px solid #999; background: #fff; }}\n\
         svg * {{ vector-effect: non-scaling-stroke; }}\n\
         .grid {{ stroke: #ddd; stroke-width: 1; }}\n\
         .label {{ fill: #555; font-family: sans-serif; }}\n\
         .landing {{ fill: #1f4fd1; }}\n\
         .sigma-1 {{ fill: none; stroke: #c81e1e; stroke-width: 2; }}\n\
         .sigma-2 {{ fill: none; stroke: #e6781e; stroke-width: 2; }}\n\
         .sigma-3 {{ fill: none; stroke: #c8aa28; stroke-width: 2; }}\n\
         .mean {{ stroke: #000; stroke-width: 2; fill: none; }}\n\
         .release {{ fill: #1a9a3a; }}\n\
         .wind {{ stroke: #1a9a3a; stroke-width: 3; }}\n\
         table {{ border-collapse: collapse; margin: 0.8em 0; }}\n\
         th, td {{ border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: left; }}\n\
         </style></head><body>\n<h1>{title}: landing footprint</h1>\n\
         <p>Landings (blue; hover for the sample), 1σ/2σ/3σ covariance ellipses (red, orange, yellow), \
         mean point (cross), release point (green triangle) and the wind's direction (green line). \
         Axes in metres: the scenario's x and y.</p>\n{}{}</body></html>\n",
        svg(p),
        tables(p)
    )
}
