//! Physical ranges and cross-key consistency of a typed scenario. Each rule says *why* a
//! value is refused; the first violation in reading order is reported.

use super::error::ScenarioError;
use super::source::Provenance;
use super::{CanopyShape, DragLaw, LoadMode, ModelKind, Scenario, SiteSet, Sites};

/// Upper bounds that keep a typo (an extra zero or three) from exhausting memory or time.
const MAX_ROD_NODES: usize = 100_000;
const MAX_SHELL_TRIANGLES: f64 = 2.0e6;
const MAX_STEPS: f64 = 1.0e8;
const MAX_LINE_SEGMENTS: usize = 10_000;
const MAX_SITES: usize = 10_000;
const MAX_NEWTON: usize = 1_000;

struct Checker<'a> {
    prov: &'a Provenance,
    errors: Vec<((u8, usize, usize), ScenarioError)>,
}

impl Checker<'_> {
    fn fail(&mut self, key: &str, value: impl ToString, reason: impl Into<String>) {
        let e = ScenarioError::Invalid {
            key: key.to_string(),
            value: value.to_string(),
            reason: reason.into(),
            origin: self.prov.origin(key),
        };
        self.errors.push((self.prov.rank(key), e));
    }

    fn positive(&mut self, key: &str, v: f64, why: &str) {
        if v <= 0.0 {
            self.fail(key, v, format!("must be positive ({why})"));
        }
    }

    fn non_negative(&mut self, key: &str, v: f64, why: &str) {
        if v < 0.0 {
            self.fail(key, v, format!("must not be negative ({why})"));
        }
    }

    fn count(&mut self, key: &str, v: usize, lo: usize, hi: usize, why: &str) {
        if v < lo || v > hi {
            self.fail(key, v, format!("must be between {lo} and {hi} ({why})"));
        }
    }

    fn poisson(&mut self, key: &str, v: f64) {
        if !(v > -1.0 && v <= 0.5) {
            self.fail(
                key,
                v,
                "must lie in (−1, 0.5] for a stable isotropic material",
            );
        }
    }

    fn choice(
        &mut self,
        key: &str,
        value: &str,
        allowed: &'static [&'static str],
        context: &'static str,
    ) {
        let e = ScenarioError::BadChoice {
            key: key.to_string(),
            value: value.to_string(),
            allowed,
            context,
            origin: self.prov.origin(key),
        };
        self.errors.push((self.prov.rank(key), e));
    }
}

