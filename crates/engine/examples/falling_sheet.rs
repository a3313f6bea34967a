//! A square elastic sheet (a discrete shell) released flat from rest, falling under gravity
//! with quadratic triangle drag, compared with the analytic law of a flat plate:
//! `v(t) = v_t tanh(g t / v_t)`, `v_t = √(2 ρ_s g / (ρ C_n))` (`ρ_s` the sheet's mass per
//! area). Lumped masses are a third of each triangle's mass per vertex and each vertex gets a
//! third of its triangle's drag, so a flat sheet falls without deforming and follows the law
//! up to backward Euler's O(dt) error.
//!
//! Run with `cargo run --release -p chute-engine --example falling_sheet`.
use engine::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 11 × 11 nodes over 1 m × 1 m, each cell split into two triangles.
    let n = 11;
    let h = 1.0 / (n - 1) as f64;
    let positions: Vec<[f64; 3]> = (0..n * n)
        .map(|k| [(k % n) as f64 * h, (k / n) as f64 * h, 100.0])
        .collect();
    let mut faces = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let (a, b, c, d) = (
                j * n + i,
                j * n + i + 1,
                (j + 1) * n + i + 1,
                (j + 1) * n + i,
            );
            faces.extend([[a, b, c], [a, c, d]]);
        }
    }
    let mesh = TriMesh::new(faces, &positions)?;
    // A 1 mm rubber-like sheet: 0.98 kg/m², so v_t ≈ 3 m/s in sea-level air.
    let sheet = ShellMaterial {
        youngs_modulus: 1e7,
        thickness: 1e-3,
        density: 980.0,
    };
    let q0: Vec<f64> = positions.iter().flatten().copied().collect();
    let mut model = Model::new(DofLayout::new(n * n, 0));
    engine::shell::install(&mesh, &sheet, &mut model, &q0)?;
    let g = 9.81;
    let nodes: Vec<usize> = (0..n * n).collect();
    let masses: Vec<f64> = nodes.iter().map(|&i| model.node_mass(i)).collect();
    model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -g]));
    let air = Fluid::air();
    let (c_n, c_t) = (1.75, 0.5);
    let drag = model.add_force(TriangleDrag::new(&mesh.faces, c_n, c_t, &air));

    let rho_s = sheet.areal_density();
    let v_t = (2.0 * rho_s * g / (air.density * c_n)).sqrt();
    let opts = NewtonOptions {
        reference_acceleration: g,
        ..NewtonOptions::recommended()
    };
    let mut stepper = ImplicitEuler::new(&model, opts)?;
    let mut state = State::at_rest(q0);
    let dt = 1e-3;
    println!(
        "falling sheet: {} nodes, {} triangles",
        n * n,
        mesh.faces.len()
    );
    println!("   t (s)   descent speed (m/s)   tanh law (m/s)   drag force (N)");
    for step in 1..=2000 {
        stepper.step(&mut model, &mut state, dt)?;
        if step % 250 == 0 {
            let vz = -mean(&model, &state.v, 2);
            let exact = v_t * (g * state.t / v_t).tanh();
            let f = engine::aero::resultant(model.force(drag), &model.layout, &state.q, &state.v);
            println!("{:8.3} {:21.6} {:16.6} {:16.4}", state.t, vz, exact, f[2]);
        }
    }
    let vz = -mean(&model, &state.v, 2);
    println!(
        "terminal speed {vz:.5} m/s, analytic √(2ρ_s g/(ρ C_n)) = {v_t:.5} m/s (error {:.1e})",
        vz / v_t - 1.0
    );
    println!(
        "Newton iterations: {} in {} steps",
        stepper.counters().iterations,
        2000
    );
    Ok(())
}

/// Mass-weighted mean of velocity component `k` over all nodes (m/s).
fn mean(model: &Model, v: &[f64], k: usize) -> f64 {
    let n = model.layout.n_nodes;
    (0..n)
        .map(|i| model.node_mass(i) * v[3 * i + k])
        .sum::<f64>()
        / model.total_mass()
}
