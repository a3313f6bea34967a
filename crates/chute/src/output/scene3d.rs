//! Shaded 3-D pictures of the canopy for the PNG plots: an orthographic projection along a
//! view direction, triangles depth-sorted back to front (painter's algorithm) and shaded by
//! the angle to a light, coloured by height, speed or each triangle's membrane state;
//! segments drawn in the same depth order; load sites and the payload marked on top.
//!
//! Drawn through plotters into an equal-aspect chart of the projected coordinates, so the
//! side views keep their axes in metres and no view is distorted.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::vtk::{ROLE_CANOPY, ROLE_LOAD_SITE, ROLE_PAYLOAD};

/// Marker colour of load sites (a magenta no colour map produces).
pub const LOAD_SITE_RGB: (u8, u8, u8) = (230, 0, 170);
/// Marker colour of the payload.
pub const PAYLOAD_RGB: (u8, u8, u8) = (20, 20, 20);
/// Colour of suspension lines and other non-canopy segments.
pub const LINE_RGB: (u8, u8, u8) = (150, 60, 30);
/// Colours of the membrane states 0 taut (blue), 1 wrinkled (orange) and 2 slack (red), the
/// `membrane_state` cell values of the frames (docs/outputs.md §Frames).
pub const MEMBRANE_STATE_RGB: [(u8, u8, u8); 3] = [(60, 110, 200), (245, 160, 20), (200, 20, 60)];
/// Legend names of the membrane states.
const MEMBRANE_STATE_NAMES: [&str; 3] = ["taut", "wrinkled", "slack"];

/// The field that colours the canopy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourBy {
    /// Height above the lowest canopy node of this state (m).
    Height,
    /// Node speed |v| (m/s).
    Speed,
    /// Each triangle's membrane state ([`ShapeScene::cell_state`]): taut, wrinkled or slack.
    MembraneState,
}

/// One state of the model to draw.
#[derive(Debug, Clone, Copy)]
pub struct ShapeScene<'a> {
    /// Node positions (m).
    pub positions: &'a [[f64; 3]],
    /// Node velocities (m/s); may be empty unless colouring by speed.
    pub velocities: &'a [[f64; 3]],
    /// Canopy triangles (node indices).
    pub triangles: &'a [[usize; 3]],
    /// Segments: rod canopy edges and suspension lines (node indices).
    pub segments: &'a [[usize; 2]],
    /// What each node is ([`super::vtk::point_roles`]); empty: every node is canopy and
    /// nothing is marked.
    pub roles: &'a [u8],
    /// Colouring of the canopy.
    pub colour_by: ColourBy,
    /// One membrane state per triangle (0 taut, 1 wrinkled, 2 slack; the frames'
    /// `membrane_state`); needed only for [`ColourBy::MembraneState`], else may be empty.
    pub cell_state: &'a [u8],
}

impl<'a> ShapeScene<'a> {
    /// A scene of canopy triangles and segments, no roles, coloured by height.
    pub fn new(
        positions: &'a [[f64; 3]],
        triangles: &'a [[usize; 3]],
        segments: &'a [[usize; 2]],
    ) -> Self {
        Self {
            positions,
            velocities: &[],
            triangles,
            segments,
            roles: &[],
            colour_by: ColourBy::Height,
            cell_state: &[],
        }
    }

    /// Whether node `i` belongs to the canopy (load sites do).
    fn is_canopy(&self, i: usize) -> bool {
        self.roles
            .get(i)
            .is_none_or(|&r| r == ROLE_CANOPY || r == ROLE_LOAD_SITE)
    }

