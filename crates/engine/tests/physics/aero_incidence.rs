//! The incidence pressure against its closed forms. On a uniform flow the windward excess
//! `C_1 q sᵢ` gives the whole canopy exactly the tabulated side force `−C_N(α) q S₀ ĉ`
//! (that is how `C_1` is chosen), the mean pressure `C_p q cos²α` times the rim's vector
//! area along the axis, and nothing else on a canopy symmetric about its axis; at zero
//! incidence it is the inflation law. Exact identities: round-off tolerances.
use engine::aero::{
    resultant, Fabric, Fluid, IncidenceCurve, IncidencePressure, InflationPressure,
};
use engine::force::{EvalInput, Force};
use engine::DofLayout;
use std::f64::consts::PI;

const CP: f64 = 1.4;

/// A spherical cap of radius 1 m from the crown (0, 0, 1) down to the polar angle `theta`,
/// `rings` rings of `spokes` nodes: symmetric under x → −x and y → −y.
fn cap(rings: usize, spokes: usize, theta: f64) -> (Vec<[usize; 3]>, Vec<f64>) {
    let mut q = vec![0.0, 0.0, 1.0];
    for r in 1..=rings {
        let t = theta * r as f64 / rings as f64;
        for k in 0..spokes {
            let p = 2.0 * PI * k as f64 / spokes as f64;
            q.extend([t.sin() * p.cos(), t.sin() * p.sin(), t.cos()]);
        }
    }
    let at = |r: usize, k: usize| 1 + (r - 1) * spokes + k % spokes;
    let mut tris = Vec::new();
    for k in 0..spokes {
        tris.push([0, at(1, k), at(1, k + 1)]);
        for r in 1..rings {
            tris.push([at(r, k), at(r + 1, k), at(r + 1, k + 1)]);
            tris.push([at(r, k), at(r + 1, k + 1), at(r, k + 1)]);
        }
    }
    (tris, q)
}

/// A solid canopy's shape of curve: pushes away from zero incidence up to 25°.
fn curve() -> IncidenceCurve {
    let a = [-90.0, -25.0, -10.0, 0.0, 10.0, 25.0, 90.0];
    let c = [0.3, 0.0, 0.08, 0.0, -0.08, 0.0, -0.3];
    IncidenceCurve::try_from_degrees(&a, &c).unwrap()
}

/// Every node moving at `vel`.
fn uniform(n: usize, vel: [f64; 3]) -> Vec<f64> {
    (0..n).flat_map(|_| vel).collect()
}

#[test]
fn a_symmetric_cap_feels_the_tabulated_side_force_and_the_rim_pressure() {
    let rho = Fluid::air().density;
    let (tris, q) = cap(8, 24, PI / 3.0);
    let n = q.len() / 3;
    // The rim is a 24-gon of circumradius sin 60°.
    let rim_area = 12.0 * (PI / 3.0).sin().powi(2) * (PI / 12.0).sin();
    for deg in [4.0_f64, 10.0, 17.0, 40.0] {
        let (alpha, speed) = (deg.to_radians(), 7.0);
        let vel = [speed * alpha.sin(), 0.0, -speed * alpha.cos()];
        let v = uniform(n, vel);
        let mut law = IncidencePressure::new(&tris, &q, CP, curve(), &Fluid::air());
        law.commit(&q, &v);
        assert!(
            (law.law().alpha() - alpha).abs() < 1e-12,
            "α read from the state"
        );
        let f = resultant(&law, &DofLayout::new(n, 0), &q, &v);
        let dyn_p = 0.5 * rho * speed * speed;
        let s0 = law.law().reference_area();
        let side = -curve().at(alpha) * dyn_p * s0;
        let axial = CP * dyn_p * alpha.cos().powi(2) * rim_area;
        let tol = 1e-11 * axial;
        assert!(
            (f[0] - side).abs() < tol,
            "{deg}°: side {} against {side}",
            f[0]
        );
        assert!(f[1].abs() < tol, "{deg}°: no force across the crossflow");
        assert!(
            (f[2] - axial).abs() < tol,
            "{deg}°: axial {} against {axial}",
            f[2]
        );
        assert!(
            law.law().c1().abs() < CP,
            "{deg}°: the bound does not bind on the cap"
        );
    }
}

