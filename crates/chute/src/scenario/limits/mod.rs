//! Limits on what the keys imply together, checked with the scenario (so by `chute check` and
//! before `run` builds anything): the masses, the total weight, the flat-canopy terminal
//! speed and its Mach number, and the size of the model. A value every key accepts on its own
//! can still make one of these absurd (a weight of 1e308 N, a gravity of 1e300 m/s², 10 000
//! rim sites refining the circle past the triangle limit); the run would then fail at t = 0 or
//! exhaust memory. Each is refused naming the key that made it so (docs/scenarios.md
//! §Derived limits).

mod extent;
mod imported;

use super::derived::sig4;
use super::error::short;
use super::validate::Checker;
use super::{CanopyShape, DragLaw, LoadMode, ModelKind, Scenario, SiteSet, Sites};
use crate::metrics::{MACH_INCOMPRESSIBLE_MAX, SPEED_OF_SOUND_MPS};

/// No derived quantity may exceed this in SI units: the residual and the Jacobian multiply
/// them (squares of speeds, stiffness × displacement, mass / dt²), and every product must stay
/// far inside f64's 1.8e308.
pub const MAX_MAGNITUDE: f64 = 1e100;
/// Most triangles a shell canopy may have (memory and time). Measured peak memory of the
/// first step of a flat imported mesh: 12 kB per triangle with hinge bending (79,202
/// triangles 0.96 GB, 318,402 4.0 GB), 25 kB with mid-edge bending (79,202: 2.0 GB), nearly
/// all of it the sparse factorisation; a model at the limit needs 5–10 GB.
pub const MAX_SHELL_TRIANGLES: f64 = 4.0e5;
/// Most nodes the suspension lines may have together.
pub const MAX_LINE_NODES: f64 = 1.0e6;
/// Largest stiffness-to-inertia ratio `E h²/(ρ l²)` of one element over one step: the
/// Newton matrix is `M/h² + K`, whose condition number grows as this ratio; at 1e13 f64's
/// rounding perturbs its solves by ε κ ≈ 1e-3, which the Krylov-corrected Newton update
/// absorbs (the report's rod runs at 5.5e12 and fails its first step at 5.5e13, with
/// ε κ ≈ 1e-2 and the rounding of its residual on top); near 1e16 they are noise (bundled
/// scenarios: below 2e8).
pub const MAX_STEP_STIFFNESS: f64 = 1e13;
/// Smallest factor on the payload node's lumped mass (`load.mass_scale`): the factor divides
/// that node's stiffness-to-inertia ratio, which for a mesh's elements lies near 1e8, so
/// below 1e-5 it passes [`MAX_STEP_STIFFNESS`]; the node's mass is also formed as
/// `m + (s − 1) m`, which cancels to zero for s below f64's ε.
pub const MIN_MASS_SCALE: f64 = 1e-5;

/// Largest nominal strain a load site's force may impose on the element that carries it,
/// F/(E A) with A the element's cross-section (a shell's `h l`, a rod strip's `w h`, a
/// line's `π r²`): beyond 1 (the element doubled in length) no fabric is still elastic
/// (nylon breaks near 0.3, aramid near 0.04), and the first step's Newton solve, which
/// must stretch the element that far in one step, fails. Bundled scenarios: below 3e-3.
pub const MAX_NOMINAL_STRAIN: f64 = 1.0;

/// One input of a derived quantity: its key, its value and how far that is from a typical
/// one (value / typical), so that the key blamed is the one furthest from the usual.
#[derive(Clone, Copy)]
struct Input {
    key: &'static str,
    value: f64,
    ratio: f64,
}

fn input(key: &'static str, value: f64, typical: f64) -> Input {
    Input {
        key,
        value,
        ratio: value / typical,
    }
}

/// A quantity the keys imply and what it depends on.
struct Derived {
    name: &'static str,
    unit: &'static str,
    value: f64,
    inputs: Vec<Input>,
}

