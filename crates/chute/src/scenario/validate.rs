//! Validation of a typed scenario: first the rules declared with each key in
//! [`super::sections`] (ranges, "only with", "required with"), checked generically on the
//! resolved tree, then the cross-key consistency rules written out here. Each rule says *why*
//! a value is refused; the first violation in reading order is reported.

use super::error::Origin;
use super::error::{short, ScenarioError};
use super::sections::SECTIONS;
use super::source::Provenance;
use super::{AtmosphereModel, CanopyShape, DragLaw, LoadMode, ModelKind, Scenario, Sites};

/// Upper bounds that keep a typo (an extra zero or three) from exhausting memory or time.
use super::limits::MAX_SHELL_TRIANGLES;
pub(super) const MAX_STEPS: f64 = 1.0e8;
const MAX_SITES: usize = 10_000;

/// The problems found so far, each with its place in reading order.
pub(super) struct Checker<'a> {
    pub(super) prov: &'a Provenance,
    errors: Vec<((u8, usize, usize), ScenarioError)>,
}

impl<'a> Checker<'a> {
    pub(super) fn new(prov: &'a Provenance) -> Self {
        Self {
            prov,
            errors: Vec::new(),
        }
    }

    /// The first problem in reading order.
    pub(super) fn first(mut self) -> Result<(), ScenarioError> {
        self.errors.sort_by_key(|(rank, _)| *rank);
        match self.errors.into_iter().next() {
            Some((_, e)) => Err(e),
            None => Ok(()),
        }
    }

    /// Record `e`, ranked where `rank_key` was written.
    pub(super) fn push(&mut self, rank_key: &str, e: ScenarioError) {
        self.errors.push((self.prov.rank(rank_key), e));
    }

    pub(super) fn fail(&mut self, key: &str, value: impl ToString, reason: impl Into<String>) {
        // Numbers in short form (1e308, not 309 digits).
        let value = value.to_string();
        let value = match value.parse::<f64>() {
            Ok(x) if x.is_finite() => short(x),
            _ => value,
        };
        let e = ScenarioError::Invalid {
            key: key.to_string(),
            value,
            reason: reason.into(),
            origin: self.prov.origin(key),
        };
        self.push(key, e);
    }

    /// Of two keys whose values conflict, the one [`Self::changed`] blames, with its value.
    fn blame<'k>(&self, pair: [(&'k str, f64); 2]) -> (&'k str, f64) {
        let key = self.changed(&[pair[0].0, pair[1].0]);
        pair.into_iter().find(|p| p.0 == key).unwrap_or(pair[0])
    }

    /// The key a cross-key rule blames: the first of `keys` the user changed with `--set`,
    /// else the first (the key the rule is about).
    fn changed<'k>(&self, keys: &[&'k str]) -> &'k str {
        keys.iter()
            .copied()
            .find(|k| matches!(self.prov.origin(k), super::error::Origin::Set(_)))
            .unwrap_or(keys[0])
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
        self.push(key, e);
    }
}

/// Check every declared rule and cross-key rule; `Ok` means the builders can use `s`.
pub fn validate(s: &Scenario, prov: &Provenance) -> Result<(), ScenarioError> {
    let mut c = Checker::new(prov);
    // The declared rules read the resolved tree, exactly what `to_toml` writes.
    let tree = toml::Table::try_from(s).map_err(|e| ScenarioError::Syntax {
        file: prov.file.clone(),
        line: 1,
        col: 1,
        message: format!("cannot represent the scenario as TOML: {e}"),
    })?;
    super::rules::declared(&mut c, SECTIONS, &tree);
    name(&mut c, &s.name);
    canopy(&mut c, s);
    load(&mut c, s);
    permeability(&mut c, s);
    super::incidence::check(&mut c, s);
    super::wind::check(&mut c, s);
    super::round::check(&mut c, s);
    super::opening::check(&mut c, s);
    atmosphere(&mut c, s);
    time_and_output(&mut c, s);
    super::control::check(&mut c, s);
    // Derived quantities of keys already out of their own range would blame a key the user
    // did not change (a huge `rim_site_count` showing up as a terminal speed of the
    // thickness): the limits judge only a scenario whose keys are each valid.
    if c.errors.is_empty() {
        super::limits::check(&mut c, s);
    }
    c.first()
}