/// Check every physical range and cross-key rule; `Ok` means the builders can use `s`.
pub fn validate(s: &Scenario, prov: &Provenance) -> Result<(), ScenarioError> {
    let mut c = Checker {
        prov,
        errors: Vec::new(),
    };
    name(&mut c, &s.name);
    canopy(&mut c, s);
    material_and_lines(&mut c, s);
    load(&mut c, s);
    fluid(&mut c, s);
    time_and_output(&mut c, s);
    c.errors.sort_by_key(|(rank, _)| *rank);
    match c.errors.into_iter().next() {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}

fn name(c: &mut Checker, name: &str) {
    let ok_chars = name
        .chars()
        .all(|ch| ch.is_ascii_alphanumeric() || "-_.".contains(ch));
    if name.is_empty() || name.len() > 100 || !ok_chars || name.starts_with('.') {
        c.fail(
            "name",
            format!("\"{name}\""),
            "it names the output directory: use 1–100 letters, digits, '-', '_' or '.', not starting with '.'",
        );
    }
}

/// The in-plane size that bounds the thickness and the shell edge length (m).
fn in_plane_size(s: &Scenario) -> Option<f64> {
    let cn = &s.canopy;
    match (s.model.kind, cn.shape) {
        (ModelKind::Rod, _) | (_, CanopyShape::Rectangle) => Some(cn.span_m.min(cn.width_m)),
        (_, CanopyShape::Hexagon | CanopyShape::Circle) => Some(2.0 * cn.radius_m),
        (_, CanopyShape::Mesh) => None,
    }
}

fn canopy(c: &mut Checker, s: &Scenario) {
    let cn = &s.canopy;
    c.positive("canopy.span_m", cn.span_m, "a length");
    c.positive("canopy.width_m", cn.width_m, "a length");
    c.positive("canopy.thickness_m", cn.thickness_m, "a length");
    c.positive("canopy.edge_length_m", cn.edge_length_m, "a length");
    c.positive("canopy.radius_m", cn.radius_m, "a length");
    if s.model.kind == ModelKind::Rod {
        if cn.shape != CanopyShape::Rectangle {
            c.choice(
                "canopy.shape",
                shape_name(cn.shape),
                &["rectangle"],
                "for a rod model (a strip)",
            );
        }
        c.count(
            "canopy.nodes",
            cn.nodes,
            3,
            MAX_ROD_NODES,
            "a rod needs 3 nodes to bend",
        );
    }
    let size = in_plane_size(s).filter(|x| *x > 0.0);
    if let Some(size) = size {
        if cn.thickness_m > 0.1 * size {
            c.fail(
                "canopy.thickness_m",
                cn.thickness_m,
                format!("thin-structure models need a thickness below 1/10 of the canopy size ({size} m); is it in metres?"),
            );
        }
    }
    if s.model.kind == ModelKind::Shell && cn.edge_length_m > 0.0 {
        if let (Some(size), Some(area)) = (size, s.planform_area_m2()) {
            if cn.edge_length_m > 0.5 * size {
                c.fail(
                    "canopy.edge_length_m",
                    cn.edge_length_m,
                    format!("the mesh needs at least two edges across the canopy (size {size} m)"),
                );
            }
            let triangles = area / (0.25 * 3f64.sqrt() * cn.edge_length_m.powi(2));
            if triangles > MAX_SHELL_TRIANGLES {
                c.fail(
                    "canopy.edge_length_m",
                    cn.edge_length_m,
                    format!("about {triangles:.0} triangles; at most {MAX_SHELL_TRIANGLES:.0} are allowed"),
                );
            }
        }
    }
    imperfection(c, s, size);
    mesh(c, s);
}

/// `canopy.imperfection_m`: a shell-only initial perturbation, at most 5 % of the canopy size
/// (a probe of the flat start's symmetry, not a new rest shape).
fn imperfection(c: &mut Checker, s: &Scenario, size: Option<f64>) {
    let a = s.canopy.imperfection_m;
    let key = "canopy.imperfection_m";
    if a == 0.0 {
        return;
    }
    if s.model.kind == ModelKind::Rod {
        c.fail(
            key,
            a,
            "only a shell canopy takes an initial out-of-plane perturbation; a rod starts straight",
        );
    } else if let Some(size) = size.filter(|&x| a.abs() > 0.05 * x) {
        c.fail(
            key,
            a,
            format!("at most 5 % of the canopy size ({size} m): it perturbs the flat start, it is not a shape"),
        );
    }
}

fn shape_name(s: CanopyShape) -> &'static str {
    match s {
        CanopyShape::Rectangle => "rectangle",
        CanopyShape::Hexagon => "hexagon",
        CanopyShape::Circle => "circle",
        CanopyShape::Mesh => "mesh",
    }
}

fn mesh(c: &mut Checker, s: &Scenario) {
    let key = "canopy.mesh_file";
    match (&s.canopy.mesh_file, s.canopy.shape == CanopyShape::Mesh) {
        (None, true) => c.errors.push((
            c.prov.rank("canopy.shape"),
            ScenarioError::Missing {
                key: key.into(),
                reason: "`canopy.shape = \"mesh\"` reads the canopy from a mesh file (.txt DisMech or .obj)".into(),
            },
        )),
        (Some(p), false) => c.fail(
            key,
            format!("\"{}\"", p.display()),
            "a mesh file is only read when `canopy.shape = \"mesh\"`",
        ),
        (Some(p), true) => {
            let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
            if !p.is_file() {
                let e = ScenarioError::MeshMissing {
                    key: key.into(),
                    path: p.clone(),
                    origin: c.prov.origin(key),
                };
                c.errors.push((c.prov.rank(key), e));
            } else if ext != "txt" && ext != "obj" {
                c.fail(
                    key,
                    format!("\"{}\"", p.display()),
                    "the mesh format is chosen by extension: `.txt` (DisMech) or `.obj` (Wavefront)",
                );
            }
        }
        (None, false) => {}
    }
}

