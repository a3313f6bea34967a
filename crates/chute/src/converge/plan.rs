//! Turning `--vary KEY=V1,V2,…` into ladders of levels and one study of cases: every value
//! checked (a discretisation key, at least two values, strictly monotone, a valid scenario
//! that refines the model), and the representative size h of each level measured on the model
//! actually built.

use std::path::Path;

use crate::app::AppError;
use crate::build::Built;
use crate::scenario::Scenario;
use crate::study::{safe_name, Case, Study};

/// What a varied key refines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// The mesh: h is a length (m).
    Space,
    /// The time step: h = dt (s).
    Time,
    /// The local error tolerance of adaptive steps: h = √tol (m^½). An error-controlled
    /// implicit Euler step is set so that its local error `(h/2)|Δv| ≈ h² |a|/2` meets
    /// `tol`, so its steps, and its first-order global error, scale as √tol.
    Tolerance,
}

impl Axis {
    /// The formal order of the discretisation (used with two levels): the springs-and-hinges
    /// shell and the DER rod converge at second order in h, implicit Euler at first in dt.
    pub fn formal_order(self) -> f64 {
        match self {
            Axis::Space => 2.0,
            Axis::Time | Axis::Tolerance => 1.0,
        }
    }
}

/// The keys `chute converge` can refine, and what they refine.
pub const VARY_KEYS: &[(&str, Axis)] = &[
    ("canopy.edge_length_m", Axis::Space),
    ("canopy.nodes", Axis::Space),
    ("time.dt_s", Axis::Time),
    ("time.error_tolerance_m", Axis::Tolerance),
];

/// The solver-resolution inputs of one level (docs/convergence.md §Round-off).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Resolution {
    /// Absolute Newton tolerance on ‖R‖∞ (N) of the level's solves
    /// (`engine::NewtonOptions::force_tolerance`: `time.newton_tolerance_n`, or
    /// 1e-9 (1 N + Σm a_ref)).
    pub force_tolerance_n: f64,
    /// Free vertical DOFs (each may carry a residual up to the tolerance).
    pub free_z_dofs: usize,
    /// Largest node mass (kg), for the inertia term's round-off floor.
    pub max_node_mass_kg: f64,
    /// Total weight W (N).
    pub weight_n: f64,
    /// Time step (s).
    pub dt_s: f64,
    /// Simulated time (s).
    pub duration_s: f64,
    /// Canopy reference length (m).
    pub reference_length_m: f64,
}

impl Resolution {
    /// ε_F: the weight fraction the converged residuals may leave unbalanced,
    /// N_z (τ + 16 ε m_max |q|/dt²)/W with |q| ≤ |v_t| T + L the distance from the origin.
    pub fn relative_force(&self, speed_mps: f64) -> f64 {
        let q = speed_mps.abs() * self.duration_s + self.reference_length_m;
        let floor = 16.0 * f64::EPSILON * self.max_node_mass_kg * q / (self.dt_s * self.dt_s);
        self.free_z_dofs as f64 * (self.force_tolerance_n + floor) / self.weight_n
    }
}

/// One level of a ladder.
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    /// The value as given on the command line.
    pub text: String,
    /// The value as a number.
    pub value: f64,
    /// The study case that runs it (shared between ladders when the scenario is the same).
    pub case: String,
    /// Representative size h (m, or s for dt).
    pub h: f64,
    /// Nodes of the built model.
    pub nodes: usize,
    /// Solver-resolution inputs.
    pub resolution: Resolution,
}

/// One varied key and its levels, in the order given.
#[derive(Debug, Clone, PartialEq)]
pub struct Ladder {
    /// The scenario key.
    pub key: String,
    /// What it refines.
    pub axis: Axis,
    /// The levels, in the order of the values.
    pub levels: Vec<Level>,
}

/// The ladders and the study that runs their cases.
#[derive(Debug, Clone)]
pub struct Plan {
    /// One per `--vary`.
    pub ladders: Vec<Ladder>,
    /// The cases (deduplicated), named `<last key segment>-<value>`.
    pub study: Study,
}

fn input(msg: impl Into<String>) -> AppError {
    AppError::Input(msg.into())
}

