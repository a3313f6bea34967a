//! `chute bench --elements`: the cost of one element of each shell law. Every
//! membrane (edge springs, constant-strain triangles, the fabric law with and without
//! compression) and bending law (hinges, mid-edge) of the `shell-1k` mesh is evaluated alone,
//! force and Jacobian (and force only, what modified Newton's residuals cost), at one fixed
//! deformed configuration, on one thread (so the per-element
//! figures do not depend on which families are large enough for the parallel loop), in
//! `ROUNDS` (3) rounds over all the laws (each law's time its fastest round), and reported per
//! element and relative to the report's laws (springs, hinges).

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::app::AppError;

/// One law's cost.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ElementCost {
    /// Law (`springs`, `cst`, `fabric`, `fabric-nc`, `hinge`, `midedge`).
    pub law: String,
    /// `membrane` or `bending`.
    pub kind: String,
    /// Elements of the family (edges, faces or hinges).
    pub elements: usize,
    /// Wall time of one evaluation with the Jacobian, per element (ns).
    pub ns_per_element: f64,
    /// Wall time of one evaluation of the whole family (µs).
    pub us_per_family: f64,
    /// Wall time of one evaluation of the force alone (no Jacobian), per element (ns): what
    /// each residual of modified Newton costs.
    pub force_ns_per_element: f64,
    /// `force_ns_per_element` over the report's law of the same kind.
    pub ratio_force_per_element: f64,
    /// `ns_per_element` over the report's law of the same kind (springs or hinges).
    pub ratio_per_element: f64,
    /// `us_per_family` over the report's law of the same kind.
    pub ratio_per_family: f64,
}

/// The laws measured: (name, kind, overrides on top of the `shell-1k` mesh, the force's name).
fn laws() -> Vec<(&'static str, &'static str, Vec<&'static str>, &'static str)> {
    let fabric = super::fabric::fabric_law();
    let mut nc = fabric.clone();
    nc.push("material.no_compression=true");
    let stretch = engine::shell::STRETCH_NAME;
    vec![
        ("springs", "membrane", vec![], stretch),
        ("cst", "membrane", vec!["shell.membrane=cst"], stretch),
        ("fabric", "membrane", fabric, stretch),
        ("fabric-nc", "membrane", nc, stretch),
        ("hinge", "bending", vec![], engine::shell::BEND_NAME),
        (
            "midedge",
            "bending",
            vec!["shell.bending=midedge"],
            engine::shell::midedge::NAME,
        ),
    ]
}

/// Rounds over all the laws; each law's time is its fastest round, so that a burst of
/// load on a shared machine does not land on one law only.
const ROUNDS: usize = 3;

/// One law's force and its fixed deformed configuration.
struct Subject {
    law: &'static str,
    kind: &'static str,
    model: engine::Model,
    force: usize,
    q: Vec<f64>,
}

/// Build the model of every law, and the configuration it is evaluated at.
fn subjects() -> Result<Vec<Subject>, AppError> {
    let mut out = Vec::new();
    for (law, kind, ov, force_name) in laws() {
        let c = super::case("elements", "shell", &["canopy.edge_length_m=0.138"], 0, 0);
        let set: Vec<String> = ov.iter().map(|s| s.to_string()).collect();
        let s = super::scenario_of(&c, &set)?;
        let built = crate::build::build(&s)?;
        let force = built
            .model
            .forces
            .iter()
            .position(|f| f.name() == force_name)
            .ok_or_else(|| AppError::RunFailed(format!("{law}: no force `{force_name}`")))?;
        // A fixed deformed configuration: strains ~1e-3 of both signs, some bending.
        let q: Vec<f64> = built
            .state
            .q
            .iter()
            .enumerate()
            .map(|(i, x)| x + 1e-4 * (1.7 * i as f64).sin())
            .collect();
        out.push(Subject {
            law,
            kind,
            model: built.model,
            force,
            q,
        });
    }
    Ok(out)
}

/// Measure every law (see the module docs).
pub fn measure() -> Result<Vec<ElementCost>, AppError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| AppError::RunFailed(format!("thread pool: {e}")))?;
    let subjects = subjects()?;
    // Fastest round of each law, with the Jacobian and force only.
    let mut best = vec![[f64::INFINITY; 2]; subjects.len()];
    for _ in 0..ROUNDS {
        for (s, best) in subjects.iter().zip(best.iter_mut()) {
            for (b, jacobian) in best.iter_mut().zip([true, false]) {
                *b = b.min(pool.install(|| time_one(s, jacobian)));
            }
        }
    }
    let mut out: Vec<ElementCost> = subjects
        .iter()
        .zip(&best)
        .map(|(s, &[per_eval, per_force])| {
            let n = s.model.forces[s.force].n_stencils();
            ElementCost {
                law: s.law.into(),
                kind: s.kind.into(),
                elements: n,
                ns_per_element: 1e9 * per_eval / n as f64,
                us_per_family: 1e6 * per_eval,
                ratio_per_element: 1.0,
                ratio_per_family: 1.0,
                force_ns_per_element: 1e9 * per_force / n as f64,
                ratio_force_per_element: 1.0,
            }
        })
        .collect();
    for i in 0..out.len() {
        let base = out
            .iter()
            .find(|b| b.kind == out[i].kind)
            .cloned()
            .expect("the first law of each kind is the report's");
        out[i].ratio_per_element = out[i].ns_per_element / base.ns_per_element;
        out[i].ratio_per_family = out[i].us_per_family / base.us_per_family;
        out[i].ratio_force_per_element = out[i].force_ns_per_element / base.force_ns_per_element;
    }
    Ok(out)
}

/// Seconds per evaluation of one law's family (with the Jacobian or force only): at least
/// 20 evaluations and 0.1 s, after one warm-up.
fn time_one(s: &Subject, jacobian: bool) -> f64 {
    let f = &s.model.forces[s.force];
    let v = vec![0.0; s.q.len()];
    let input = engine::EvalInput::outside_step(&s.q, &v, 0.0, jacobian);
    let mut blocks = f.new_blocks();
    f.evaluate(&input, &mut blocks);
    let (mut reps, t0) = (0u32, Instant::now());
    while reps < 20 || t0.elapsed().as_secs_f64() < 0.1 {
        f.evaluate(&input, &mut blocks);
        reps += 1;
    }
    t0.elapsed().as_secs_f64() / f64::from(reps)
}

/// The table `chute bench --elements` prints.
pub fn table(costs: &[ElementCost]) -> String {
    let mut s = format!(
        "{:<10} {:<9} {:>8} {:>10} {:>8} {:>10} {:>8} {:>12} {:>8}\n",
        "law",
        "kind",
        "elements",
        "ns/elem",
        "×/elem",
        "µs/family",
        "×/family",
        "force ns/el",
        "×/force"
    );
    for c in costs {
        s += &format!(
            "{:<10} {:<9} {:>8} {:>10.1} {:>8.2} {:>10.1} {:>8.2} {:>12.1} {:>8.2}\n",
            c.law,
            c.kind,
            c.elements,
            c.ns_per_element,
            c.ratio_per_element,
            c.us_per_family,
            c.ratio_per_family,
            c.force_ns_per_element,
            c.ratio_force_per_element
        );
    }
    s += "ns/elem: one evaluation with the Jacobian, per element; µs/family: one evaluation \
          of the whole family; force ns/el: the force alone (no Jacobian), per element; ×: \
          over the report's law of the same kind (springs or hinges)\n";
    s
}