/// The loader's warnings about keys the scenario sets but the model does not use: with
/// `atmosphere.model = "isa1976"`, `fluid.density_kg_m3` and `fluid.viscosity_pa_s` (one
/// warning for both, so that a sea-level scenario flown at altitude with one `--set` says it
/// once).
pub fn notes(s: &Scenario, prov: &Provenance) -> Vec<String> {
    let mut out = Vec::new();
    if s.atmosphere.model == AtmosphereModel::Isa1976 {
        let set: Vec<String> = ["fluid.density_kg_m3", "fluid.viscosity_pa_s"]
            .into_iter()
            .filter(|k| prov.origin(k) != Origin::Default)
            .map(|k| format!("{k} ({})", prov.origin(k)))
            .collect();
        if !set.is_empty() {
            out.push(format!(
                "{} ignored: atmosphere.model = \"isa1976\" takes the density and viscosity of \
                 the 1976 standard atmosphere at each element's altitude \
                 (fluid.density_kg_m3 and fluid.viscosity_pa_s are used only with \"constant\")",
                set.join(" and ")
            ));
        }
    }
    super::incidence::notes(s, prov, &mut out);
    out
}

/// The fabric's permeability: one of the two forms, a Forchheimer term only on top of one,
/// and only with the quadratic laws that split the normal flow (the declared rules make it
/// positive and shell-only).
fn permeability(c: &mut Checker, s: &Scenario) {
    let m = &s.material;
    if let (Some(_), Some(cfm)) = (m.permeability_m2, m.air_permeability_cfm) {
        c.fail(
            "material.air_permeability_cfm",
            cfm,
            "give the fabric's permeability once: material.permeability_m2 is set too",
        );
    }
    let permeable = m.permeability_m2.is_some() || m.air_permeability_cfm.is_some();
    if let (Some(cf), false) = (m.forchheimer_coefficient, permeable) {
        c.fail(
            "material.forchheimer_coefficient",
            cf,
            "only used with a permeable fabric: set material.permeability_m2 or material.air_permeability_cfm",
        );
    }
    if !permeable {
        return;
    }
    let (key, value) = match m.permeability_m2 {
        Some(k) => ("material.permeability_m2", k),
        None => (
            "material.air_permeability_cfm",
            m.air_permeability_cfm.unwrap_or(0.0),
        ),
    };
    if s.fluid.drag == DragLaw::Linear {
        c.fail(
            key,
            value,
            "leakage splits the quadratic drag's normal flow; fluid.drag = \"linear\" has none",
        );
    }
}

