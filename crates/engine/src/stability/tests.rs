//! The steady descent and its modes against closed forms and a dense eigen-solve.

use faer::{c64, Mat};

use super::*;
use crate::aero::{Fluid, LinearDrag};
use crate::reference::falling::{point_mass, G, VT};
use crate::rod::Stretch;
use crate::{DofLayout, Model};

/// Iterative modes are the companion matrix's eigenvalues to this relative accuracy.
const EIG_TOL: f64 = 1e-7;

#[test]
fn a_point_mass_descends_at_its_terminal_velocity_in_the_wind() {
    let fluid = Fluid {
        wind: [2.0, -1.0, 0.0],
        ..Fluid::air()
    };
    let (model, state) = point_mass(&fluid, 100.0);
    let opts = SteadyOptions::recommended(&model, G, 0);
    let s = steady_descent(&model, &state.q, [0.3, 0.2, -1.0], 0.0, &opts).unwrap();
    let want = [2.0, -1.0, -VT];
    for k in 0..3 {
        assert!(
            (s.velocity[k] - want[k]).abs() < 1e-9 * VT,
            "{:?}",
            s.velocity
        );
    }
    assert!(s.residual_n <= opts.tolerance_n);
    assert_eq!(s.q, state.q, "the held node stays");
}

#[test]
fn a_held_node_outside_the_model_is_an_error() {
    let (model, state) = point_mass(&Fluid::air(), 0.0);
    let opts = SteadyOptions::recommended(&model, G, 3);
    let e = steady_descent(&model, &state.q, [0.0; 3], 0.0, &opts).unwrap_err();
    assert!(
        matches!(e, StabilityError::NoSuchNode { node: 3, .. }),
        "{e}"
    );
}

/// At terminal speed V the drag's ∂F/∂v is −ρC_DA V along the motion and half that across
/// it, with K = 0: modes λ = 0 (position, three), −g/V (across, two), −2g/V (along).
#[test]
fn a_falling_point_has_the_drag_relaxation_modes() {
    let (model, state) = point_mass(&Fluid::air(), 0.0);
    let opts = SteadyOptions::recommended(&model, G, 0);
    let s = steady_descent(&model, &state.q, [0.0, 0.0, -1.0], 0.0, &opts).unwrap();
    let lin = Linearized::at(&model, &s.q, &s.v, 0.0);
    // Both paths; the iteration's two passes find the multiple eigenvalues' shapes twice, and
    // each shape is kept once.
    for dense_up_to in [0, DENSE_UP_TO] {
        let opts = ModeOptions {
            dense_up_to,
            ..Default::default()
        };
        point_modes(&modes(&lin, &opts).unwrap());
    }
}

fn point_modes(found: &[Mode]) {
    let mut re: Vec<f64> = found.iter().map(|m| m.eigenvalue.re).collect();
    re.sort_by(f64::total_cmp);
    let want = [-2.0 * G / VT, -G / VT, -G / VT, 0.0, 0.0, 0.0];
    assert_eq!(re.len(), 6, "{re:?}");
    for (got, want) in re.iter().zip(want) {
        assert!((got - want).abs() < EIG_TOL * G / VT, "{re:?} vs {want}");
    }
    assert!(found.iter().all(|m| m.eigenvalue.im.abs() < EIG_TOL));
}

/// A mass on a spring along x with a linear damper, its other end held: along x,
/// `m λ² + c λ + k = 0`; across (an unloaded string has no lateral stiffness), λ = 0 and −c/m.
#[test]
fn a_damped_oscillator_has_its_closed_form_modes() {
    let (m, c, k) = (2.0, 0.6, 50.0);
    let mut model = Model::new(DofLayout::new(2, 0));
    let q = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0];
    model.add_node_mass(1, m);
    model.fix_node(0);
    model.add_force(Stretch::new("spring", &[[0, 1]], &q, vec![k]));
    model.add_force(LinearDrag::new(&[1], &[c], &Fluid::air()));
    let lin = Linearized::at(&model, &q, &[0.0; 6], 0.0);
    for dense_up_to in [0, DENSE_UP_TO] {
        let opts = ModeOptions {
            dense_up_to,
            ..Default::default()
        };
        oscillator_modes(&modes(&lin, &opts).unwrap(), m, c, k);
    }
}

