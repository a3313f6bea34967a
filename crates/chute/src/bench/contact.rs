//! `chute bench --contact`: what self-contact costs, and how it grows with the mesh. The
//! bundled `opening` scenario at three meshes is stepped through its opening to the peak
//! force (where the cloth is folded and the most pairs are near), and there each part of the
//! contact is timed alone, on the pool (`ROUNDS` rounds, each part its fastest): the
//! barrier's evaluation with its Jacobian against every other force's, the broad phase that
//! takes the pairs, the CCD bound of one update, and the rebuild of the sparsity pattern with
//! its symbolic factorisation that a change of pairs costs.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::app::AppError;
use engine::contact::broad::candidates;
use engine::force::EvalInput;

const OPENING: &str = include_str!("../../../../scenarios/opening.toml");
const OPENING_PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/opening.toml");

/// Rounds of each measurement (each part's time is its fastest round).
const ROUNDS: usize = 5;
/// The meshes measured (`canopy.edge_length_m`).
const MESHES: [f64; 3] = [0.25, 0.18, 0.125];
/// The opening is stepped to its peak force, about 35 ms after line stretch at 25 m/s.
const STEP_TO_S: f64 = 0.035;

/// What contact costs on one mesh.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ContactCost {
    /// `canopy.edge_length_m` (m).
    pub edge_length_m: f64,
    /// Nodes of the model.
    pub nodes: usize,
    /// Pairs held by the contact force (the pattern's contact stencils).
    pub pairs: usize,
    /// One evaluation of the barrier with its Jacobian (ms).
    pub barrier_ms: f64,
    /// One evaluation with Jacobians of every other force (ms).
    pub other_forces_ms: f64,
    /// The broad phase that takes the pairs (ms).
    pub broad_phase_ms: f64,
    /// The CCD bound of one update (ms).
    pub ccd_ms: f64,
    /// A rebuild of the stepper: pattern, ordering and symbolic factorisation (ms).
    pub rebuild_ms: f64,
}

fn fastest(mut f: impl FnMut()) -> f64 {
    (0..ROUNDS)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64() * 1e3
        })
        .fold(f64::INFINITY, f64::min)
}

/// Measure every mesh (0.25, 0.18 and 0.125 m).
pub fn measure() -> Result<Vec<ContactCost>, AppError> {
    MESHES.iter().map(|&h| measure_one(h)).collect()
}

fn measure_one(h: f64) -> Result<ContactCost, AppError> {
    let set = [format!("canopy.edge_length_m={h}")];
    let s = crate::scenario::Scenario::from_str_with_name(OPENING, OPENING_PATH, &set)?;
    let mut b = crate::build::build(&s).map_err(|e| AppError::Input(e.to_string()))?;
    let cfg = crate::resolve::run_config(&s, false);
    let fail = |e: String| AppError::RunFailed(format!("bench --contact: {e}"));
    let mut stepper =
        crate::runner::new_stepper(&b.model, &cfg).map_err(|e| fail(e.to_string()))?;
    // As a run steps (a failed solve halved); the measurement needs only the state.
    crate::runner::Driver::new(&cfg)
        .map_err(|e| fail(e.to_string()))?
        .advance_to(&mut stepper, &mut b, STEP_TO_S)
        .map_err(|e| fail(e.to_string()))?;
    let dt = cfg.stepping.dt_s;
    let (q, v) = (b.state.q.clone(), b.state.v.clone());
    let input = EvalInput {
        q: &q,
        v: &v,
        t: b.state.t,
        dt,
        jacobian: true,
    };
    let contact = (b.model.forces.iter())
        .position(|f| f.name() == "contact")
        .expect("the opening has contact");
    let mut blocks: Vec<_> = b.model.forces.iter().map(|f| f.new_blocks()).collect();
    let mut times = vec![0.0; blocks.len()];
    for (i, (f, out)) in b.model.forces.iter().zip(&mut blocks).enumerate() {
        times[i] = fastest(|| f.evaluate(&input, out));
    }
    let surface = b.contact.as_ref().expect("contact surface");
    let force = &b.model.forces[contact];
    // The reach a retake uses when the step's motion is small (docs/opening.md §Contact).
    let distance = crate::resolve::ModelSpec::of(&s)
        .contact
        .expect("the opening has contact")
        .0;
    let reach = engine::contact::force::HYSTERESIS * distance;
    let dq: Vec<f64> = v.iter().map(|x| x * dt).collect();
    Ok(ContactCost {
        edge_length_m: h,
        nodes: b.model.layout.n_nodes,
        pairs: force.n_stencils(),
        barrier_ms: times[contact],
        other_forces_ms: times.iter().sum::<f64>() - times[contact],
        broad_phase_ms: fastest(|| drop(candidates(surface, &q, reach))),
        ccd_ms: fastest(|| {
            std::hint::black_box(force.max_step(&q, &dq, engine::stepper::ITERATE_GAP));
        }),
        rebuild_ms: fastest(|| drop(crate::runner::new_stepper(&b.model, &cfg))),
    })
}

/// The costs as a Markdown table.
pub fn table(rows: &[ContactCost]) -> String {
    let mut out = String::from(
        "| edge (m) | nodes | pairs | barrier (ms) | other forces (ms) | barrier share | broad phase (ms) | CCD (ms) | rebuild (ms) |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let share = r.barrier_ms / (r.barrier_ms + r.other_forces_ms);
        out.push_str(&format!(
            "| {} | {} | {} | {:.3} | {:.3} | {:.0} % | {:.3} | {:.3} | {:.2} |\n",
            r.edge_length_m,
            r.nodes,
            r.pairs,
            r.barrier_ms,
            r.other_forces_ms,
            100.0 * share,
            r.broad_phase_ms,
            r.ccd_ms,
            r.rebuild_ms
        ));
    }
    out
}