/// Check every derived quantity of `s`.
pub(super) fn check(c: &mut Checker, s: &Scenario) {
    let quantities = derived(s);
    let mut bad = false;
    for q in &quantities {
        if !(q.value.is_finite() && q.value.abs() <= MAX_MAGNITUDE) {
            let reason = format!(
                "makes the {} {} {}, beyond what the solver can compute with (at most {MAX_MAGNITUDE:e} {}); is the value or its unit wrong?",
                q.name,
                sig4(q.value),
                q.unit,
                q.unit
            );
            blame(c, &q.inputs, reason);
            bad = true;
        }
    }
    if s.load.mode == LoadMode::NodeMassScale && s.load.mass_scale < MIN_MASS_SCALE {
        c.fail(
            "load.mass_scale",
            s.load.mass_scale,
            format!("the payload node's mass would be its lumped mass × {}: below {MIN_MASS_SCALE:e} the node is so light that its step's Newton matrix M/dt² + K is too ill-conditioned to solve in f64", sig4(s.load.mass_scale)),
        );
        bad = true;
    }
    if !bad {
        mach(c, s, quantities.iter().find(|q| q.name == TERMINAL_SPEED));
        let strain = format!(
            "above {MAX_NOMINAL_STRAIN} the load would more than double the element's length, beyond any fabric and beyond what the first step can solve; is the value or its unit wrong?"
        );
        refuse_above(c, &load_strains(s), MAX_NOMINAL_STRAIN, &strain);
        let size = format!(
            "above {:e} m no parachute is this large, and far above it the model's coordinates cannot be computed with; is the value or its unit wrong?",
            extent::MAX_EXTENT_M
        );
        refuse_above(c, &extent::largest(s), extent::MAX_EXTENT_M, &size);
        let stiff = format!(
            "above {MAX_STEP_STIFFNESS:e} the step's Newton matrix M/dt² + K is too ill-conditioned to solve in f64 (a mass far too small, a stiffness far too large, or a smaller dt_s)"
        );
        refuse_above(c, &step_stiffness(s), MAX_STEP_STIFFNESS, &stiff);
        refuse_above(c, &imported::step_stiffness(s), MAX_STEP_STIFFNESS, &stiff);
    }
    model_size(c, s);
}

/// Refuse each of `quantities` that is not finite or exceeds `max`, blaming its input
/// furthest from the usual; `why` says what goes wrong above `max`.
fn refuse_above(c: &mut Checker, quantities: &[Derived], max: f64, why: &str) {
    for q in quantities {
        if !(q.value.is_finite() && q.value <= max) {
            let reason = format!("makes the {} {}: {why}", q.name, sig4(q.value));
            blame(c, &q.inputs, reason);
        }
    }
}

const TERMINAL_SPEED: &str = "flat-canopy terminal speed √(2W/(ρ C_D A))";

/// Refuse the input most responsible for a bad quantity: among those set with `--set` (else
/// all), the one furthest (in orders of magnitude) from its typical value.
fn blame(c: &mut Checker, inputs: &[Input], reason: String) {
    let set: Vec<&Input> = inputs
        .iter()
        .filter(|i| matches!(c.prov.origin(i.key), super::error::Origin::Set(_)))
        .collect();
    let pool: Vec<&Input> = if set.is_empty() {
        inputs.iter().collect()
    } else {
        set
    };
    let far = |i: &Input| {
        let r = i.ratio.abs();
        if r.is_finite() && r > 0.0 {
            r.ln().abs()
        } else {
            f64::INFINITY
        }
    };
    let worst = pool.into_iter().max_by(|a, b| far(a).total_cmp(&far(b)));
    if let Some(i) = worst {
        c.fail(i.key, i.value, reason);
    }
}

