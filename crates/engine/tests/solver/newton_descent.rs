//! The Newton stage's descent shift (`stage/newton.rs` §Descent) where the step's matrix has
//! an indefinite symmetric part at the solution itself, as a follower load gives: the
//! unshifted Newton update is uphill for the merit but converges, and is taken.

use engine::dof::DofLayout;
use engine::force::{EvalInput, Force, JacobianKind, LocalBlocks};
use engine::{ImplicitEuler, Model, NewtonOptions, State};

/// Mass (kg) and step (s): `c = m/h² = 1e4 N/m`.
const M: f64 = 1.0;
const H: f64 = 0.01;
const C: f64 = M / (H * H);
/// Skew stiffness (N/m), larger than `C` so that `J = C I + K` is invertible.
const B: f64 = 3.0 * C;

/// `F = −K q` on one node with `K = [[−2C, B, 0], [−B, 0, 0], [0, 0, 0]]`: linear, not
/// conservative (K is not symmetric). The step's matrix `J = C I + K` has the symmetric part
/// `diag(−C, C, C)` (indefinite) and the eigenvalues `±i √(B² − C²)` and `C`.
struct Follower;

const K: [[f64; 3]; 3] = [[-2.0 * C, B, 0.0], [-B, 0.0, 0.0], [0.0, 0.0, 0.0]];

impl Force for Follower {
    fn name(&self) -> &str {
        "linear-follower"
    }
    fn stencil_size(&self) -> usize {
        3
    }
    fn stencils(&self) -> &[usize] {
        &[0, 1, 2]
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind {
            dq: true,
            dv: false,
            symmetric: false,
        }
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        for i in 0..3 {
            out.f[i] = -(0..3).map(|j| K[i][j] * input.q[j]).sum::<f64>();
            if input.jacobian {
                for j in 0..3 {
                    out.dfdq[3 * i + j] = -K[i][j];
                }
            }
        }
    }
}

/// From rest at the origin with `v = (1, 0, 0)`: the predictor's residual `R = K q̃ =
/// (−200, −300, 0) N` has `R · J⁻¹ R = C (R₁² − R₂²)/(B² − C²) < 0`, so the Newton update is
/// uphill for the merit. Shifted by the added inertia the iteration creeps (300 → 67 → 35 N,
/// five factorisations before an update descends unshifted); the unshifted update solves
/// the linear step in one iteration (the Krylov correction makes it exact Newton). The
/// result is the exact solution `q = C J⁻¹ q̃`.
#[test]
fn an_uphill_newton_update_that_converges_is_taken_unshifted() {
    let mut model = Model::new(DofLayout::new(1, 0));
    model.mass.iter_mut().for_each(|m| *m = M);
    model.add_force(Follower);
    let mut state = State::at_rest(vec![0.0; 3]);
    state.v[0] = 1.0;
    let c = one_strict_step(&mut model, &mut state, 1e-9);
    assert_eq!((c.factorizations, c.iterations), (1, 1), "{c:?}");
    // q = C J⁻¹ q̃ with q̃ = (H, 0, 0) and J⁻¹ = [[C, −B], [B, −C]] / (B² − C²) on x, y.
    let det = B * B - C * C;
    let exact = [C * C * H / det, C * B * H / det, 0.0];
    for (q, e) in state.q.iter().zip(exact) {
        // The residual's 1e-9 N moves q by at most 1e-9 / (smallest |eigenvalue| of J ~ C).
        assert!(
            (q - e).abs() <= 1e-9 / C * 10.0,
            "{:?} vs {exact:?}",
            state.q
        );
    }
}

/// Depth of the double well (J).
const WELL: f64 = 1.0;
/// Inertia of the angle (kg·m²): negligible, as a mid-edge bending angle's is.
const ANGLE_INERTIA: f64 = 1e-12;

/// `E(ψ) = WELL (ψ² − 1)²` on one angle DOF: wells at `ψ = ±1`, a maximum at 0, not convex
/// for `|ψ| < 1/√3` (as mid-edge bending's energy in its edge angle is in a sharp fold).
struct DoubleWell([usize; 1]);

impl Force for DoubleWell {
    fn name(&self) -> &str {
        "double-well"
    }
    fn stencil_size(&self) -> usize {
        1
    }
    fn stencils(&self) -> &[usize] {
        &self.0
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::ELASTIC
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let p = input.q[self.0[0]];
        out.f[0] = -4.0 * WELL * p * (p * p - 1.0);
        if input.jacobian {
            out.dfdq[0] = -WELL * (12.0 * p * p - 4.0);
        }
    }
}

/// An angle of negligible inertia starting at rest where its energy is concave (ψ = 0.45):
/// the step's matrix is `E''(ψ) < 0` there, and the full Newton update overshoots without
/// reducing the residual. A shift in the mass metric (`μ c_m m`, at most 1e-5 here) could not
/// make it descend; the shift by its own negative diagonal does, and the step ends in the well
/// at ψ ≈ 1 (the minimum that descent reaches), not at the maximum ψ = 0 nor across it in
/// the far well ψ = −1, where the unshifted uphill updates of a mass-metric shift ended.
#[test]
fn a_massless_dof_on_a_concave_energy_is_shifted_into_its_well() {
    let mut model = Model::new(DofLayout::new(1, 1));
    model.mass.iter_mut().for_each(|m| *m = M);
    let angle = model.layout.twist(0);
    model.mass[angle] = ANGLE_INERTIA;
    model.add_force(DoubleWell([angle]));
    let mut q = vec![0.0; 4];
    q[angle] = 0.45;
    let mut state = State::at_rest(q);
    let c = one_strict_step(&mut model, &mut state, 1e-12);
    // The well, moved by the angle's inertia: c_m m (ψ − 0.45) + E'(ψ) = 0 with c_m m = 1e-8
    // puts it within 1e-8 of ψ = 1.
    let p = state.q[angle];
    assert!((p - 1.0).abs() < 1e-6, "ψ = {p}, {c:?}");
}

/// One step of `H` by plain Newton to the absolute force tolerance `tol` (N), which must
/// converge and meet an indefinite matrix on the way (what these tests are about).
fn one_strict_step(model: &mut Model, state: &mut State, tol: f64) -> engine::Counters {
    let opts = NewtonOptions {
        force_tol_abs: Some(tol),
        force_tol_rel: 0.0,
        ..NewtonOptions::default()
    }
    .strict();
    let mut st = ImplicitEuler::new(model, opts).unwrap();
    st.step(model, state, H).expect("the step converges");
    let c = *st.counters();
    assert!(c.indefinite_factorizations >= 1, "{c:?}");
    c
}
