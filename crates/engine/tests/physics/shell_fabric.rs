//! Uniaxial patch tests of the continuum membranes and the no-compression (tension-field)
//! law against their closed forms.
//!
//! **Uniaxial tension.** A unit square (irregular interior nodes) under a dead traction `T`
//! (N per rest length) on its edges `X = 0, 1` has, for a St Venant–Kirchhoff law, the exact
//! homogeneous solution `x = (λ₁X, λ₂Y)`: `S₂₂ = 0` gives the Green strain `E₂₂ = −ν E₁₁`
//! (isotropic ν; for a fabric `ν₁₂` pulling the warp and `ν₂₁ = ν₁₂E₂/E₁` pulling the weft),
//! `S₁₁ = E h E₁₁` (the uniaxial modulus) and `T = λ₁ S₁₁`. Linear triangles reproduce it
//! exactly, so the nodal residual `f_int + f_ext` of that state vanishes to round-off
//! (1e-12 of the nodal forces); the same state with a Poisson ratio off by 0.02 leaves a
//! residual of ~1e-3, so the test can fail.
//!
//! **No compression.** For the tension field with regularisation strain `ε_r` (see
//! `engine::shell::tension_field`), in the wrinkled state (stretch along the warp, compression
//! across) the stress is uniaxial `S₁₁ = E₁ h E₁₁` with relative error `(ε_r/ε)²` and a
//! transverse stress `~μ/γ = ε_r² k_ref/γ` (γ the wrinkle strain); in compression
//! (slack) the stress is `~ε_r² k_ref/|ε|` where the elastic law would give `k|ε|`.
use crate::shell_membrane::irregular_square;
use engine::fdcheck::dense_eval;
use engine::shell::{CstMembrane, FabricMembrane, Orthotropic};
use engine::Force;

const FABRIC: Orthotropic = Orthotropic {
    warp_modulus: 1.2e9,
    weft_modulus: 0.6e9,
    shear_modulus: 0.05e9,
    poisson_ratio: 0.3,
    thickness: 1e-4,
};

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Relative nodal residual of the homogeneous uniaxial state of `force` on the unit-square
/// mesh `q0`: Green strain `e` along `axis` (0 = x, 1 = y), `−ratio · e` across it, dead
/// traction `λ₁ · modulus_h · e` on the two loaded edges (consistent nodal loads).
fn uniaxial_residual(
    force: &dyn Force,
    q0: &[f64],
    axis: usize,
    e: f64,
    ratio: f64,
    modulus_h: f64,
) -> f64 {
    let along = (1.0 + 2.0 * e).sqrt();
    let across = (1.0 - 2.0 * ratio * e).sqrt();
    let mut x = q0.to_vec();
    for node in x.chunks_mut(3) {
        node[axis] *= along;
        node[1 - axis] *= across;
    }
    let (mut r, _, _) = dense_eval(force, &x, &vec![0.0; x.len()]);
    let f_int = max_abs(&r);
    let traction = along * modulus_h * e;
    let n_nodes = q0.len() / 3;
    let n = (n_nodes as f64).sqrt().round() as usize;
    let h = 1.0 / (n - 1) as f64;
    for i in 0..n_nodes {
        let (xa, xb) = (q0[3 * i + axis], q0[3 * i + 1 - axis]);
        let on_edge = xa.abs() < 1e-12 || (xa - 1.0).abs() < 1e-12;
        if on_edge {
            let corner = xb.abs() < 1e-12 || (xb - 1.0).abs() < 1e-12;
            let tributary = if corner { 0.5 * h } else { h };
            let sign = if xa > 0.5 { 1.0 } else { -1.0 };
            r[3 * i + axis] += sign * traction * tributary;
        }
    }
    max_abs(&r) / f_int
}

#[test]
fn cst_uniaxial_tension_contracts_by_nu() {
    let (faces, q, _) = irregular_square(7, 21);
    let (e, nu, h) = (1e9, 0.3, 1e-3);
    let m = CstMembrane::new("cst", &faces, &q, e, nu, h).unwrap();
    for axis in [0, 1] {
        let exact = uniaxial_residual(&m, &q, axis, 0.05, nu, e * h);
        assert!(exact < 1e-12, "axis {axis}: residual {exact:e}");
        let wrong = uniaxial_residual(&m, &q, axis, 0.05, nu + 0.02, e * h);
        assert!(wrong > 1e-4, "axis {axis}: a wrong ν passes ({wrong:e})");
    }
}

#[test]
fn fabric_uniaxial_tension_contracts_by_its_poisson_ratios() {
    let (faces, q, _) = irregular_square(7, 22);
    let nu12 = FABRIC.poisson_ratio;
    let nu21 = nu12 * FABRIC.weft_modulus / FABRIC.warp_modulus;
    let (e1h, e2h) = (
        FABRIC.warp_modulus * FABRIC.thickness,
        FABRIC.weft_modulus * FABRIC.thickness,
    );
    // Warp along x, then along y: pulling the warp contracts by ν₁₂ against E₁, pulling
    // the weft by ν₂₁ against E₂.
    for (warp, axis_of_warp) in [([1.0, 0.0, 0.0], 0), ([0.0, 1.0, 0.0], 1)] {
        let m = FabricMembrane::new("fabric", &faces, &q, &FABRIC, warp, None).unwrap();
        for axis in [0, 1] {
            let (ratio, eh) = if axis == axis_of_warp {
                (nu12, e1h)
            } else {
                (nu21, e2h)
            };
            let exact = uniaxial_residual(&m, &q, axis, 0.05, ratio, eh);
            assert!(
                exact < 1e-12,
                "warp {warp:?} axis {axis}: residual {exact:e}"
            );
            let wrong = uniaxial_residual(&m, &q, axis, 0.05, ratio + 0.02, eh);
            assert!(
                wrong > 1e-4,
                "warp {warp:?} axis {axis}: wrong ν passes ({wrong:e})"
            );
        }
    }
}

