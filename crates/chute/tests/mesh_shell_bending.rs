//! Discrete-shell bending against plate theory on the generated meshes:
//! cylinder bending energy (both mesh orientations, union-jack and equilateral lattices),
//! a simply supported square plate under uniform pressure, and a cantilever strip under
//! self-weight. `D_eff` is the lattice's effective plate stiffness (`docs/shells.md`).
use chute::mesh::{generate, CanopyMesh};
use engine::loads::{Gravity, PointForces};
use engine::shell::{install, HingeBending, Lattice, ShellMaterial};
use engine::{DofLayout, Model, NewtonOptions, State, StaticSolver};

const MAT: ShellMaterial = ShellMaterial {
    youngs_modulus: 1e9,
    thickness: 0.01,
    density: 1000.0,
};

fn shell_model(m: &CanopyMesh, mat: &ShellMaterial) -> (Model, Vec<f64>) {
    let q = m.q();
    let tri = m.tri_mesh().unwrap();
    let mut model = Model::new(DofLayout::new(m.n_nodes(), 0));
    install(&tri, mat, &mut model, &q);
    (model, q)
}

/// Node positions of the flat mesh `m` wrapped onto a cylinder of radius `r` (axis along x
/// when `axis_x`, else along y; arc length preserved), and the unit normals there.
fn wrap_on_cylinder(m: &CanopyMesh, r: f64, axis_x: bool) -> (Vec<f64>, Vec<[f64; 3]>) {
    let mut q = Vec::with_capacity(3 * m.n_nodes());
    let mut normals = Vec::with_capacity(m.n_nodes());
    for p in &m.positions {
        let (x, y) = (p[0], p[1]);
        let phi = if axis_x { y } else { x } / r;
        let (round, z) = (r * phi.sin(), r * (1.0 - phi.cos()));
        if axis_x {
            q.extend([x, round, z]);
            normals.push([0.0, -phi.sin(), phi.cos()]);
        } else {
            q.extend([round, y, z]);
            normals.push([-phi.sin(), 0.0, phi.cos()]);
        }
    }
    (q, normals)
}

/// Bending energy per area `Σ E_h / Σ A_h` at `q` over the hinges whose flat midpoint lies
/// in `inside`, with hinge area `A_h = (A_A + A_B)/3`: only interior hinges are sampled, so
/// the free boundary (where hinges are missing) does not bias the density.
fn energy_density(m: &CanopyMesh, q: &[f64], inside: &dyn Fn(f64, f64) -> bool) -> f64 {
    let tri = m.tri_mesh().unwrap();
    let flat = m.q();
    let kb = vec![MAT.hinge_stiffness(); tri.hinges.len()];
    let bend = HingeBending::new("bend", &tri.hinges, &flat, kb);
    let (mut energy, mut area) = (0.0, 0.0);
    for (i, h) in tri.hinges.iter().enumerate() {
        let [a, b] = h.edge;
        let mx = 0.5 * (flat[3 * a] + flat[3 * b]);
        let my = 0.5 * (flat[3 * a + 1] + flat[3 * b + 1]);
        if inside(mx, my) {
            energy += bend.hinge_energy(q, i);
            area += (tri.face_areas[h.faces[0]] + tri.face_areas[h.faces[1]]) / 3.0;
        }
    }
    energy / area
}

/// `q` with the union-jack checkerboard mode of amplitude `u` (m) along the normals: nodes
/// with even `i + j` (8 neighbours) move by `+u`, the others by `−u`.
fn checkerboard(m: &CanopyMesh, q: &[f64], normals: &[[f64; 3]], ell: f64, u: f64) -> Vec<f64> {
    let mut out = q.to_vec();
    for (k, p) in m.positions.iter().enumerate() {
        let ij = ((p[0] + 0.5) / ell).round() as i64 + ((p[1] + 0.5) / ell).round() as i64;
        let s = if ij % 2 == 0 { u } else { -u };
        for c in 0..3 {
            out[3 * k + c] += s * normals[k][c];
        }
    }
    out
}

