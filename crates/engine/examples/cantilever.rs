//! A clamped steel rod (a discrete elastic rod) under a tip load, solved for static
//! equilibrium, compared with Euler–Bernoulli beam theory `δ = P L³ / (3 E I)` at small
//! load; then released and swinging freely, its first period against
//! `T₁ = 2π / (1.8751² √(EI / (ρ A L⁴)))`.
//!
//! Run with `cargo run --release -p chute-engine --example cantilever`.
use engine::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (length, radius, n) = (1.0, 0.005, 41);
    let (e, g_mod, rho) = (200e9, 200e9 / 2.6, 7850.0);
    // The clamp fixes nodes 0 and 1 and the first twist; the continuum clamp section is the
    // midpoint of that edge, so nodes sit at x_k = (k − ½) l with l = L / (n − 1.5).
    let l = length / (n as f64 - 1.5);
    let layout = DofLayout::new(n, n - 1);
    let mut q = vec![0.0; layout.len()];
    for k in 0..n {
        q[3 * k] = (k as f64 - 0.5) * l;
    }
    let section = Section::Circle { radius };
    let mut net = RodNetwork::new();
    let rod = net.add_rod(RodSpec::new((0..n).collect(), section, e, g_mod, rho));
    let mut model = Model::new(layout);
    net.install(&mut model, &q, 0)?;
    net.clamp_end(&mut model, rod, true, 0);

    let ei = section.ei1(e);
    let p = 3.0 * ei * 1e-3 / (length * length); // δ/L = 1e-3
    let tip = n - 1;
    let load = model.add_force(PointForces::new(&[tip], &[[0.0, 0.0, -p]]));
    let mut state = State::at_rest(q.clone());
    let opts = NewtonOptions {
        max_iterations: 40,
        ..NewtonOptions::default()
    };
    StaticSolver::new(&model, opts)?.solve(&mut model, &mut state, 1)?;
    let delta = q[3 * tip + 2] - state.q[3 * tip + 2];
    let exact = p * length.powi(3) / (3.0 * ei);
    println!("cantilever: {n} nodes, L = {length} m, r = {radius} m, EI = {ei:.4} N·m²");
    println!(
        "tip deflection under P = {p:.4} N: {delta:.6e} m, P L³/(3EI) = {exact:.6e} m (error {:.1e})",
        delta / exact - 1.0
    );

    // Release: remove the load and step through a few periods.
    model.force_mut(load).set_load_scale(0.0);
    let rho_a = rho * section.area();
    let omega = 1.8751f64.powi(2) * (ei / (rho_a * length.powi(4))).sqrt();
    let period = std::f64::consts::TAU / omega;
    let dt = period / 400.0;
    let mut stepper = ImplicitEuler::new(&model, NewtonOptions::recommended())?;
    let (mut z_prev, mut crossings) = (state.q[3 * tip + 2], Vec::new());
    while state.t < 4.3 * period {
        stepper.step(&mut model, &mut state, dt)?;
        let z = state.q[3 * tip + 2];
        if z_prev.signum() != z.signum() && z != 0.0 {
            crossings.push(state.t - dt * z / (z - z_prev));
        }
        z_prev = z;
    }
    // Skip the first two crossings (the static shape holds a little of mode 2, which
    // backward Euler damps within the first period).
    let c = &crossings[2..];
    let measured = 2.0 * (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64;
    println!(
        "first period: {measured:.6} s from {} zero crossings, Euler–Bernoulli {period:.6} s (error {:.1e})",
        c.len(),
        measured / period - 1.0
    );
    Ok(())
}