    /// Nodes with role `role`.
    fn nodes_with(&self, role: u8) -> impl Iterator<Item = usize> + '_ {
        (0..self.roles.len()).filter(move |&i| self.roles[i] == role)
    }

    /// The problem with this scene, if any: no nodes, bad indices, wrong lengths.
    pub fn check(&self) -> Result<(), &'static str> {
        let n = self.positions.len();
        if n == 0 {
            return Err("no nodes");
        }
        let cells = self.triangles.iter().flatten();
        if cells.chain(self.segments.iter().flatten()).any(|&i| i >= n) {
            return Err("cell node index out of range");
        }
        if !self.roles.is_empty() && self.roles.len() != n {
            return Err("roles do not match the nodes");
        }
        let need_v = self.colour_by == ColourBy::Speed;
        if need_v && self.velocities.len() != n {
            return Err("colouring by speed needs one velocity per node");
        }
        let need_state = self.colour_by == ColourBy::MembraneState;
        if need_state && self.cell_state.len() != self.triangles.len() {
            return Err("colouring by membrane state needs one state per triangle");
        }
        if need_state && self.cell_state.iter().any(|&c| c > 2) {
            return Err("a membrane state is 0 (taut), 1 (wrinkled) or 2 (slack)");
        }
        if self.positions.iter().flatten().any(|x| !x.is_finite()) {
            return Err("non-finite position");
        }
        Ok(())
    }

    /// The colouring value of node `i` and the (min, max) over the canopy nodes.
    fn field(&self) -> (Vec<f64>, (f64, f64)) {
        let vals: Vec<f64> = match self.colour_by {
            ColourBy::Height => self.positions.iter().map(|p| p[2]).collect(),
            // Triangles take their state's colour; nodes have no field.
            ColourBy::MembraneState => vec![0.0; self.positions.len()],
            ColourBy::Speed => self
                .velocities
                .iter()
                .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
                .collect(),
        };
        let (lo, hi) = (0..vals.len())
            .filter(|&i| self.is_canopy(i))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), i| {
                (a.min(vals[i]), b.max(vals[i]))
            });
        let lo = if self.colour_by != ColourBy::Height {
            0.0
        } else {
            lo
        };
        (vals, (lo, hi))
    }
}

/// An orthographic view: screen axes `right` and `up`, and the unit vector `toward` the
/// viewer (depth grows toward the viewer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Screen x axis (unit, world frame).
    pub right: [f64; 3],
    /// Screen y axis (unit, world frame).
    pub up: [f64; 3],
    /// Unit vector from the scene to the viewer.
    pub toward: [f64; 3],
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalised(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    if n > 0.0 {
        a.map(|x| x / n)
    } else {
        a
    }
}

impl View {
    /// The view from azimuth `az_deg` (from +x toward +y) and elevation `el_deg` above the
    /// horizon, z up on screen. |elevation| must be below 90°.
    pub fn from_angles(az_deg: f64, el_deg: f64) -> Self {
        let (az, el) = (az_deg.to_radians(), el_deg.to_radians());
        let toward = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
        let forward = toward.map(|x| -x);
        let right = normalised(cross(forward, [0.0, 0.0, 1.0]));
        Self {
            right,
            up: cross(right, forward),
            toward,
        }
    }

    /// The oblique view of the 3-D panel: from azimuth −60°, 25° above the horizon.
    pub fn oblique() -> Self {
        Self::from_angles(-60.0, 25.0)
    }