fn material_and_lines(c: &mut Checker, s: &Scenario) {
    let m = &s.material;
    c.positive(
        "material.youngs_modulus_pa",
        m.youngs_modulus_pa,
        "a stiffness",
    );
    c.positive(
        "material.density_kg_m3",
        m.density_kg_m3,
        "the canopy needs mass",
    );
    c.poisson("material.poisson_ratio", m.poisson_ratio);
    let l = &s.lines;
    c.positive("lines.length_m", l.length_m, "a length");
    c.count(
        "lines.segments",
        l.segments,
        1,
        MAX_LINE_SEGMENTS,
        "rod edges per line",
    );
    c.positive("lines.radius_m", l.radius_m, "a length");
    c.positive(
        "lines.youngs_modulus_pa",
        l.youngs_modulus_pa,
        "a stiffness",
    );
    c.positive(
        "lines.density_kg_m3",
        l.density_kg_m3,
        "the lines need mass",
    );
    c.poisson("lines.poisson_ratio", l.poisson_ratio);
    if let Some(cd) = l.drag_coefficient {
        c.non_negative("lines.drag_coefficient", cd, "a drag coefficient");
    }
}

/// Named site sets that make sense for this model and outline.
fn allowed_sites(s: &Scenario) -> (&'static [&'static str], &'static str) {
    match (s.model.kind, s.canopy.shape) {
        (ModelKind::Rod, _) => (&["ends", "center"], "for a rod canopy"),
        (_, CanopyShape::Rectangle) => (
            &["corners", "corners_and_midspan", "center"],
            "for a rectangular shell",
        ),
        (_, CanopyShape::Hexagon) => (&["corners", "center"], "for a hexagonal shell"),
        (_, CanopyShape::Circle) => (&["rim", "center"], "for a circular shell"),
        (_, CanopyShape::Mesh) => (&["center"], "for a mesh canopy (or give [x, y] points)"),
    }
}

fn site_name(s: SiteSet) -> &'static str {
    match s {
        SiteSet::Ends => "ends",
        SiteSet::Corners => "corners",
        SiteSet::CornersAndMidspan => "corners_and_midspan",
        SiteSet::Center => "center",
        SiteSet::Rim => "rim",
    }
}

fn load(c: &mut Checker, s: &Scenario) {
    let l = &s.load;
    c.positive(
        "load.weight_n",
        l.weight_n,
        "the load must pull the canopy down",
    );
    if l.mode == LoadMode::NodeMassScale {
        if s.canopy.shape != CanopyShape::Mesh {
            c.choice(
                "load.mode",
                "node_mass_scale",
                &["force", "payload", "mass"],
                "unless `canopy.shape = \"mesh\"`",
            );
        }
        c.count(
            "load.node",
            l.node,
            1,
            usize::MAX,
            "a 1-based mesh node number",
        );
        c.positive("load.mass_scale", l.mass_scale, "a mass factor");
        return;
    }
    let (allowed, context) = allowed_sites(s);
    match &l.sites {
        Sites::Named(set) => {
            let n = site_name(*set);
            if !allowed.contains(&n) {
                c.choice("load.sites", n, allowed, context);
            }
            if *set == SiteSet::Rim {
                c.count(
                    "load.rim_site_count",
                    l.rim_site_count,
                    3,
                    MAX_SITES,
                    "rim sites around the circle",
                );
            }
        }
        Sites::Points(points) => {
            if points.len() > MAX_SITES {
                c.fail(
                    "load.sites",
                    format!("{} points", points.len()),
                    format!("at most {MAX_SITES} sites"),
                );
            }
            for (i, p) in points.iter().enumerate() {
                if let Some(shape) = outside(s, *p) {
                    let e = ScenarioError::SiteOutside {
                        key: "load.sites".into(),
                        index: i,
                        x: p[0],
                        y: p[1],
                        shape,
                        origin: c.prov.origin("load.sites"),
                    };
                    c.errors.push((c.prov.rank("load.sites"), e));
                    break;
                }
            }
        }
    }
}