fn oscillator_modes(found: &[Mode], m: f64, c: f64, k: f64) {
    assert_eq!(found.len(), 6);
    let disc = (4.0 * m * k - c * c).sqrt();
    let pair = c64::new(-c / (2.0 * m), disc / (2.0 * m));
    let want = [
        pair,
        pair.conj(),
        0.0.into(),
        0.0.into(),
        (-c / m).into(),
        (-c / m).into(),
    ];
    for w in want {
        let near = found
            .iter()
            .filter(|f| (f.eigenvalue - w).norm() < EIG_TOL * pair.norm());
        assert!(near.count() >= 1, "{w} not in {:?}", eigenvalues(found));
    }
    for f in found {
        assert!(f.backward_error < 1e-12, "{f:?}");
    }
    // The oscillating pair moves along x only.
    let osc = found.iter().find(|f| f.eigenvalue.im > 0.0).unwrap();
    assert!((osc.shape[3].norm() - 1.0).abs() < 1e-12 && osc.shape[4].norm() < 1e-9);
}

/// The stiff sheet of `reference::sheet` crumpled by ±1.5 cm, moving down and sideways,
/// with node `held` fixed: `(model, q, v)`.
fn crumpled_sheet(held: usize) -> (Model, Vec<f64>, Vec<f64>) {
    let (mut model, state) = crate::reference::sheet::kevlar_sheet(4, 3, 1.0, 0.8, 5.0);
    model.fix_node(held);
    let q: Vec<f64> = state
        .q
        .iter()
        .enumerate()
        .map(|(i, x)| x + 0.03 * ((i as f64 * 0.7548776662).fract() - 0.5))
        .collect();
    let v = (0..q.len())
        .map(|d| if d % 3 == 2 { -4.0 } else { 0.3 })
        .collect();
    (model, q, v)
}

fn eigenvalues(modes: &[Mode]) -> Vec<c64> {
    modes.iter().map(|m| m.eigenvalue).collect()
}

/// On a crumpled sheet with drag (non-symmetric K and C, compressed springs that buckle),
/// every mode found is an eigenvalue of the dense companion matrix, and no eigenvalue the
/// Cayley map ranks clearly above the last one found is missing.
#[test]
fn modes_match_a_dense_eigen_solve_on_a_crumpled_sheet() {
    // A held corner: no free translation, whose triple λ = 0 is ill-conditioned.
    let (model, q, v) = crumpled_sheet(0);
    let lin = Linearized::at(&model, &q, &v, 0.0);
    // The iteration, not the dense path that small models take.
    let opts = ModeOptions {
        dense_up_to: 0,
        ..Default::default()
    };
    let found = modes(&lin, &opts).unwrap();
    assert!(found.len() >= 2, "{} converged", found.len());
    let dense = dense_eigenvalues(&lin);
    let is_found = |d: &c64| {
        found
            .iter()
            .any(|f| (f.eigenvalue - d).norm() < 1e-6 * (1.0 + d.norm()))
    };
    for f in &found {
        assert!(
            is_found(&f.eigenvalue)
                && dense
                    .iter()
                    .any(|d| (d - f.eigenvalue).norm() < 1e-6 * (1.0 + d.norm())),
            "{} not an eigenvalue",
            f.eigenvalue
        );
        assert!(f.backward_error <= opts.max_backward_error, "{f:?}");
    }
    // Every clearly growing mode (this crumpled state is no equilibrium: compressed springs
    // buckle) is found, and of the others, every one nearer σ than the farthest found.
    for d in dense.iter().filter(|d| d.re > 1e-3) {
        assert!(is_found(d), "growing {d} missing");
    }
    let reach = found
        .iter()
        .filter(|f| f.eigenvalue.re <= NEUTRAL_RATE)
        .map(|f| (f.eigenvalue - opts.shift).norm())
        .fold(0.0, f64::max);
    for d in dense
        .iter()
        .filter(|d| (*d - opts.shift).norm() < 0.999 * reach)
    {
        assert!(
            is_found(d),
            "{d} (|λ − σ| = {}) missing",
            (*d - opts.shift).norm()
        );
    }
}