/// The planform area (m²) of a generated canopy and the keys it comes from.
fn area(s: &Scenario) -> Option<(f64, Vec<Input>)> {
    let cn = &s.canopy;
    let a = s.planform_area_m2()?;
    let keys = match (s.model.kind, cn.shape) {
        (ModelKind::Rod, _) | (_, CanopyShape::Rectangle) => vec![
            input("canopy.span_m", cn.span_m, 6.0),
            input("canopy.width_m", cn.width_m, 3.0),
        ],
        _ => vec![input("canopy.radius_m", cn.radius_m, 1.5)],
    };
    Some((a, keys))
}

/// The masses of `s` (canopy, lines) as quantities, their sum (kg) and the keys they come
/// from.
fn masses(s: &Scenario) -> (Vec<Derived>, f64, Vec<Input>) {
    let (mut out, mut total, mut inputs) = (Vec::new(), 0.0, Vec::new());
    if let Some((a, mut keys)) = area(s) {
        keys.push(input("canopy.thickness_m", s.canopy.thickness_m, 1e-3));
        keys.push(input(
            "material.density_kg_m3",
            s.material.density_kg_m3,
            1000.0,
        ));
        let m = a * s.canopy.thickness_m * s.material.density_kg_m3;
        out.push(Derived {
            name: "canopy mass",
            unit: "kg",
            value: m,
            inputs: keys.clone(),
        });
        total += m;
        inputs.extend(keys);
    }
    if let (LoadMode::Payload, Some(n)) = (s.load.mode, s.site_count()) {
        let l = &s.lines;
        let keys = vec![
            input("lines.length_m", l.length_m, 3.0),
            input("lines.radius_m", l.radius_m, 1e-3),
            input("lines.density_kg_m3", l.density_kg_m3, 1000.0),
        ];
        let m = n as f64 * l.length_m * std::f64::consts::PI * l.radius_m.powi(2) * l.density_kg_m3;
        out.push(Derived {
            name: "suspension lines' mass",
            unit: "kg",
            value: m,
            inputs: keys.clone(),
        });
        total += m;
        inputs.extend(keys);
    }
    (out, total, inputs)
}

/// The stiffness-to-inertia ratios `E h²/(ρ l²)` of the canopy's and the lines' elements over
/// one step `h` of length `l` (an imported mesh's edge length is not known here).
fn step_stiffness(s: &Scenario) -> Vec<Derived> {
    let dt = input("time.dt_s", s.time.dt_s, 1e-3);
    let mut out = Vec::new();
    let (cn, m) = (&s.canopy, &s.material);
    let edge = match s.model.kind {
        ModelKind::Rod => Some((
            cn.span_m / (cn.nodes.max(2) - 1) as f64,
            vec![
                input("canopy.nodes", cn.nodes as f64, 61.0),
                input("canopy.span_m", cn.span_m, 6.0),
            ],
        )),
        ModelKind::Shell if cn.mesh_file.is_none() => Some((
            cn.edge_length_m,
            vec![input("canopy.edge_length_m", cn.edge_length_m, 0.125)],
        )),
        ModelKind::Shell => None,
    };
    if let Some((len, l)) = edge {
        out.push(Derived {
            name: "canopy element's stiffness-to-inertia ratio over a step E dt²/(ρ l²)",
            unit: "",
            value: m.youngs_modulus_pa * s.time.dt_s.powi(2) / (m.density_kg_m3 * len * len),
            inputs: [
                vec![
                    input("material.youngs_modulus_pa", m.youngs_modulus_pa, 1e9),
                    input("material.density_kg_m3", m.density_kg_m3, 1000.0),
                    dt,
                ],
                l,
            ]
            .concat(),
        });
    }
    if let (LoadMode::Payload, Some(_)) = (s.load.mode, s.site_count()) {
        let ln = &s.lines;
        let seg = ln.length_m / ln.segments.max(1) as f64;
        out.push(Derived {
            name: "line segment's stiffness-to-inertia ratio over a step E dt²/(ρ l²)",
            unit: "",
            value: ln.youngs_modulus_pa * s.time.dt_s.powi(2) / (ln.density_kg_m3 * seg * seg),
            inputs: vec![
                input("lines.youngs_modulus_pa", ln.youngs_modulus_pa, 1e9),
                input("lines.density_kg_m3", ln.density_kg_m3, 1000.0),
                dt,
                input("lines.segments", ln.segments as f64, 10.0),
                input("lines.length_m", ln.length_m, 3.0),
            ],
        });
    }
    out
}