/// The ground lies below the start (the declared range keeps both inside the standard
/// atmosphere with `isa1976`).
fn atmosphere(c: &mut Checker, s: &Scenario) {
    let a = &s.atmosphere;
    if let Some(g) = a.ground_altitude_m {
        if g >= a.altitude_m {
            c.fail(
                "atmosphere.ground_altitude_m",
                g,
                format!(
                    "the ground must lie below the start, atmosphere.altitude_m = {} m",
                    a.altitude_m
                ),
            );
        }
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

/// The canopy's smallest in-plane size (m) and the key that sets it.
fn in_plane_size(s: &Scenario) -> Option<(f64, &'static str, f64)> {
    let cn = &s.canopy;
    match (s.model.kind, cn.shape) {
        (ModelKind::Rod, _) | (_, CanopyShape::Rectangle) if cn.width_m < cn.span_m => {
            Some((cn.width_m, "canopy.width_m", cn.width_m))
        }
        (ModelKind::Rod, _) | (_, CanopyShape::Rectangle) => {
            Some((cn.span_m, "canopy.span_m", cn.span_m))
        }
        (_, CanopyShape::Hexagon | CanopyShape::Circle) => {
            Some((2.0 * cn.radius_m, "canopy.radius_m", cn.radius_m))
        }
        (_, CanopyShape::Mesh) => None,
    }
}

fn canopy(c: &mut Checker, s: &Scenario) {
    let cn = &s.canopy;
    if let (true, Some(v)) = (cn.released_with_wind, cn.initial_velocity_mps) {
        c.fail(
            "canopy.released_with_wind",
            "true",
            format!("gives the start velocity, which canopy.initial_velocity_mps = {v:?} gives too: set one"),
        );
    }
    if s.model.kind == ModelKind::Rod && cn.shape != CanopyShape::Rectangle {
        c.choice(
            "canopy.shape",
            cn.shape.name(),
            &["rectangle"],
            "for a rod model (a strip)",
        );
    }
    if let (ModelKind::Rod, Some(p)) = (s.model.kind, cn.mesh_pattern) {
        c.fail(
            "canopy.mesh_pattern",
            format!("\"{}\"", p.name()),
            "only used with `model.kind = \"shell\"` (a rod canopy has no triangles)",
        );
    }
    let sized = in_plane_size(s).filter(|(x, _, _)| *x > 0.0);
    let size = sized.map(|(x, _, _)| x);
    // The in-plane size as the messages print it (they are only printed when there is one).
    let size_text = size.map(short).unwrap_or_default();
    // A length above `fraction` of the in-plane size, blamed on whichever of the two the
    // user set (Checker::blame).
    let mut at_most = |key: &'static str, value: f64, fraction: f64, why: String| {
        if let Some((_, size_key, size_value)) = sized.filter(|(x, _, _)| value > fraction * x) {
            let (key, value) = c.blame([(key, value), (size_key, size_value)]);
            c.fail(key, value, why);
        }
    };
    at_most(
        "canopy.thickness_m",
        cn.thickness_m,
        0.1,
        format!("thin-structure models need a thickness ({} m) below 1/10 of the canopy's in-plane size ({size_text} m); is it in metres?", short(cn.thickness_m)),
    );
    if s.model.kind == ModelKind::Shell && cn.edge_length_m > 0.0 {
        at_most(
            "canopy.edge_length_m",
            cn.edge_length_m,
            0.5,
            format!("the mesh needs at least two edges ({} m each) across the canopy (size {size_text} m)", short(cn.edge_length_m)),
        );
        if let (Some(_), Some(area)) = (sized, s.planform_area_m2()) {
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
    fabric(c, s);
}

/// A fabric's law is positive definite only when `ν₁₂² < E_warp/E_weft`
/// (`Δ = 1 − ν₁₂ν₂₁ > 0`, `ν₂₁ = ν₁₂ E_weft/E_warp`).
fn fabric(c: &mut Checker, s: &Scenario) {
    let m = &s.material;
    let (Some(e1), Some(e2), Some(nu)) =
        (m.warp_modulus_pa, m.weft_modulus_pa, m.fabric_poisson_ratio)
    else {
        return;
    };
    if e1 > 0.0 && e2 > 0.0 && (nu.is_nan() || nu * nu >= e1 / e2) {
        c.fail(
            "material.fabric_poisson_ratio",
            nu,
            format!(
                "the orthotropic law is positive definite only for ν₁₂² < warp_modulus_pa/weft_modulus_pa = {}, i.e. |ν₁₂| < {}",
                e1 / e2,
                (e1 / e2).sqrt()
            ),
        );
        return;
    }
    if let Some(r) = super::wrinkle::estimate(s).filter(|r| r.strain_error > super::wrinkle::REFUSE)
    {
        c.fail(
            "material.wrinkle_strain",
            r.strain,
            r.explain(super::wrinkle::REFUSE),
        );
    }
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

/// The mesh file (required with, and only allowed with, `shape = "mesh"`: declared) must
/// exist and have a format the builder reads.
fn mesh(c: &mut Checker, s: &Scenario) {
    let key = "canopy.mesh_file";
    let (Some(p), CanopyShape::Mesh) = (&s.canopy.mesh_file, s.canopy.shape) else {
        return;
    };
    let ext = p
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if p.is_dir() {
        c.fail(
            key,
            format!("\"{}\"", p.display()),
            "it is a directory; give the mesh file in it (`.txt` DisMech or `.obj` Wavefront)",
        );
    } else if let Some(why) = std::fs::metadata(p)
        .ok()
        .and_then(|m| crate::mesh::too_large(m.len()))
    {
        c.fail(key, format!("\"{}\"", p.display()), &why);
    } else if p.exists() && !p.is_file() {
        c.fail(
            key,
            format!("\"{}\"", p.display()),
            "it is not a plain file (a FIFO, a device?); give the mesh file (`.txt` DisMech or `.obj` Wavefront)",
        );
    } else if !p.is_file() {
        let e = ScenarioError::MeshMissing {
            key: key.into(),
            path: p.clone(),
            origin: c.prov.origin(key),
        };
        c.push(key, e);
    } else if ext != "txt" && ext != "obj" {
        c.fail(
            key,
            format!("\"{}\"", p.display()),
            "the mesh format is chosen by extension: `.txt` (DisMech) or `.obj` (Wavefront)",
        );
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

fn load(c: &mut Checker, s: &Scenario) {
    let l = &s.load;
    if l.mode == LoadMode::NodeMassScale {
        if s.canopy.shape != CanopyShape::Mesh {
            c.choice(
                "load.mode",
                "node_mass_scale",
                &["force", "payload", "mass"],
                "unless `canopy.shape = \"mesh\"`",
            );
        }
        return;
    }
    let (allowed, context) = allowed_sites(s);
    match &l.sites {
        Sites::Named(set) => {
            let n = set.name();
            if !allowed.contains(&n) {
                c.choice("load.sites", n, allowed, context);
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
                    c.push("load.sites", e);
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
    let (shape, _, _) = in_plane_size(s)?;
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

fn time_and_output(c: &mut Checker, s: &Scenario) {
    let t = &s.time;
    let (dt, dur) = ("time.dt_s", "time.duration_s");
    if t.dt_s > 0.0 && t.duration_s > 0.0 {
        let steps = t.duration_s / t.dt_s;
        if t.dt_s > t.duration_s {
            match c.changed(&[dt, dur]) {
                k if k == dur => c.fail(
                    dur,
                    t.duration_s,
                    format!("shorter than one step, time.dt_s = {} s", short(t.dt_s)),
                ),
                _ => c.fail(
                    dt,
                    t.dt_s,
                    format!("longer than time.duration_s = {} s", short(t.duration_s)),
                ),
            }
        } else if steps > MAX_STEPS {
            let (key, value, other) = match c.changed(&[dt, dur]) {
                k if k == dur => (
                    dur,
                    t.duration_s,
                    format!("time.dt_s = {} s", short(t.dt_s)),
                ),
                _ => (
                    dt,
                    t.dt_s,
                    format!("time.duration_s = {} s", short(t.duration_s)),
                ),
            };
            c.fail(
                key,
                value,
                format!(
                    "{} steps with {other}; at most {}",
                    short(steps.ceil()),
                    short(MAX_STEPS)
                ),
            );
        }
    }
    adaptive(c, s);
    let o = &s.output;
    let frame = "output.frame_interval_s";
    if o.frame_interval_s > 0.0 && o.frame_interval_s < t.dt_s {
        match c.changed(&[frame, dt]) {
            k if k == dt => c.fail(
                dt,
                t.dt_s,
                format!(
                    "frames are written at steps, so a step must not be longer than output.frame_interval_s = {} s",
                    short(o.frame_interval_s)
                ),
            ),
            _ => c.fail(
                frame,
                o.frame_interval_s,
                format!(
                    "frames are written at steps, so it must be at least time.dt_s = {} s",
                    short(t.dt_s)
                ),
            ),
        }
    }
}

/// The order of the error-control keys, `dt_min_s ≤ dt_s ≤ dt_max_s ≤
/// output.frame_interval_s` (that they are positive and only written with `time.adaptive =
/// true` is declared with them).
fn adaptive(c: &mut Checker, s: &Scenario) {
    let t = &s.time;
    let (true, Some(lo), Some(hi)) = (t.adaptive, t.dt_min_s, t.dt_max_s) else {
        return; // filled by the loader; a hand-built struct gets the defaults at run time
    };
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