    /// Looking down the −z axis, x right and y up on screen.
    pub fn top() -> Self {
        Self {
            right: [1.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            toward: [0.0, 0.0, 1.0],
        }
    }

    /// Side view x–z, looking along +y.
    pub fn side_xz() -> Self {
        Self::from_angles(-90.0, 0.0)
    }

    /// Side view y–z, looking along −x.
    pub fn side_yz() -> Self {
        Self::from_angles(0.0, 0.0)
    }

    /// Screen coordinates of a point (m).
    pub fn project(&self, p: [f64; 3]) -> (f64, f64) {
        (dot(p, self.right), dot(p, self.up))
    }
}

/// The viridis colour map at `s` ∈ [0, 1] (five stops, linear between them).
pub fn viridis(s: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let x = if s.is_finite() {
        s.clamp(0.0, 1.0)
    } else {
        0.0
    } * 4.0;
    let k = (x.floor() as usize).min(3);
    let f = x - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |u: f64, v: f64| (u + f * (v - u)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Something drawn in depth order.
enum Item {
    Triangle([usize; 3], RGBColor),
    Segment([usize; 2], ShapeStyle),
}

/// Equal-aspect ranges of the projected points for a plotting area of `px` pixels.
fn equal_aspect(pts: &[(f64, f64)], px: (u32, u32)) -> ((f64, f64), (f64, f64)) {
    let fold = |f: fn(&(f64, f64)) -> f64| {
        pts.iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
    };
    let ((x0, x1), (y0, y1)) = (fold(|p| p.0), fold(|p| p.1));
    let (w, h) = (f64::from(px.0.max(1)), f64::from(px.1.max(1)));
    let span = (x1 - x0).max(y1 - y0).max(1e-6);
    let m_per_px = ((x1 - x0) / w).max((y1 - y0) / h).max(span * 1e-3 / w) * 1.08;
    let centred = |lo: f64, hi: f64, px: f64| {
        let mid = 0.5 * (lo + hi);
        (mid - 0.5 * m_per_px * px, mid + 0.5 * m_per_px * px)
    };
    (centred(x0, x1, w), centred(y0, y1, h))
}

/// Pixel sizes of the chart decorations of a panel: (label area x, label area y, margin).
const AXES_PX: (u32, u32, u32) = (45, 65, 12);

/// Draw `scene` seen along `view` into `area`, with axis labels `axes` (e.g. `("x (m)",
/// "z (m)")`) or none (the oblique view: screen axes mean nothing there).
pub fn draw_view<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    scene: &ShapeScene<'_>,
    view: &View,
    axes: Option<(&str, &str)>,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let proj: Vec<(f64, f64)> = scene.positions.iter().map(|&p| view.project(p)).collect();
    let (lx, ly, margin) = if axes.is_some() { AXES_PX } else { (0, 0, 12) };
    let (w, h) = area.dim_in_pixel();
    let plot_px = (
        w.saturating_sub(2 * margin + ly),
        h.saturating_sub(2 * margin + lx),
    );
    let ((x0, x1), (y0, y1)) = equal_aspect(&proj, plot_px);
    let mut chart = ChartBuilder::on(area)
        .margin(margin)
        .x_label_area_size(lx)
        .y_label_area_size(ly)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(e)?;
    if let Some((xd, yd)) = axes {
        chart
            .configure_mesh()
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .x_desc(xd)
            .y_desc(yd)
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(e)?;
    }
    let (vals, (lo, hi)) = scene.field();
    let colour = |v: f64| viridis((v - lo) / (hi - lo).max(1e-12));
    let light =
        normalised([0, 1, 2].map(|c| view.toward[c] + 0.5 * view.up[c] - 0.3 * view.right[c]));
    let pos = scene.positions;
    let mut items: Vec<(f64, Item)> =
        Vec::with_capacity(scene.triangles.len() + scene.segments.len());
    for (k, &t) in scene.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|i| pos[i]);
        let n = normalised(cross(
            [0, 1, 2].map(|k| b[k] - a[k]),
            [0, 1, 2].map(|k| c[k] - a[k]),
        ));
        // Two-sided Lambert shading plus ambient: the canopy has no outside or inside.
        let shade = 0.35 + 0.65 * dot(n, light).abs();
        let RGBColor(r, g, bl) = match scene.cell_state.get(k) {
            Some(&st) if scene.colour_by == ColourBy::MembraneState => {
                let (r, g, b) = MEMBRANE_STATE_RGB[usize::from(st)];
                RGBColor(r, g, b)
            }
            _ => colour(t.iter().map(|&i| vals[i]).sum::<f64>() / 3.0),
        };
        let lit = |x: u8| (f64::from(x) * shade).round() as u8;
        let depth = (dot(a, view.toward) + dot(b, view.toward) + dot(c, view.toward)) / 3.0;
        items.push((depth, Item::Triangle(t, RGBColor(lit(r), lit(g), lit(bl)))));
    }
    for &s in scene.segments {
        let canopy = scene.is_canopy(s[0]) && scene.is_canopy(s[1]);
        let style = if canopy {
            colour(0.5 * (vals[s[0]] + vals[s[1]])).stroke_width(4)
        } else {
            let (r, g, b) = LINE_RGB;
            RGBColor(r, g, b).stroke_width(1)
        };
        let depth = 0.5 * (dot(pos[s[0]], view.toward) + dot(pos[s[1]], view.toward));
        items.push((depth, Item::Segment(s, style)));
    }
    items.sort_by(|a, b| a.0.total_cmp(&b.0));
    let plot = chart.plotting_area();
    for (_, item) in &items {
        match item {
            Item::Triangle(t, c) => {
                plot.draw(&Polygon::new(t.map(|i| proj[i]).to_vec(), c.filled()))
            }
            Item::Segment(s, style) => {
                plot.draw(&PathElement::new(vec![proj[s[0]], proj[s[1]]], *style))
            }
        }
        .map_err(e)?;
    }
    draw_markers(plot, scene, &proj).map_err(e)
}