/// The nominal strains F/(E A) a load site's force imposes on the canopy element and the
/// line that carry it (none for a load carried by a node's mass, or an imported mesh whose
/// element size is not known here).
fn load_strains(s: &Scenario) -> Vec<Derived> {
    let (Some(n), LoadMode::Payload | LoadMode::Force | LoadMode::Mass) =
        (s.site_count(), s.load.mode)
    else {
        return Vec::new();
    };
    let force = s.load.weight_n / n.max(1) as f64;
    let (cn, m, ln) = (&s.canopy, &s.material, &s.lines);
    let w = input("load.weight_n", s.load.weight_n, 200.0);
    let e = input("material.youngs_modulus_pa", m.youngs_modulus_pa, 1e9);
    let h = input("canopy.thickness_m", cn.thickness_m, 1e-3);
    let canopy = match (s.model.kind, &cn.mesh_file) {
        (ModelKind::Rod, _) => Some((
            "nominal strain F/(E w h) of the strip at a load site",
            cn.width_m,
            input("canopy.width_m", cn.width_m, 3.0),
        )),
        (ModelKind::Shell, None) => Some((
            "nominal strain F/(E h l) of the canopy element at a load site",
            cn.edge_length_m,
            input("canopy.edge_length_m", cn.edge_length_m, 0.125),
        )),
        (ModelKind::Shell, Some(_)) => None,
    };
    let mut out: Vec<Derived> = canopy
        .into_iter()
        .map(|(name, width, key)| Derived {
            name,
            unit: "",
            value: force / (m.youngs_modulus_pa * cn.thickness_m * width),
            inputs: vec![w, e, h, key],
        })
        .collect();
    if s.load.mode == LoadMode::Payload {
        let area = std::f64::consts::PI * ln.radius_m * ln.radius_m;
        out.push(Derived {
            name: "nominal strain F/(E π r²) of a suspension line",
            unit: "",
            value: force / (ln.youngs_modulus_pa * area),
            inputs: vec![
                w,
                input("lines.youngs_modulus_pa", ln.youngs_modulus_pa, 1e9),
                input("lines.radius_m", ln.radius_m, 1e-3),
            ],
        });
    }
    out
}

/// The quantities of `s` that must be finite and bounded.
fn derived(s: &Scenario) -> Vec<Derived> {
    let (mut out, mass, mass_keys) = masses(s);
    out.push(stiffness(s));
    // What an imported mesh's unknown area leaves out of the masses and the weight: the
    // factors themselves, each of which the residual multiplies.
    let m = &s.material;
    let mut factors = vec![Derived {
        name: "canopy's mass per area ρ h",
        unit: "kg/m²",
        value: m.density_kg_m3 * s.canopy.thickness_m,
        inputs: vec![
            input("material.density_kg_m3", m.density_kg_m3, 1000.0),
            input("canopy.thickness_m", s.canopy.thickness_m, 1e-3),
        ],
    }];
    factors.push(Derived {
        name: "gravitational acceleration",
        unit: "m/s²",
        value: s.fluid.gravity_mps2,
        inputs: vec![input("fluid.gravity_mps2", s.fluid.gravity_mps2, 9.81)],
    });
    if s.load.mode == LoadMode::NodeMassScale {
        factors.push(Derived {
            name: "payload node's mass factor",
            unit: "",
            value: s.load.mass_scale,
            inputs: vec![input("load.mass_scale", s.load.mass_scale, 100.0)],
        });
        out.extend(factors);
        out.extend(imported::descent(s));
        return out;
    }
    let g = input("fluid.gravity_mps2", s.fluid.gravity_mps2, 9.81);
    let mut keys = vec![input("load.weight_n", s.load.weight_n, 200.0), g];
    keys.extend(mass_keys);
    let weight = s.load.weight_n + mass * s.fluid.gravity_mps2;
    out.push(Derived {
        name: "total weight",
        unit: "N",
        value: weight,
        inputs: keys.clone(),
    });
    if let (DragLaw::Quadratic, Some((a, area_keys))) = (s.fluid.drag, area(s)) {
        let (rho, air) = air_density(s);
        let cd = input("fluid.drag_coefficient", s.fluid.drag_coefficient, 1.0);
        let mut drag_keys = area_keys.clone();
        drag_keys.extend([air, cd]);
        out.push(Derived {
            name: "flat canopy's drag at 1 m/s ½ ρ C_D A",
            unit: "N",
            value: 0.5 * rho * s.fluid.drag_coefficient * a,
            inputs: drag_keys,
        });
        keys.extend(area_keys);
        keys.extend([air, cd]);
        out.push(Derived {
            name: TERMINAL_SPEED,
            unit: "m/s",
            value: (2.0 * weight / (rho * s.fluid.drag_coefficient * a)).sqrt(),
            inputs: keys,
        });
    }
    // After the masses and the weight, which say more when they are known.
    out.extend(factors);
    out
}