/// `Some(outline description)` when the point lies outside the canopy; meshes are checked
/// by the builder, which knows their outline.
fn outside(s: &Scenario, p: [f64; 2]) -> Option<String> {
    let cn = &s.canopy;
    let (x, y) = (p[0], p[1]);
    let shape = in_plane_size(s)?;
    let eps = 1e-9 * shape.max(1.0);
    let rect = || {
        let (hx, hy) = (cn.span_m / 2.0, cn.width_m / 2.0);
        (x.abs() > hx + eps || y.abs() > hy + eps)
            .then(|| format!("the rectangle x ∈ [−{hx}, {hx}] m, y ∈ [−{hy}, {hy}] m"))
    };
    match (s.model.kind, cn.shape) {
        (ModelKind::Rod, _) | (_, CanopyShape::Rectangle) => rect(),
        (_, CanopyShape::Circle) => {
            let r = cn.radius_m;
            (x.hypot(y) > r + eps).then(|| format!("the circle of radius {r} m about the origin"))
        }
        (_, CanopyShape::Hexagon) => {
            // Inside iff the projection on each of the six edge normals (at 30° + k·60°) is at
            // most the apothem R·√3/2.
            let r = cn.radius_m;
            let apothem = r * 3f64.sqrt() / 2.0;
            let out = (0..6).any(|k| {
                let a = (30.0 + 60.0 * k as f64).to_radians();
                x * a.cos() + y * a.sin() > apothem + eps
            });
            out.then(|| format!("the hexagon of circumradius {r} m with a corner on +x"))
        }
        (_, CanopyShape::Mesh) => None,
    }
}

fn fluid(c: &mut Checker, s: &Scenario) {
    let f = &s.fluid;
    c.positive(
        "fluid.density_kg_m3",
        f.density_kg_m3,
        "drag scales with the air density",
    );
    c.positive(
        "fluid.viscosity_pa_s",
        f.viscosity_pa_s,
        "the Reynolds number divides by it",
    );
    c.positive(
        "fluid.drag_coefficient",
        f.drag_coefficient,
        "without drag there is no terminal velocity",
    );
    c.non_negative(
        "fluid.tangential_drag_coefficient",
        f.tangential_drag_coefficient,
        "drag opposes motion",
    );
    c.positive(
        "fluid.gravity_mps2",
        f.gravity_mps2,
        "gravity points down, −z",
    );
    match (f.drag, f.linear_drag_coefficient_n_s_m) {
        (DragLaw::Linear, None) => c.errors.push((
            c.prov.rank("fluid.drag"),
            ScenarioError::Missing {
                key: "fluid.linear_drag_coefficient_n_s_m".into(),
                reason: "`fluid.drag = \"linear\"` needs the whole-canopy coefficient c (N·s/m)"
                    .into(),
            },
        )),
        (_, Some(k)) => c.positive(
            "fluid.linear_drag_coefficient_n_s_m",
            k,
            "drag opposes motion",
        ),
        _ => {}
    }
}