/// Load sites as magenta dots and the payload as a labelled black square, on top.
fn draw_markers<DB: DrawingBackend>(
    plot: &DrawingArea<
        DB,
        plotters::coord::cartesian::Cartesian2d<
            plotters::coord::types::RangedCoordf64,
            plotters::coord::types::RangedCoordf64,
        >,
    >,
    scene: &ShapeScene<'_>,
    proj: &[(f64, f64)],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (r, g, b) = LOAD_SITE_RGB;
    for i in scene.nodes_with(ROLE_LOAD_SITE) {
        plot.draw(&Circle::new(proj[i], 5, RGBColor(r, g, b).filled()))?;
        plot.draw(&Circle::new(proj[i], 5, WHITE.stroke_width(1)))?;
    }
    let (r, g, b) = PAYLOAD_RGB;
    for i in scene.nodes_with(ROLE_PAYLOAD) {
        let c = RGBColor(r, g, b);
        let square = EmptyElement::at(proj[i])
            + Rectangle::new([(-7, -7), (7, 7)], c.filled())
            + Text::new(
                "payload",
                (11, -7),
                ("sans-serif", 16).into_font().color(&c),
            );
        plot.draw(&square)?;
    }
    Ok(())
}

/// A vertical colour bar at pixel `(x, y)` of `area`, `h` pixels tall, labelled with the
/// field's range over the canopy.
pub fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    scene: &ShapeScene<'_>,
    (x, y, h): (i32, i32, i32),
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (_, (lo, hi)) = scene.field();
    let (name, value) = match scene.colour_by {
        ColourBy::Height => ("height above lowest node", hi - lo),
        ColourBy::Speed => ("speed |v|", hi),
        ColourBy::MembraneState => return draw_state_legend(area, scene, (x, y)).map_err(e),
    };
    let unit = if scene.colour_by == ColourBy::Height {
        "m"
    } else {
        "m/s"
    };
    for k in 0..h {
        let c = viridis(1.0 - f64::from(k) / f64::from(h.max(1)));
        area.draw(&Rectangle::new(
            [(x, y + k), (x + 16, y + k + 1)],
            c.filled(),
        ))
        .map_err(e)?;
    }
    let font = ("sans-serif", 15).into_font();
    let top = format!("{} {unit}", crate::scenario::derived::sig4(value));
    area.draw(&Text::new(top, (x + 22, y), font.clone()))
        .map_err(e)?;
    area.draw(&Text::new(
        format!("0 {unit}"),
        (x + 22, y + h - 14),
        font.clone(),
    ))
    .map_err(e)?;
    area.draw(&Text::new(name, (x - 4, y - 22), font))
        .map_err(e)
}

/// The membrane states' swatches at pixel `(x, y)` of `area`, each with its share of the
/// canopy's triangles.
fn draw_state_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    scene: &ShapeScene<'_>,
    (x, y): (i32, i32),
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let font = ("sans-serif", 15).into_font();
    area.draw(&Text::new("membrane state", (x - 4, y - 22), font.clone()))?;
    let n = scene.cell_state.len().max(1) as f64;
    for (k, ((r, g, b), name)) in MEMBRANE_STATE_RGB
        .iter()
        .zip(MEMBRANE_STATE_NAMES)
        .enumerate()
    {
        let count = scene
            .cell_state
            .iter()
            .filter(|&&c| usize::from(c) == k)
            .count();
        let top = y + 26 * k as i32;
        let swatch = [(x, top), (x + 16, top + 16)];
        area.draw(&Rectangle::new(swatch, RGBColor(*r, *g, *b).filled()))?;
        let label = format!("{name} {:.0} %", 100.0 * count as f64 / n);
        area.draw(&Text::new(label, (x + 22, top), font.clone()))?;
    }
    Ok(())
}

/// Axis directions x, y, z of `view` as a small labelled triad centred at pixel `(x, y)`.
pub fn draw_triad<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    view: &View,
    (x, y): (i32, i32),
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let len = 34.0;
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        let mut axis = [0.0; 3];
        axis[k] = 1.0;
        let (u, v) = view.project(axis);
        let tip = (x + (len * u).round() as i32, y - (len * v).round() as i32);
        area.draw(&PathElement::new(vec![(x, y), tip], BLACK.stroke_width(2)))
            .map_err(e)?;
        let label = (
            tip.0 + (6.0 * u).round() as i32 - 4,
            tip.1 - (6.0 * v).round() as i32 - 8,
        );
        area.draw(&Text::new(*name, label, ("sans-serif", 15).into_font()))
            .map_err(e)?;
    }
    Ok(())
}