/// Eigenvalues of `[[0, I], [M⁻¹K, M⁻¹C]]`, dense, the low-rank part added in.
fn dense_eigenvalues(lin: &Linearized) -> Vec<c64> {
    let n = lin.n_free;
    let mut a = Mat::<f64>::zeros(2 * n, 2 * n);
    for i in 0..n {
        a[(i, n + i)] = 1.0;
    }
    for col in 0..n {
        for k in lin.col_ptr[col]..lin.col_ptr[col + 1] {
            let row = lin.row_idx[k];
            a[(n + row, col)] = lin.k[k] / lin.mass[row];
            a[(n + row, n + col)] = lin.c[k] / lin.mass[row];
        }
    }
    for c in &lin.coupling {
        for row in 0..n {
            for col in 0..n {
                a[(n + row, col)] += c.u[row] * c.wq[col] / lin.mass[row];
                a[(n + row, n + col)] += c.u[row] * c.wv[col] / lin.mass[row];
            }
        }
    }
    a.eigenvalues().unwrap()
}

/// With a force coupled through held quantities (the incidence pressure on a small cone
/// held on springs below a fixed payload, committed 12° off its axis), both paths find
/// eigenvalues of the dense companion matrix that includes the low-rank part, and the part
/// moves them.
#[test]
fn modes_include_the_coupling_through_held_quantities() {
    use crate::aero::{IncidenceCurve, IncidencePressure};
    let (a, c) = ([-90.0, -20.0, 0.0, 20.0, 90.0], [0.5, 0.2, 0.0, -0.2, -0.5]);
    let curve = IncidenceCurve::try_from_degrees(&a, &c).unwrap();
    // Apex 0, rim 1..=6 (radius 1 m, 0.5 m below the apex), payload 7 held 2 m below.
    let mut q = vec![0.0, 0.0, 0.5];
    for k in 0..6 {
        let p = std::f64::consts::PI * k as f64 / 3.0;
        q.extend([p.cos(), p.sin(), 0.0]);
    }
    q.extend([0.0, 0.0, -2.0]);
    let rim = |k: usize| 1 + k % 6;
    let tris: Vec<[usize; 3]> = (0..6).map(|k| [0, rim(k), rim(k + 1)]).collect();
    let mut edges: Vec<[usize; 2]> = (0..6)
        .flat_map(|k| [[0, rim(k)], [rim(k), rim(k + 1)]])
        .collect();
    edges.extend((0..6).map(|k| [rim(k), 7]));
    let mut model = Model::new(DofLayout::new(8, 0));
    (0..7).for_each(|i| model.add_node_mass(i, 0.05));
    model.add_node_mass(7, 2.0);
    model.fix_node(7);
    model.add_force(Stretch::new(
        "springs",
        &edges,
        &q,
        vec![200.0; edges.len()],
    ));
    model.add_force(IncidencePressure::new(&tris, &q, 1.4, curve, &Fluid::air()));
    let t = 12f64.to_radians();
    let v: Vec<f64> = (0..24)
        .map(|d| {
            if d >= 21 {
                0.0
            } else {
                [5.0 * t.sin(), 0.0, -5.0 * t.cos()][d % 3]
            }
        })
        .collect();
    model.forces.iter_mut().for_each(|f| f.commit(&q, &v));
    let lin = Linearized::at(&model, &q, &v, 0.0);
    assert_eq!(lin.coupling.len(), 9);
    let dense = dense_eigenvalues(&lin);
    let without = dense_eigenvalues(&Linearized::jacobians_at(&model, &q, &v, 0.0));
    let far = |set: &[c64], d: &c64| set.iter().all(|e| (e - d).norm() > 1e-6 * (1.0 + d.norm()));
    assert!(
        dense.iter().any(|d| far(&without, d)),
        "the coupling moves some mode"
    );
    for dense_up_to in [0, DENSE_UP_TO] {
        let opts = ModeOptions {
            dense_up_to,
            ..Default::default()
        };
        let found = modes(&lin, &opts).unwrap();
        assert!(found.len() >= 4, "{} found", found.len());
        for f in &found {
            assert!(
                !far(&dense, &f.eigenvalue),
                "{} not an eigenvalue ({dense_up_to})",
                f.eigenvalue
            );
            assert!(f.backward_error <= opts.max_backward_error, "{f:?}");
        }
    }
}