#[test]
fn at_zero_incidence_it_is_the_inflation_law_with_or_without_fabric() {
    let (tris, q) = cap(5, 12, PI / 3.0);
    let n = q.len() / 3;
    let v = uniform(n, [0.0, 0.0, -6.0]);
    let fabric = Fabric::new(1e-4, 1e-10, 0.5);
    for fab in [None, Some(fabric)] {
        let (mut a, mut b) = (
            IncidencePressure::new(&tris, &q, CP, curve(), &Fluid::air()),
            InflationPressure::new(&tris, &q, CP, &Fluid::air()),
        );
        if let Some(f) = fab {
            (a, b) = (a.with_fabric(f), b.with_fabric(f));
        }
        a.commit(&q, &v);
        assert_eq!(a.law().c1(), 0.0);
        // A lifted, bent state: the law holds the frame of the commit.
        let q2: Vec<f64> = q
            .iter()
            .enumerate()
            .map(|(i, x)| x + 0.01 * (i % 7) as f64)
            .collect();
        let v2: Vec<f64> = v
            .iter()
            .enumerate()
            .map(|(i, x)| x + 0.1 * (i % 5) as f64)
            .collect();
        let input = EvalInput::outside_step(&q2, &v2, 0.0, true);
        let (mut ba, mut bb) = (a.new_blocks(), b.new_blocks());
        a.evaluate(&input, &mut ba);
        b.evaluate(&input, &mut bb);
        let scale = bb.f.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let close =
            |x: &[f64], y: &[f64], s: f64| x.iter().zip(y).all(|(p, r)| (p - r).abs() <= 1e-12 * s);
        assert!(close(&ba.f, &bb.f, scale), "forces ({fab:?})");
        let js = bb
            .dfdq
            .iter()
            .chain(&bb.dfdv)
            .fold(0.0_f64, |m, x| m.max(x.abs()));
        assert!(
            close(&ba.dfdq, &bb.dfdq, js) && close(&ba.dfdv, &bb.dfdv, js),
            "Jacobians ({fab:?})"
        );
    }
}

#[test]
fn a_flat_sheet_at_incidence_gets_no_excess_and_a_shallow_one_a_faded_one() {
    // A flat disc carries no side force (G = 0): no excess. Lifted into a shallow dome
    // (G below 0.05 S₀), the excess is G/G₀ of the full one, G₀ = 0.05 S₀.
    let (tris, cap_q) = cap(4, 12, PI / 3.0);
    let n = cap_q.len() / 3;
    let a = 10f64.to_radians();
    let v = uniform(n, [5.0 * a.sin(), 0.0, -5.0 * a.cos()]);
    let with_depth = |depth: f64| {
        let q: Vec<f64> = cap_q
            .chunks(3)
            .flat_map(|p| [p[0], p[1], depth * p[2]])
            .collect();
        let mut law = IncidencePressure::new(&tris, &cap_q, CP, curve(), &Fluid::air());
        law.commit(&q, &v);
        (law.law().c1(), law.law().reference_area())
    };
    assert_eq!(with_depth(0.0).0, 0.0, "flat");
    // The 60° cap takes the full excess −C_N S₀/G; squashed 100-fold it has G/100 < G₀ and
    // takes −C_N S₀ (G/100)/G₀².
    let ((full, s0), (shallow, _)) = (with_depth(1.0), with_depth(0.01));
    let cn = curve().at(a);
    let g = -cn * s0 / full;
    let g0 = engine::aero::incidence::SHALLOW_SIDE_AREA * s0;
    assert!(
        g > g0 && 0.01 * g < g0,
        "the cap is deep, the squashed one shallow"
    );
    let want = -cn * s0 * 0.01 * g / (g0 * g0);
    assert!(
        (shallow - want).abs() < 1e-9 * want,
        "{shallow} against {want}"
    );
}