/// Split `KEY=V1,V2,…` and check the count and monotonicity of the values.
pub fn parse_vary(spec: &str) -> Result<(String, Vec<(String, f64)>), AppError> {
    let (key, list) = spec.split_once('=').ok_or_else(|| {
        input(format!(
            "--vary `{spec}`: expected KEY=V1,V2,… (e.g. canopy.edge_length_m=0.25,0.18,0.125)"
        ))
    })?;
    let key = key.trim().to_string();
    let texts: Vec<String> = list
        .split(',')
        .map(|v| v.trim().to_string())
        .filter(|v| !v.is_empty())
        .collect();
    if texts.len() < 2 {
        return Err(input(format!(
            "--vary {key}: needs at least two values to measure convergence, got {} (`{}`)",
            texts.len(),
            list.trim()
        )));
    }
    let mut values = Vec::with_capacity(texts.len());
    for t in texts {
        let v: f64 = t
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| input(format!("--vary {key}: value `{t}` is not a number")))?;
        values.push((t, v));
    }
    let up = values[1].1 > values[0].1;
    for w in values.windows(2) {
        if (w[1].1 > w[0].1) != up || w[1].1 == w[0].1 {
            return Err(input(format!(
                "--vary {key}: value `{}` after `{}`: the values must be strictly increasing or strictly decreasing",
                w[1].0, w[0].0
            )));
        }
    }
    Ok((key, values))
}

/// Representative size of a built model: Celik's h = (A/N)^½ over its triangles (shell), or
/// the mean spacing of its canopy chain, span/(nodes − 1) (rod).
pub fn mesh_size(b: &Built) -> f64 {
    let q = &b.state.q;
    let p = |i: usize| [q[3 * i], q[3 * i + 1], q[3 * i + 2]];
    let sub = |a: [f64; 3], c: [f64; 3]| [a[0] - c[0], a[1] - c[1], a[2] - c[2]];
    if !b.triangles.is_empty() {
        let area: f64 = b
            .triangles
            .iter()
            .map(|t| {
                let (u, v) = (sub(p(t[1]), p(t[0])), sub(p(t[2]), p(t[0])));
                let c = [
                    u[1] * v[2] - u[2] * v[1],
                    u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0],
                ];
                0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
            })
            .sum();
        return (area / b.triangles.len() as f64).sqrt();
    }
    let chain = &b.canopy_nodes;
    let len: f64 = chain
        .windows(2)
        .map(|w| {
            let d = sub(p(w[1]), p(w[0]));
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        })
        .sum();
    len / (chain.len().max(2) - 1) as f64
}

fn resolution(s: &Scenario, b: &Built) -> Resolution {
    let m = &b.model;
    let free_z_dofs = (0..m.layout.n_nodes)
        .filter(|&i| !m.fixed[3 * i + 2])
        .count();
    let max_node_mass_kg = (0..m.layout.n_nodes)
        .map(|i| m.node_mass(i))
        .fold(0.0, f64::max);
    Resolution {
        // The tolerance the run's solves use (one definition: the engine's).
        force_tolerance_n: crate::app::run_config(s, false)
            .newton
            .force_tolerance(m.total_mass()),
        free_z_dofs,
        max_node_mass_kg,
        weight_n: b.total_weight_n,
        dt_s: s.time.dt_s,
        duration_s: s.time.duration_s,
        reference_length_m: b.reference_length_m,
    }
}