fn time_and_output(c: &mut Checker, s: &Scenario) {
    let t = &s.time;
    c.positive("time.dt_s", t.dt_s, "a time step");
    c.positive("time.duration_s", t.duration_s, "a duration");
    if t.dt_s > 0.0 && t.duration_s > 0.0 {
        if t.dt_s > t.duration_s {
            c.fail(
                "time.dt_s",
                t.dt_s,
                format!("longer than time.duration_s = {} s", t.duration_s),
            );
        } else if t.duration_s / t.dt_s > MAX_STEPS {
            c.fail(
                "time.dt_s",
                t.dt_s,
                format!("{:.0} steps; at most {MAX_STEPS:.0}", t.duration_s / t.dt_s),
            );
        }
    }
    c.count(
        "time.newton_max_iterations",
        t.newton_max_iterations,
        1,
        MAX_NEWTON,
        "Newton iterations per step",
    );
    if let Some(tol) = t.newton_tolerance_n {
        c.positive("time.newton_tolerance_n", tol, "a residual force tolerance");
    }
    if let Some(rel) = t.newton_relative_tolerance {
        c.positive(
            "time.newton_relative_tolerance",
            rel,
            "a relative tolerance",
        );
        if rel >= 1.0 {
            c.fail(
                "time.newton_relative_tolerance",
                rel,
                "must be below 1 (it is a fraction of the first residual)".to_string(),
            );
        }
    }
    if let Some(step) = t.newton_step_tolerance_m {
        c.positive("time.newton_step_tolerance_m", step, "a step tolerance");
    }
    adaptive(c, s);
    let o = &s.output;
    if o.frame_interval_s <= 0.0 {
        c.positive(
            "output.frame_interval_s",
            o.frame_interval_s,
            "a time interval",
        );
    } else if o.frame_interval_s < t.dt_s {
        c.fail(
            "output.frame_interval_s",
            o.frame_interval_s,
            format!(
                "frames are written at steps, so it must be at least time.dt_s = {} s",
                t.dt_s
            ),
        );
    }
    if let Some(x) = o.snapshots_s.iter().find(|x| **x < 0.0) {
        c.fail(
            "output.snapshots_s",
            x,
            format!(
                "snapshot times must not be negative (times after time.duration_s = {} s are skipped)",
                t.duration_s
            ),
        );
    }
}

/// The error-control keys: only with `time.adaptive = true` (the loader then fills the
/// absent ones), positive, and `dt_min_s ≤ dt_s ≤ dt_max_s ≤ output.frame_interval_s`.
fn adaptive(c: &mut Checker, s: &Scenario) {
    let t = &s.time;
    let keys = [
        ("time.error_tolerance_m", t.error_tolerance_m),
        ("time.dt_min_s", t.dt_min_s),
        ("time.dt_max_s", t.dt_max_s),
    ];
    if !t.adaptive {
        for (key, value) in keys {
            if let Some(v) = value {
                c.fail(
                    key,
                    v,
                    "only used with `time.adaptive = true` (an error-controlled step); set \
                     that, or remove this key (a fixed step uses time.dt_s)",
                );
            }
        }
        return;
    }
    let (Some(tol), Some(lo), Some(hi)) = (t.error_tolerance_m, t.dt_min_s, t.dt_max_s) else {
        return; // filled by the loader; a hand-built struct gets the defaults at run time
    };
    c.positive("time.error_tolerance_m", tol, "a position error per step");
    c.positive("time.dt_min_s", lo, "a time step");
    c.positive("time.dt_max_s", hi, "a time step");
    if t.dt_s <= 0.0 {
        return; // reported on time.dt_s
    }
    if lo > t.dt_s {
        c.fail(
            "time.dt_min_s",
            lo,
            format!(
                "the smallest step must not exceed the first step time.dt_s = {} s",
                t.dt_s
            ),
        );
    }
    if hi > 0.0 && hi < t.dt_s {
        c.fail(
            "time.dt_max_s",
            hi,
            format!(
                "the largest step must not be below the first step time.dt_s = {} s",
                t.dt_s
            ),
        );
    }
    let frame = s.output.frame_interval_s;
    if frame > 0.0 && hi > frame {
        c.fail(
            "time.dt_max_s",
            hi,
            format!(
                "steps end on every frame time, so no step is longer than \
                 output.frame_interval_s = {frame} s"
            ),
        );
    }
}