#[test]
fn the_lag_coupling_completes_the_jacobian_of_the_unlagged_law() {
    // At incidence and at zero incidence (where ĉ turns with the perturbation).
    let (tris, q0) = cap(6, 16, PI / 3.0);
    let n = q0.len() / 3;
    for deg in [0.0_f64, 12.0, 33.0] {
        let a = deg.to_radians();
        let v0 = uniform(n, [6.0 * a.sin(), 0.0, -6.0 * a.cos()]);
        let mut law = IncidencePressure::new(&tris, &q0, CP, curve(), &Fluid::air());
        assert_lag_coupling_completes(&mut law, &q0, &v0, &format!("{deg}°"));
    }
}

/// `F(x)`, the force of `law` with its held quantities read at `x` itself: its derivative
/// is the stencils' Jacobians plus [`Force::lag_coupling`], against central differences
/// along random directions from `(q0, v0)`.
pub fn assert_lag_coupling_completes(law: &mut dyn Force, q0: &[f64], v0: &[f64], what: &str) {
    let mut seed = 11_u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let base = committed_force(law, q0, v0);
    let coupling = (law.lag_coupling(q0, v0)).expect("the law holds a state's function");
    let mut blocks = law.new_blocks();
    law.evaluate(&EvalInput::outside_step(q0, v0, 0.0, true), &mut blocks);
    let k = law.stencil_size();
    for _ in 0..3 {
        let dq: Vec<f64> = (0..q0.len()).map(|_| 0.1 * rnd()).collect();
        let dv: Vec<f64> = (0..q0.len()).map(|_| rnd()).collect();
        let mut want = vec![0.0; q0.len()];
        for (s, st) in law.stencils().chunks(k).enumerate() {
            for r in 0..k {
                for c in 0..k {
                    let at = s * k * k + r * k + c;
                    want[st[r]] += blocks.dfdq[at] * dq[st[c]] + blocks.dfdv[at] * dv[st[c]];
                }
            }
        }
        for (j, u) in coupling.u.iter().enumerate() {
            let w: f64 = (coupling.dofs.iter().enumerate())
                .map(|(i, &d)| coupling.wq[j][i] * dq[d] + coupling.wv[j][i] * dv[d])
                .sum();
            for (i, &d) in coupling.dofs.iter().enumerate() {
                want[d] += u[i] * w;
            }
        }
        let h = 1e-5;
        let mut shifted = |s: f64| {
            let q: Vec<f64> = q0.iter().zip(&dq).map(|(x, d)| x + s * d).collect();
            let v: Vec<f64> = v0.iter().zip(&dv).map(|(x, d)| x + s * d).collect();
            committed_force(law, &q, &v)
        };
        let (p, m) = (shifted(h), shifted(-h));
        let scale = base.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        for d in 0..q0.len() {
            let fd = (p[d] - m[d]) / (2.0 * h);
            assert!(
                (fd - want[d]).abs() < 1e-6 * scale,
                "{what}, DOF {d}: {fd} against {}",
                want[d]
            );
        }
    }
}

/// The law's total force on every DOF at `(q, v)` after committing there.
fn committed_force(law: &mut dyn Force, q: &[f64], v: &[f64]) -> Vec<f64> {
    law.commit(q, v);
    let mut b = law.new_blocks();
    law.evaluate(&EvalInput::outside_step(q, v, 0.0, false), &mut b);
    let mut total = vec![0.0; q.len()];
    for (d, f) in law.stencils().iter().zip(&b.f) {
        total[*d] += f;
    }
    total
}
