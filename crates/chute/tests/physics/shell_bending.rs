//! Discrete-shell bending against plate theory on the generated meshes:
//! cylinder bending energy (both mesh orientations, union-jack and equilateral lattices),
//! a simply supported square plate under uniform pressure, and a cantilever strip under
//! self-weight. `D_eff` is the lattice's effective plate stiffness (`docs/shells.md`). The
//! set-ups are shared with `chute validate` (`chute::verify::shell_cases`).
use chute::mesh::{generate, CanopyMesh};
use chute::verify::shell_cases::{
    cantilever_strip, cylinder_energies, ss_plate_deflection, ss_plate_load, MAT,
};
use engine::shell::Lattice;

fn report(name: &str, got: f64, expected: f64) -> f64 {
    let err = (got - expected).abs() / expected;
    println!("cylinder {name}: {got:.6e} J/m² vs ½D/R² = {expected:.6e}: rel. err {err:.2e}");
    err
}

#[test]
fn cylinder_bending_energy_matches_plate_theory() {
    // Union-jack, 100 × 100 cells of ℓ = 1 cm on the unit square. The window [−Kℓ, Kℓ]²
    // shifted by ℓ/4 holds exactly (2K)² cells' worth of each hinge type, so the density
    // is exact up to the chord-vs-arc error O((ℓ/R)²) ≈ 1e-4. Nodes held on the cylinder
    // see the affine stiffness k_b; with the checkerboard mode relaxed, D_eff = ¾ k_b.
    // Equilateral: hexagon of 50 rings (ℓ = 2 cm), disc window of radius 0.5 m. One node per
    // lattice cell, so there is no internal relaxation; θ per hinge type is exact to
    // O((ℓ/R)²) ≈ 4e-4, and the window samples the three edge directions equally up to its
    // boundary fraction (~ℓ/0.5 m, far below 1 % for the difference between directions).
    let samples = cylinder_energies(1.0);
    assert_eq!(samples.len(), 6);
    for s in &samples {
        assert!(report(&s.label, s.density, s.reference) < 0.01, "{s:?}");
    }
    // The nominal plate stiffness is the equilateral one.
    let (d_eq, _) = MAT.effective_bending(Lattice::Equilateral);
    assert!((d_eq - MAT.plate_stiffness()).abs() < 1e-12 * d_eq);
}

#[test]
fn simply_supported_plate_under_pressure() {
    // Navier series for a simply supported square plate: w_c = 0.0040624 q a⁴/D (independent
    // of ν). The union-jack lattice is isotropic in bending with D_eff = ¾ k_b (relaxed).
    // Small load: w_c ≈ 1e-3 h, so membrane (geometric) effects ~ (w/h)² are negligible.
    let a = 1.0f64;
    let (p, reference) = ss_plate_load(a);
    let mut errors = Vec::new();
    for n in [10, 20, 40] {
        let w = ss_plate_deflection(a, n, p).unwrap();
        let err = (w - reference).abs() / reference;
        println!(
            "SS plate {n}×{n}: w_c = {w:.6e} m, reference {reference:.6e} m, rel. err {err:.3e}"
        );
        errors.push(err);
    }
    // Discretisation error (the hinge model is first/second order in ℓ): the 20 × 20 and
    // 40 × 40 meshes must be within 10 %, and the error must fall as the mesh refines.
    assert!(errors[1] < 0.10 && errors[2] < 0.10, "{errors:?}");
    assert!(errors[2] < errors[1] && errors[1] < errors[0], "{errors:?}");
}

#[test]
fn cantilever_strip_under_self_weight() {
    // Strip L × b along x, clamped at x = −L/2 by fixing the first two node columns (this
    // also fixes the slope). The free span is therefore L_f = L − ℓ, from column 1 to the tip.
    let len = 1.0;
    let r = cantilever_strip(0.025).unwrap();
    let (delta, reference) = (r.delta, r.reference);
    let err = (delta - reference).abs() / reference;
    println!("cantilever: tip δ = {delta:.6e} m, EB {reference:.6e} m, rel. err {err:.3e}");
    // Linear regime: δ/L must be small for Euler–Bernoulli to apply.
    assert!(delta / len < 1e-2, "{delta}");
    // Discretisation: lumped nodal loads and the two-column clamp, O(ℓ/L) = 2.5 %.
    assert!(err < 0.10, "{delta} vs {reference}");
}

/// Stretching energy per area `Σ E_e / Σ A_e` of the affine strain `(exx, eyy)` over the
/// edges whose midpoint lies in `inside`, edge area `A_e = (A_A + A_B)/3` (interior edges).
fn stretch_density(m: &CanopyMesh, exx: f64, eyy: f64, inside: &dyn Fn(f64, f64) -> bool) -> f64 {
    let tri = m.tri_mesh().unwrap();
    let (mut energy, mut area) = (0.0, 0.0);
    for h in &tri.hinges {
        let [a, b] = h.edge;
        let (pa, pb) = (m.positions[a], m.positions[b]);
        let (dx, dy) = (pb[0] - pa[0], pb[1] - pa[1]);
        if !inside(0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])) {
            continue;
        }
        let rest = dx.hypot(dy);
        let eps = (dx * (1.0 + exx)).hypot(dy * (1.0 + eyy)) / rest - 1.0;
        energy += 0.5 * MAT.stretch_stiffness(rest) * eps * eps * rest;
        area += (tri.face_areas[h.faces[0]] + tri.face_areas[h.faces[1]]) / 3.0;
    }
    energy / area
}

#[test]
fn in_plane_stiffness_of_the_edge_springs() {
    // Plane-strain modulus C11 = (Eh)_eff/(1 − ν²) from ε_xx alone, and C11 + C12 =
    // (Eh)_eff/(1 − ν) from equibiaxial strain. ε = 1e-6 keeps the geometric nonlinearity
    // of ε_edge at 1e-6 relative; the windows sample the edge types as in the cylinder test.
    let eps = 1e-6;
    let ell = 0.02;
    let rect = generate::rectangle(1.0, 1.0, ell);
    let w = 12.0 * ell;
    let window = move |x: f64, y: f64| (x - ell / 4.0).abs() < w && (y - ell / 4.0).abs() < w;
    let hex = generate::hexagon(1.0, 0.02);
    let disc = |x: f64, y: f64| x * x + y * y < 0.25;
    for (name, mesh, lattice, win) in [
        (
            "union-jack",
            &rect,
            Lattice::UnionJack,
            &window as &dyn Fn(f64, f64) -> bool,
        ),
        ("equilateral", &hex, Lattice::Equilateral, &disc),
    ] {
        let (eh, nu) = MAT.effective_membrane(lattice);
        for (exx, eyy, modulus) in [
            (eps, 0.0, eh / (1.0 - nu * nu)),
            (0.0, eps, eh / (1.0 - nu * nu)),
            (eps, eps, 2.0 * eh / (1.0 - nu)),
        ] {
            let got = stretch_density(mesh, exx, eyy, win);
            let expected = 0.5 * modulus * eps * eps;
            let err = (got - expected).abs() / expected;
            println!("membrane {name} ({exx:e}, {eyy:e}): {got:.6e} vs {expected:.6e}: {err:.2e}");
            assert!(err < 1e-3, "{name}: {got} vs {expected}");
        }
    }
    assert_eq!(MAT.effective_membrane(Lattice::Equilateral).0, 1e9 * 0.01);
}