/// The canopy's axial stiffness: E h (N/m) for a shell, E w h (N) for a rod strip.
fn stiffness(s: &Scenario) -> Derived {
    let (cn, m) = (&s.canopy, &s.material);
    let mut inputs = vec![
        input("material.youngs_modulus_pa", m.youngs_modulus_pa, 1e9),
        input("canopy.thickness_m", cn.thickness_m, 1e-3),
    ];
    let (name, unit, value) = match s.model.kind {
        ModelKind::Rod => {
            inputs.push(input("canopy.width_m", cn.width_m, 3.0));
            (
                "strip's axial stiffness E w h",
                "N",
                m.youngs_modulus_pa * cn.width_m * cn.thickness_m,
            )
        }
        ModelKind::Shell => (
            "membrane stiffness E h",
            "N/m",
            m.youngs_modulus_pa * cn.thickness_m,
        ),
    };
    Derived {
        name,
        unit,
        value,
        inputs,
    }
}

/// The speeds of the canopy through the air that the scenario implies: the wind's at the
/// start (the canopy starts at rest over the ground) and the flat-canopy terminal speed
/// (quadratic drag of a generated canopy), both in m/s.
pub fn air_speeds(s: &Scenario) -> (f64, Option<f64>) {
    let w = s.fluid.wind_mps;
    let wind = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    let terminal = derived(s)
        .into_iter()
        .find(|q| q.name == TERMINAL_SPEED)
        .map(|q| q.value);
    (wind, terminal)
}

/// The warning for a scenario whose canopy moves through the air faster than Mach
/// [`MACH_INCOMPRESSIBLE_MAX`] (below Mach 1, which `check` refuses).
pub fn mach_warning(s: &Scenario) -> Option<String> {
    let (wind, terminal) = air_speeds(s);
    let mach = |v: f64| v / SPEED_OF_SOUND_MPS;
    let high = |v: f64| mach(v) > MACH_INCOMPRESSIBLE_MAX && mach(v) < 1.0;
    let what = match terminal {
        Some(v) if v > wind && high(v) => format!(
            "the flat-canopy terminal speed is {} m/s, Mach {} through the air",
            sig4(v),
            sig4(mach(v))
        ),
        _ if high(wind) => format!(
            "the canopy starts at rest in a {} m/s wind: it moves through the air at Mach {}",
            sig4(wind),
            sig4(mach(wind))
        ),
        _ => return None,
    };
    Some(format!(
        "{what} (speed of sound {SPEED_OF_SOUND_MPS} m/s); above Mach {MACH_INCOMPRESSIBLE_MAX} air is compressible and the drag laws do not hold"
    ))
}