/// Build the ladders of `vary` on `scenario` (with the `set` overrides applied to every
/// level) and the study `name` that runs them. Any bad value: an input error naming the key
/// and the value (exit 2).
pub fn plan(
    scenario: &Path,
    name: &str,
    vary: &[String],
    set: &[String],
) -> Result<Plan, AppError> {
    if vary.is_empty() {
        return Err(input(
            "give at least one --vary KEY=V1,V2,… (e.g. --vary canopy.edge_length_m=0.25,0.18,0.125)",
        ));
    }
    let mut study = Study {
        name: safe_name(name),
        description: Some(format!("chute converge {}", scenario.display())),
        file: None,
        content_digest: None,
        // Absolute, as recorded in each level's done.json for `chute collect` from elsewhere.
        base: crate::study::recorded_path(scenario),
        cases: Vec::new(),
        objective: None,
        dispersion: None,
    };
    // Each case's scenario with a common name, to find levels that are the same run.
    let mut seen: Vec<Scenario> = Vec::new();
    let mut ladders: Vec<Ladder> = Vec::new();
    for spec in vary {
        let (key, values) = parse_vary(spec)?;
        if ladders.iter().any(|l| l.key == key) {
            return Err(input(format!("--vary {key} is given twice")));
        }
        let mut levels = Vec::new();
        let mut axis = Axis::Space;
        for (text, value) in values {
            let (s, a) = level_scenario(scenario, set, &key, &text)?;
            axis = a;
            let what = format!("--vary {key}={text}");
            let built = crate::build::build(&s).map_err(|e| input(format!("{what}: {e}")))?;
            let h = match axis {
                Axis::Time => s.time.dt_s,
                Axis::Tolerance => s
                    .adaptive_settings()
                    .map_or(f64::NAN, |a| a.error_tolerance_m.sqrt()),
                Axis::Space => mesh_size(&built),
            };
            let case = match seen.iter().position(|o| *o == s) {
                Some(i) => study.cases[i].name.clone(),
                None => {
                    let short = key.rsplit('.').next().unwrap_or(&key);
                    let name = safe_name(&format!("{short}-{text}"));
                    study.cases.push(Case {
                        index: study.cases.len(),
                        name: name.clone(),
                        set: vec![format!("{key}={text}")],
                    });
                    seen.push(s.clone());
                    name
                }
            };
            levels.push(Level {
                text,
                value,
                case,
                h,
                nodes: built.model.layout.n_nodes,
                resolution: resolution(&s, &built),
            });
        }
        check_refines(&key, &levels)?;
        ladders.push(Ladder { key, axis, levels });
    }
    dedupe_names(&mut study)?;
    Ok(Plan { ladders, study })
}

/// The validated scenario of one level (named `level`, so equal levels compare equal) and
/// what its key refines; errors name the key and the value.
fn level_scenario(
    scenario: &Path,
    set: &[String],
    key: &str,
    text: &str,
) -> Result<(Scenario, Axis), AppError> {
    let what = format!("--vary {key}={text}");
    let mut s_set = set.to_vec();
    s_set.push(format!("{key}={text}"));
    s_set.push("name=level".into());
    let s = Scenario::load(scenario, &s_set).map_err(|e| input(format!("{what}: {e}")))?;
    let axis = VARY_KEYS
        .iter()
        .find(|(k, _)| *k == key)
        .map(|(_, a)| *a)
        .ok_or_else(|| {
            input(format!(
                "--vary {key}: not a discretisation parameter; chute converge refines {}",
                VARY_KEYS
                    .iter()
                    .map(|(k, _)| format!("`{k}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
    if axis == Axis::Time && s.time.adaptive {
        return Err(input(format!(
            "{what}: with time.adaptive = true, time.dt_s is only the first step; a dt ladder needs a fixed step (or vary time.error_tolerance_m)"
        )));
    }
    if axis == Axis::Tolerance && !s.time.adaptive {
        return Err(input(format!(
            "{what}: time.error_tolerance_m sets the steps only with time.adaptive = true; set it (--set time.adaptive=true) or vary time.dt_s"
        )));
    }
    Ok((s, axis))
}

/// The sizes h must change strictly with the values, or the key does not refine this model.
fn check_refines(key: &str, levels: &[Level]) -> Result<(), AppError> {
    for w in levels.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        if (b.h - a.h).abs() <= 1e-12 * a.h.max(b.h) {
            return Err(input(format!(
                "--vary {key}={}: does not refine the model: its representative size h = {:.6} equals that of `{}` (does this model use {key}?)",
                b.text, b.h, a.text
            )));
        }
    }
    let up = levels[1].h > levels[0].h;
    if levels.windows(2).any(|w| (w[1].h > w[0].h) != up) {
        return Err(input(format!(
            "--vary {key}: the values do not give monotone mesh sizes h ({})",
            levels
                .iter()
                .map(|l| format!("{} → {:.4}", l.text, l.h))
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    Ok(())
}

/// Two different values may sanitise to one case name (`1e-3` vs `1e_3` cannot happen, but
/// `0.001` vs `1e-3` are the same scenario and share a case already); refuse real clashes.
fn dedupe_names(study: &mut Study) -> Result<(), AppError> {
    let mut names = std::collections::HashSet::new();
    for c in &study.cases {
        if !names.insert(c.name.clone()) {
            return Err(input(format!(
                "two levels would share the case directory `{}`; write the values differently",
                c.name
            )));
        }
    }
    Ok(())
}