/// Stress of every triangle of `m` at the homogeneous in-plane stretch `(sx, sy)` of `q`.
fn stresses(m: &FabricMembrane, q: &[f64], sx: f64, sy: f64) -> Vec<[f64; 3]> {
    let x: Vec<f64> = q
        .chunks(3)
        .flat_map(|n| [sx * n[0], sy * n[1], n[2]])
        .collect();
    (0..m.n_stencils()).map(|i| m.stress(&x, i)).collect()
}

/// Principal values of a Voigt stress `(S₁₁, S₂₂, S₁₂)`, larger first.
fn principal(s: &[f64; 3]) -> (f64, f64) {
    let mean = 0.5 * (s[0] + s[1]);
    let r = (0.5 * (s[0] - s[1])).hypot(s[2]);
    (mean + r, mean - r)
}

#[test]
fn no_compression_wrinkled_sheet_carries_uniaxial_tension_only() {
    let (faces, q, _) = irregular_square(6, 23);
    let eps_r = 1e-4;
    let m = FabricMembrane::new("nc", &faces, &q, &FABRIC, [1.0, 0.0, 0.0], Some(eps_r)).unwrap();
    let k_ref = 0.5 * (FABRIC.stiffness()[0][0] + FABRIC.stiffness()[1][1]);
    // Stretch 1 % along the warp, compress 1 % across: wrinkles along the warp.
    let (sx, sy) = (1.01f64, 0.99f64);
    let e11 = 0.5 * (sx * sx - 1.0);
    let uniaxial = FABRIC.warp_modulus * FABRIC.thickness * e11;
    // The elastic law would carry Q₁₂E₁₁ + Q₂₂E₂₂ across the wrinkles (compressive here).
    let elastic_across = {
        let qm = FABRIC.stiffness();
        qm[1][0] * e11 + qm[1][1] * 0.5 * (sy * sy - 1.0)
    };
    assert!(elastic_across < -0.1 * uniaxial);
    for s in stresses(&m, &q, sx, sy) {
        let rel = (s[0] - uniaxial).abs() / uniaxial;
        // (ε_r/ε)² = 1e-4, with a factor 10 for the constants of the expansion.
        assert!(rel < 1e-3, "S₁₁ = {} vs uniaxial {uniaxial}", s[0]);
        let (_, s2) = principal(&s);
        assert!(s2 > 0.0, "compressive principal stress {s2}");
        // μ/γ with γ ≈ |E₂₂| + ν₁₂E₁₁ ≈ 1.3e-2: ~1e-6 k_ref; bound 1e-5 k_ref.
        assert!(s[1] < 1e-5 * k_ref && s[2].abs() < 1e-5 * k_ref, "{s:?}");
    }
}

#[test]
fn no_compression_sheet_under_compression_carries_none() {
    let (faces, q, _) = irregular_square(6, 24);
    let eps_r = 1e-4;
    let k_ref = 0.5 * (FABRIC.stiffness()[0][0] + FABRIC.stiffness()[1][1]);
    for warp in [[1.0, 0.0, 0.0], [0.6, 0.8, 0.0]] {
        let m = FabricMembrane::new("nc", &faces, &q, &FABRIC, warp, Some(eps_r)).unwrap();
        let elastic = FabricMembrane::new("el", &faces, &q, &FABRIC, warp, None).unwrap();
        // Biaxial 2 % and 1 % compression (slack): elastic stresses ~1e-2 k_ref.
        let (sx, sy) = (0.98, 0.99);
        let el = stresses(&elastic, &q, sx, sy);
        for (s, e) in stresses(&m, &q, sx, sy).iter().zip(&el) {
            let (s1, s2) = principal(s);
            let (_, e2) = principal(e);
            assert!(e2 < -5e-3 * k_ref, "the elastic law compresses: {e:?}");
            assert!(s2 > 0.0, "compressive principal stress {s2}");
            // ~ε_r² k/|E| ≈ 1e-6 k_ref; bound 1e-5 k_ref, i.e. 1e-3 of the elastic stress.
            assert!(s1 < 1e-5 * k_ref, "slack sheet carries {s1}");
        }
        // And the nodal forces are the same fraction of the elastic ones.
        let x: Vec<f64> = q
            .chunks(3)
            .flat_map(|n| [sx * n[0], sy * n[1], n[2]])
            .collect();
        let f = |force: &dyn Force| max_abs(&dense_eval(force, &x, &vec![0.0; x.len()]).0);
        assert!(f(&m) < 2e-3 * f(&elastic), "{} vs {}", f(&m), f(&elastic));
    }
}