/// The air density at the start (kg/m³) and the input it comes from: the constant density,
/// or the altitude of the standard atmosphere (as far from the usual as its density).
fn air_density(s: &Scenario) -> (f64, Input) {
    const SEA_LEVEL: f64 = 1.225;
    match s.atmosphere.model {
        super::AtmosphereModel::Constant => {
            let rho = s.fluid.density_kg_m3;
            (rho, input("fluid.density_kg_m3", rho, SEA_LEVEL))
        }
        super::AtmosphereModel::Isa1976 => {
            let h = s.atmosphere.altitude_m;
            let rho = engine::aero::atmosphere::isa1976(h).density_kg_m3;
            let air = Input {
                key: "atmosphere.altitude_m",
                value: h,
                ratio: rho / SEA_LEVEL,
            };
            (rho, air)
        }
    }
}

/// The canopy moves through the air at the wind's speed at the start (it starts at rest over
/// the ground) and at about the flat-canopy terminal speed at the end: at Mach 1 or more the
/// incompressible drag laws do not hold at all.
fn mach(c: &mut Checker, s: &Scenario, terminal: Option<&Derived>) {
    let w = s.fluid.wind_mps;
    let wind = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    if !(wind.is_finite() && wind < SPEED_OF_SOUND_MPS) {
        let shown = format!("[{}, {}, {}]", short(w[0]), short(w[1]), short(w[2]));
        c.fail(
            "fluid.wind_mps",
            shown,
            if wind.is_finite() {
                format!(
                    "the canopy starts at rest in a {} m/s wind, Mach {} through the air (speed of sound {SPEED_OF_SOUND_MPS} m/s): the drag laws hold only well below Mach 1",
                    sig4(wind),
                    sig4(wind / SPEED_OF_SOUND_MPS)
                )
            } else {
                "the wind's speed is not a finite number (its square overflows): the drag laws hold only well below Mach 1".into()
            },
        );
        return;
    }
    if let Some(t) = terminal.filter(|t| t.value >= SPEED_OF_SOUND_MPS) {
        let reason = format!(
            "makes the {} {} m/s, Mach {} (speed of sound {SPEED_OF_SOUND_MPS} m/s): the drag laws hold only well below Mach 1",
            t.name,
            sig4(t.value),
            sig4(t.value / SPEED_OF_SOUND_MPS)
        );
        blame(c, &t.inputs, reason);
    }
}

/// The triangles a circle gets when its rim must hold the rim sites, and the line nodes.
fn model_size(c: &mut Checker, s: &Scenario) {
    let cn = &s.canopy;
    let rim = matches!(s.load.sites, Sites::Named(SiteSet::Rim));
    if s.model.kind == ModelKind::Shell
        && cn.shape == CanopyShape::Circle
        && rim
        && cn.radius_m > 0.0
        && cn.edge_length_m > 0.0
    {
        let plain = crate::mesh::generate::circle_rings(cn.radius_m, cn.edge_length_m, 1);
        let n = crate::mesh::generate::circle_rings(
            cn.radius_m,
            cn.edge_length_m,
            s.load.rim_site_count,
        );
        let triangles = 6.0 * (n as f64).powi(2);
        if triangles > MAX_SHELL_TRIANGLES && n > plain {
            c.fail(
                "load.rim_site_count",
                s.load.rim_site_count,
                format!(
                    "the rim must hold a node at every site, which refines the circle to {n} rings, {} triangles; at most {MAX_SHELL_TRIANGLES:.0} are allowed (a count that divides the rim's {} nodes keeps the mesh as it is)",
                    sig4(triangles),
                    6 * plain
                ),
            );
        }
    }
    if let (LoadMode::Payload, Some(n)) = (s.load.mode, s.site_count()) {
        let nodes = n as f64 * s.lines.segments as f64;
        if nodes > MAX_LINE_NODES {
            c.fail(
                "lines.segments",
                s.lines.segments,
                format!(
                    "{n} lines of {} segments are {} line nodes; at most {MAX_LINE_NODES:e} are allowed",
                    s.lines.segments,
                    sig4(nodes)
                ),
            );
        }
    }
}