fn report(name: &str, got: f64, expected: f64) -> f64 {
    let err = (got - expected).abs() / expected;
    println!("cylinder {name}: {got:.6e} J/m² vs ½D/R² = {expected:.6e}: rel. err {err:.2e}");
    err
}

#[test]
fn cylinder_bending_energy_matches_plate_theory() {
    let r = 1.0;
    let kb = MAT.hinge_stiffness();
    // Union-jack, 100 × 100 cells of ℓ = 1 cm on the unit square. The window [−Kℓ, Kℓ]²
    // shifted by ℓ/4 holds exactly (2K)² cells' worth of each hinge type, so the density
    // is exact up to the chord-vs-arc error O((ℓ/R)²) ≈ 1e-4.
    let ell = 0.01;
    let rect = generate::rectangle(1.0, 1.0, ell);
    let w = 25.0 * ell;
    let window = |x: f64, y: f64| (x - ell / 4.0).abs() < w && (y - ell / 4.0).abs() < w;
    let (d_uj, _) = MAT.effective_bending(Lattice::UnionJack);
    for axis_x in [true, false] {
        let tag = if axis_x { "x" } else { "y" };
        let (q, normals) = wrap_on_cylinder(&rect, r, axis_x);
        // Nodes held on the cylinder (a prescribed surface): the affine stiffness k_b.
        let affine = energy_density(&rect, &q, &window);
        assert!(
            report(
                &format!("union-jack affine, axis {tag}"),
                affine,
                0.5 * kb / (r * r)
            ) < 0.01
        );
        // Free checkerboard relaxation: the energy is quadratic in its amplitude u (u ~
        // ℓ²/R ≪ ℓ), so three samples locate the minimum.
        let du = 0.1 * ell * ell / r;
        let e = [-du, 0.0, du]
            .map(|u| energy_density(&rect, &checkerboard(&rect, &q, &normals, ell, u), &window));
        let u_star = 0.5 * du * (e[0] - e[2]) / (e[0] - 2.0 * e[1] + e[2]);
        let relaxed = energy_density(
            &rect,
            &checkerboard(&rect, &q, &normals, ell, u_star),
            &window,
        );
        let err = report(
            &format!("union-jack relaxed, axis {tag}"),
            relaxed,
            0.5 * d_uj / (r * r),
        );
        assert!(err < 0.01, "u* = {u_star:e}");
    }
    // Equilateral: hexagon of 50 rings (ℓ = 2 cm), disc window of radius 0.5 m. One node per
    // lattice cell, so there is no internal relaxation; θ per hinge type is exact to
    // O((ℓ/R)²) ≈ 4e-4, and the window samples the three edge directions equally up to its
    // boundary fraction (~ℓ/0.5 m, far below 1 % for the difference between directions).
    let hex = generate::hexagon(1.0, 0.02);
    let disc = |x: f64, y: f64| x * x + y * y < 0.25;
    let (d_eq, _) = MAT.effective_bending(Lattice::Equilateral);
    for axis_x in [true, false] {
        let (q, _) = wrap_on_cylinder(&hex, r, axis_x);
        let got = energy_density(&hex, &q, &disc);
        let tag = if axis_x { "x" } else { "y" };
        assert!(
            report(
                &format!("equilateral, axis {tag}"),
                got,
                0.5 * d_eq / (r * r)
            ) < 0.01
        );
    }
    // The nominal plate stiffness is the equilateral one.
    assert!((d_eq - MAT.plate_stiffness()).abs() < 1e-12 * d_eq);
}

