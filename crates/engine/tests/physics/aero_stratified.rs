//! Falling through air whose density varies with height: drag at each element's own
//! height, against a reference integration of the point-mass equation of motion.
//!
//! A point mass of terminal speed 3 m/s at z = 0 falls from rest into an isothermal
//! atmosphere `ρ = ρ₀ e^{−z/H}` with H = 20 m: by t = 8 s (z ≈ −18 m) the density has
//! risen 2.5-fold and the local terminal speed fallen to 1.9 m/s. The reference solves
//! `dv/dt = g (1 − e^{−z/H} v²/v_t²)`, `dz/dt = −v` by classical RK4 with 10⁻⁵ s steps
//! (error ~ 1e-20 relative); the model is the engine's point mass with `NodeDrag`, whose
//! position Jacobian now carries ∂ρ/∂z.
use engine::aero::{Fluid, Profile};
use engine::reference::falling::{point_mass, run, G, VT};

const H: f64 = 20.0;
const T_END: f64 = 8.0;

/// (t, descent speed) of the reference ODE at the times `times`.
fn reference(times: &[f64]) -> Vec<f64> {
    let rhs = |z: f64, v: f64| (-v, G * (1.0 - (-z / H).exp() * v * v / (VT * VT)));
    let (mut z, mut v, mut t) = (0.0f64, 0.0f64, 0.0f64);
    let h: f64 = 1e-5;
    let mut out = Vec::with_capacity(times.len());
    for &target in times {
        while t < target - 1e-12 {
            let step = h.min(target - t);
            let (k1z, k1v) = rhs(z, v);
            let (k2z, k2v) = rhs(z + 0.5 * step * k1z, v + 0.5 * step * k1v);
            let (k3z, k3v) = rhs(z + 0.5 * step * k2z, v + 0.5 * step * k2v);
            let (k4z, k4v) = rhs(z + step * k3z, v + step * k3v);
            z += step / 6.0 * (k1z + 2.0 * k2z + 2.0 * k3z + k4z);
            v += step / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            t += step;
        }
        out.push(v);
    }
    out
}

/// Largest |v − v_ref| / v_t of a run with step `dt`.
fn max_error(dt: f64) -> f64 {
    let fluid = Fluid {
        profile: Profile::Exponential { scale_height: H },
        ..Fluid::air()
    };
    let (mut model, mut state) = point_mass(&fluid, 0.0);
    let series = run(&mut model, &mut state, dt, (T_END / dt).round() as usize).unwrap();
    let times: Vec<f64> = series.iter().map(|s| s.0).collect();
    let exact = reference(&times);
    series
        .iter()
        .zip(&exact)
        .map(|(s, e)| (-s.1[2] - e).abs() / VT)
        .fold(0.0, f64::max)
}

#[test]
fn point_mass_in_an_exponential_atmosphere_follows_the_reference() {
    let (e1, e2) = (max_error(1e-3), max_error(5e-4));
    eprintln!(
        "stratified fall: max err {e1:.3e} (dt = 1e-3), {e2:.3e} (dt = 5e-4), ratio {:.3}",
        e1 / e2
    );
    // Backward Euler is first order: C·dt with C = O(g/v_t) ≈ 3 /s relative, as in the
    // uniform tanh test (0.3 % at dt = 1e-3); a wrong density (e.g. taken at z = 0) would
    // be off by O(1) at the end.
    assert!(e1 < 0.01, "error {e1}");
    assert!((e1 / e2 - 2.0).abs() < 0.1, "ratio {}", e1 / e2);
}
