//! `NewtonOptions::exact_retry`: a step that modified Newton (stale factors, the symmetric
//! approximation of the drag Jacobian, the extrapolating predictor) gives up on, but that
//! exact Newton with a line search converges, is taken instead of being rejected.

use engine::prelude::*;
use engine::shell;

const G: f64 = 9.81;

/// A Kevlar sheet (E = 55 GPa, 2 mm, 1,440 kg/m³; the course report's canopy) of
/// `lx × ly` m on an `nx × ny` grid, flat at rest, under gravity, the DisMech pressure drag
/// and a downward point force `corner_n` on each corner: the stiff-membrane, drag-dominated
/// start of the report's flight.
fn kevlar(nx: usize, ny: usize, lx: f64, ly: f64, corner_n: f64) -> (Model, State) {
    let s = engine::reference::sheet::sheet(nx, ny, lx, ly, 0.0);
    let mesh = TriMesh::from_q(s.tris.clone(), &s.q, s.n_nodes).unwrap();
    let mut model = Model::new(DofLayout::new(s.n_nodes, 0));
    let mat = ShellMaterial {
        youngs_modulus: 55e9,
        thickness: 2e-3,
        density: 1440.0,
    };
    shell::install(&mesh, &mat, &mut model, &s.q).unwrap();
    let nodes: Vec<usize> = (0..s.n_nodes).collect();
    let masses: Vec<f64> = nodes.iter().map(|&i| model.mass[3 * i]).collect();
    model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -G]));
    model.add_force(PressureDrag::new(&s.tris, &s.q, 1.75, &Fluid::air()));
    let corners = [0, nx - 1, nx * (ny - 1), nx * ny - 1];
    model.add_force(PointForces::new(&corners, &[[0.0, 0.0, -corner_n]; 4]));
    (model, State::at_rest(s.q))
}

/// Steps of `dt` over `t_end` with `opts`; the number of failed solves (each would halve
/// `dt` in a run) and the stepper's timings.
fn failures(opts: NewtonOptions, dt: f64, steps: usize, m: (Model, State)) -> (usize, engine::Timings) {
    let (mut model, mut state) = m;
    let mut st = ImplicitEuler::new(&model, opts).unwrap();
    let mut failed = 0;
    for _ in 0..steps {
        // A failure is retried at dt/2 twice, as the run loop would.
        if st.step(&mut model, &mut state, dt).is_err() {
            failed += 1;
            for _ in 0..2 {
                st.step(&mut model, &mut state, dt / 2.0).expect("half step");
            }
        }
    }
    (failed, *st.timings())
}

#[test]
fn explore() {
    for (nx, ny) in [(5, 3), (7, 4), (9, 5), (13, 7)] {
        for dt in [1e-2, 5e-3] {
            let o = NewtonOptions {
                reference_acceleration: G,
                ..NewtonOptions::recommended()
            };
            let no = NewtonOptions { exact_retry: false, ..o };
            let (f0, t0) = failures(no, dt, 40, kevlar(nx, ny, 6.0, 3.0, 50.0));
            let (f1, t1) = failures(o, dt, 40, kevlar(nx, ny, 6.0, 3.0, 50.0));
            eprintln!("{nx}x{ny} dt {dt}: no retry {f0} failed ({} it); retry {f1} failed, {} retries {} ok ({} it)",
                t0.iterations, t1.exact_retries, t1.exact_retries_converged, t1.iterations);
        }
    }
}
