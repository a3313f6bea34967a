//! Newton converges quadratically on a drag-dominated step, because the drag Jacobians are
//! exact (including ∂n̂/∂x and the projected area); dropping ∂F/∂x of the drag, as a
//! simplified Jacobian would, degrades it to linear convergence. The same holds with the
//! air's added mass, whose Jacobian is all low-rank part (completed factors,
//! Sherman–Morrison–Woodbury): dropping that part degrades it too.
use engine::reference::sheet;

use engine::aero::{AddedMass, Fluid, TriangleDrag};
use engine::force::{EvalInput, Force, JacobianKind, LocalBlocks};
use engine::{ImplicitEuler, Model, NewtonOptions, State};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// `inner` with part of its Jacobian dropped (a "simplified Jacobian"): it declares `kind`
/// and no low-rank part, and writes only the blocks that `kind` has.
struct Simplified<F: Force> {
    inner: F,
    name: &'static str,
    kind: JacobianKind,
}

impl<F: Force> Force for Simplified<F> {
    fn name(&self) -> &str {
        self.name
    }
    fn stencil_size(&self) -> usize {
        self.inner.stencil_size()
    }
    fn stencils(&self) -> &[usize] {
        self.inner.stencils()
    }
    fn jacobian_kind(&self) -> JacobianKind {
        self.kind
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let mut full = self.inner.new_blocks();
        self.inner.evaluate(input, &mut full);
        out.f.copy_from_slice(&full.f);
        if self.kind.dq {
            out.dfdq.copy_from_slice(&full.dfdq);
        }
        if self.kind.dv {
            out.dfdv.copy_from_slice(&full.dfdv);
        }
    }
    fn commit(&mut self, q: &[f64], v: &[f64]) {
        self.inner.commit(q, v);
    }
}

/// Which forces act on the sheet besides its elasticity.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Variant {
    /// Triangle drag, exact.
    Drag,
    /// Triangle drag with its ∂F/∂x dropped.
    DragWithoutDq,
    /// Triangle drag and added mass, exact.
    AddedMass,
    /// Triangle drag and added mass without its low-rank Jacobian.
    AddedMassWithoutJacobian,
}

/// The crumpled, thrown sheet of `engine::reference::sheet` with the forces of `variant`.
fn model(variant: Variant) -> (Model, State) {
    let mut rng = StdRng::seed_from_u64(7);
    let (mut model, state, s) = sheet::thrown_crumpled_sheet(&mut || rng.random_range(-1.0..1.0));
    let air = Fluid::air();
    let drag = TriangleDrag::new(&s.tris, 1.75, 0.5, &air);
    let added = || AddedMass::new(&s.tris, &state.q, &state.v, &air);
    match variant {
        Variant::DragWithoutDq => model.add_force(Simplified {
            inner: drag,
            name: "triangle-drag-without-dq",
            kind: JacobianKind {
                dq: false,
                ..JacobianKind::GENERAL
            },
        }),
        _ => model.add_force(drag),
    };
    match variant {
        Variant::AddedMass => {
            model.add_force(added());
        }
        Variant::AddedMassWithoutJacobian => {
            model.add_force(Simplified {
                inner: added(),
                name: "added-mass-without-jacobian",
                kind: JacobianKind::CONSTANT,
            });
        }
        _ => {}
    }
    (model, state)
}

/// Residual histories of the first `steps` steps at `dt`.
fn histories(variant: Variant, dt: f64, steps: usize) -> Vec<Vec<f64>> {
    let exact = matches!(variant, Variant::Drag | Variant::AddedMass);
    let (mut model, mut state) = model(variant);
    let opts = NewtonOptions {
        force_tol_abs: Some(1e-11),
        force_tol_rel: 0.0,
        max_iterations: 50,
        ..Default::default()
    };
    let mut stepper = ImplicitEuler::new(&model, opts).unwrap();
    (0..steps)
        .map(|_| {
            let ok = stepper.step(&mut model, &mut state, dt).is_ok();
            assert!(ok || !exact, "exact Jacobians must converge");
            stepper.residual_history().to_vec()
        })
        .collect()
}

/// Close to the solution (‖R‖∞ ≤ 1 N, a tenth of the weight) every Newton update must
/// satisfy `r_{k+1} ≤ C r_k²` while `r_{k+1}` is above the round-off floor. Returns the
/// largest `r_{k+1}/r_k²` seen and the number of pairs checked.
fn quadratic_constant(h: &[f64]) -> (f64, usize) {
    const CLOSE: f64 = 1.0;
    // Final residuals sit at 3–6e-12 N (round-off of forces of ~100 N); 1e-10 is 20× above.
    const FLOOR: f64 = 1e-10;
    h.windows(2)
        .filter(|w| w[0] <= CLOSE && w[1] > FLOOR)
        .fold((0.0, 0), |(c, n), w| {
            (f64::max(c, w[1] / (w[0] * w[0])), n + 1)
        })
}

#[test]
fn newton_converges_quadratically_with_exact_drag_jacobians() {
    // C = 10 /N. Newton's bound r_{k+1} ≤ ½ |∂²R| ‖J⁻¹‖² r_k² is loose here; measured C is
    // 0.41–2.2 over these steps. A linearly converging iteration (contraction ρ) has
    // r_{k+1}/r_k² = ρ/r_k, which exceeds 10 /N as soon as r_k < ρ/10: the variant without
    // ∂F/∂x below (ρ ≈ 0.1) fails the same check, so the test discriminates.
    const C: f64 = 10.0;
    for (exact, inexact) in [
        (Variant::Drag, Variant::DragWithoutDq),
        (Variant::AddedMass, Variant::AddedMassWithoutJacobian),
    ] {
        for (step, h) in histories(exact, 0.05, 5).iter().enumerate() {
            let (c, pairs) = quadratic_constant(h);
            eprintln!("{exact:?}, step {step}: C = {c:.2e} over {pairs} pairs");
            assert!(
                pairs >= 1,
                "{exact:?} step {step}: nothing to check in {h:?}"
            );
            assert!(
                c <= C,
                "{exact:?} step {step}: r_(k+1)/r_k² = {c} > {C}: {h:?}"
            );
        }
        let worst = histories(inexact, 0.05, 5)
            .iter()
            .map(|h| quadratic_constant(h).0)
            .fold(0.0, f64::max);
        eprintln!("{inexact:?}: worst C = {worst:.2e}");
        assert!(
            worst > C,
            "negative control {inexact:?} converged quadratically: {worst}"
        );
    }
}

#[test]
fn a_model_with_more_low_rank_terms_than_supported_is_refused() {
    let (mut model, state) = model(Variant::Drag);
    let mut rng = StdRng::seed_from_u64(7);
    let (_, _, s) = sheet::thrown_crumpled_sheet(&mut || rng.random_range(-1.0..1.0));
    // Three terms each (the three axes): one force more than fit.
    let forces = engine::MAX_LOW_RANK / 3 + 1;
    for _ in 0..forces {
        model.add_force(AddedMass::new(&s.tris, &state.q, &state.v, &Fluid::air()));
    }
    match ImplicitEuler::new(&model, NewtonOptions::default()) {
        Err(engine::EngineError::LowRank { rank, max }) => {
            assert_eq!((rank, max), (3 * forces, engine::MAX_LOW_RANK))
        }
        other => panic!("expected EngineError::LowRank, got {:?}", other.err()),
    }
}