/// `K` and `C` are the sums of the forces' own Jacobians (each checked against finite
/// differences by the conformance tests), scattered onto the free DOFs.
#[test]
fn k_and_c_are_the_forces_jacobians_on_the_free_dofs() {
    let (model, q, v) = crumpled_sheet(4);
    let lin = Linearized::at(&model, &q, &v, 0.0);
    let n = q.len();
    let (mut k, mut c) = (vec![0.0; n * n], vec![0.0; n * n]);
    for f in &model.forces {
        let (_, kf, cf) = crate::fdcheck::dense_eval(f.as_ref(), &q, &v);
        k.iter_mut().zip(kf).for_each(|(a, b)| *a += b);
        c.iter_mut().zip(cf).for_each(|(a, b)| *a += b);
    }
    assert_eq!(lin.n_free, n - 3);
    let mut stored = 0.0;
    for col in 0..lin.n_free {
        for e in lin.col_ptr[col]..lin.col_ptr[col + 1] {
            let (r, d) = (lin.dof_of[lin.row_idx[e]], lin.dof_of[col]);
            // The same sums in another order: equal to round-off.
            assert!((lin.k[e] - k[r * n + d]).abs() <= 1e-9 * (1.0 + k[r * n + d].abs()));
            assert!((lin.c[e] - c[r * n + d]).abs() <= 1e-12 * (1.0 + c[r * n + d].abs()));
            stored += k[r * n + d].abs();
        }
    }
    // Every nonzero of the free block is in the pattern.
    let free = |d: usize| !model.fixed[d];
    let all: f64 = (0..n * n)
        .filter(|i| free(i / n) && free(i % n))
        .map(|i| k[i].abs())
        .sum();
    assert!((stored - all).abs() <= 1e-9 * all);
}

/// A payload pendulum under a drag node: every root of its lateral characteristic cubic is
/// a mode, to round-off (`reference::pendulum`), moving the nodes sideways only.
#[test]
fn a_payload_pendulum_has_its_small_oscillation_modes() {
    use crate::reference::pendulum::Pendulum;
    let p = Pendulum::example();
    let fluid = Fluid::air();
    let (model, mut q) = p.model(&fluid);
    q[5] -= 0.01; // a taut line, as after a flight
    let opts = SteadyOptions::recommended(&model, p.g, 1);
    let s = steady_descent(&model, &q, [0.0, 0.0, -4.0], 0.0, &opts).unwrap();
    let (v, _) = p.steady(fluid.density);
    assert!((s.velocity[2] + v).abs() < 1e-9 * v);
    let lin = Linearized::at(&model, &s.q, &s.v, 0.0);
    let found = modes(&lin, &ModeOptions::default()).unwrap();
    let roots = p.lateral(fluid.density);
    // A light canopy over a heavy payload: a damped swing pair and a fast canopy mode.
    assert!(
        roots.iter().any(|r| r.im > 0.0) && roots.iter().all(|r| r.re < 0.0),
        "{roots:?}"
    );
    for r in roots {
        let m = found
            .iter()
            .find(|m| (m.eigenvalue - r).norm() < 1e-8 * r.norm());
        let m = m.unwrap_or_else(|| panic!("{r} not in {:?}", eigenvalues(&found)));
        assert!(
            m.shape[2].norm() < 1e-9 && m.shape[5].norm() < 1e-9,
            "{m:?}"
        );
    }
}