/// Centre deflection of a simply supported `a × a` union-jack plate with `n × n` cells under
/// pressure `p` (Pa, downward).
fn ss_plate_deflection(a: f64, n: usize, p: f64) -> f64 {
    let m = generate::rectangle(a, a, a / n as f64);
    let (mut model, q) = shell_model(&m, &MAT);
    let tri = m.tri_mesh().unwrap();
    for &i in &tri.boundary_nodes {
        model.fixed[3 * i + 2] = true;
    }
    // In-plane rigid modes: centre node in x and y, a long-edge midpoint in x (rotation).
    let c = m.node_set("center").unwrap()[0];
    let mid = m.node_set("long_edge_midpoints").unwrap()[1];
    model.fixed[3 * c] = true;
    model.fixed[3 * c + 1] = true;
    model.fixed[3 * mid] = true;
    let nodes: Vec<usize> = (0..m.n_nodes()).collect();
    let forces: Vec<[f64; 3]> = tri
        .vertex_areas
        .iter()
        .map(|&av| [0.0, 0.0, -p * av])
        .collect();
    model.add_force(PointForces::new(&nodes, &forces));
    let opts = NewtonOptions {
        force_tol_abs: Some(1e-6 * p * a * a),
        ..Default::default()
    };
    let mut solver = StaticSolver::new(&model, opts).unwrap();
    let mut state = State::at_rest(q);
    solver.solve(&mut model, &mut state, 1).unwrap();
    -state.q[3 * c + 2]
}

#[test]
fn simply_supported_plate_under_pressure() {
    // Navier series for a simply supported square plate: w_c = 0.00406 q a⁴/D (independent
    // of ν). The union-jack lattice is isotropic in bending with D_eff = ¾ k_b (relaxed).
    // Small load: w_c ≈ 1e-3 h, so membrane (geometric) effects ~ (w/h)² are negligible.
    let (a, d_eff) = (1.0f64, MAT.effective_bending(Lattice::UnionJack).0);
    let p = 1e-3 * MAT.thickness * d_eff / (0.00406 * a.powi(4));
    let reference = 0.00406 * p * a.powi(4) / d_eff;
    let mut errors = Vec::new();
    for n in [10, 20, 40] {
        let w = ss_plate_deflection(a, n, p);
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
    let (len, b, ell) = (1.0, 0.1, 0.025);
    let mat = ShellMaterial {
        youngs_modulus: 1e10,
        thickness: 0.005,
        density: 100.0,
    };
    let m = generate::rectangle(len, b, ell);
    let (mut model, q) = shell_model(&m, &mat);
    let x0 = -0.5 * len;
    for (i, p) in m.positions.iter().enumerate() {
        if p[0] < x0 + 1.5 * ell {
            model.fix_node(i);
        }
    }
    let nodes: Vec<usize> = (0..m.n_nodes()).collect();
    let masses: Vec<f64> = nodes.iter().map(|&i| model.node_mass(i)).collect();
    let g = 9.81;
    model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -g]));
    let weight = model.total_mass() * g;
    // Pure Newton: the first linear step from the flat strip creates second-order membrane
    // strains (residual 0.5 N → ~1e2 N through k_s ≈ 1e6 N) that the residual-norm line
    // search rejects, although the full steps converge quadratically (1e2 → 1e-3 → 1e-8).
    // The floor is round-off in k_s ε (~1e-8 N), hence the tolerance 1e-6 × weight.
    let opts = NewtonOptions {
        force_tol_abs: Some(1e-6 * weight),
        line_search: false,
        ..Default::default()
    };
    let mut solver = StaticSolver::new(&model, opts).unwrap();
    let mut state = State::at_rest(q);
    solver.solve(&mut model, &mut state, 1).unwrap();
    let tip: Vec<f64> = m
        .positions
        .iter()
        .enumerate()
        .filter(|(_, p)| p[0] > 0.5 * len - 1e-9)
        .map(|(i, _)| -state.q[3 * i + 2])
        .collect();
    let delta = tip.iter().sum::<f64>() / tip.len() as f64;
    // Euler–Bernoulli: δ = w L⁴/(8 EI) with w = ρ h g b. A narrow plate strip bends with
    // free anticlastic curvature, EI = D_eff (1 − ν_b²) b; here b²/(R h) ≈ 0.05 ≪ 1 (R the
    // smallest bending radius), so the narrow-strip limit applies. Union-jack lattice:
    // D_eff = ¾ k_b, ν_b = −1/3, hence EI = (8/9) D_eff b.
    let (d_eff, nu_b) = mat.effective_bending(Lattice::UnionJack);
    let ei = d_eff * (1.0 - nu_b * nu_b) * b;
    let l_free = len - ell;
    let reference = mat.areal_density() * g * b * l_free.powi(4) / (8.0 * ei);
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
