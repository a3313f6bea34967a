//! First natural period of a clamped cantilever, stepped with implicit Euler, against
//! Euler–Bernoulli beam theory: `T₁ = 2π / ((1.8751)² √(EI/(ρ A L⁴)))`.
use super::cantilever::{cantilever, ei_round, round, G, STEEL_RHO};
use super::RefError;
use crate::loads::PointForces;
use crate::rod::Section;
use crate::{ImplicitEuler, NewtonOptions};

/// Measured first period and its diagnostics.
#[derive(Debug, Clone)]
pub struct PeriodResult {
    /// Period from the zero crossings of the tip displacement (s).
    pub measured: f64,
    /// Euler–Bernoulli first period (s).
    pub exact: f64,
    /// Zero-crossing times used (s).
    pub crossings: Vec<f64>,
    /// Newton iterations over the whole run.
    pub newton_iterations: usize,
}

/// Release a round cantilever (`n` nodes, length `length`, radius `r`, all m) from its
/// static shape under a small tip load (`δ/L = 1e-3`, almost pure mode 1) and step it with
/// `dt = T₁/steps_per_period` for `periods` periods. The period is twice the mean spacing of
/// the tip's zero crossings, skipping the first two (the mode-2 content of the static shape,
/// ≈ 2.5 %, shifts them; backward Euler damps it within the first period).
pub fn first_period(
    n: usize,
    length: f64,
    r: f64,
    steps_per_period: usize,
    periods: f64,
) -> Result<PeriodResult, RefError> {
    let mut c = cantilever(n, length, round(r))?;
    let sec = Section::Circle { radius: r };
    let ei = ei_round(r);
    let rho_a = STEEL_RHO * sec.area();
    let omega = 1.8751f64.powi(2) * (ei / (rho_a * length.powi(4))).sqrt();
    let exact = std::f64::consts::TAU / omega;

    let p = 3.0 * ei * 1e-3 / length.powi(2);
    let tip = c.tip();
    c.model
        .add_force(PointForces::new(&[tip], &[[0.0, 0.0, -p]]));
    c.solve_static(1)?;
    if let Some(f) = c.model.forces.last_mut() {
        f.set_load_scale(0.0);
    }

    let dt = exact / steps_per_period as f64;
    // Force scale of the reference problems (the rod's weight scale, as in `static_opts`).
    let opts = NewtonOptions {
        reference_acceleration: G,
        ..Default::default()
    };
    let mut stepper = ImplicitEuler::new(&c.model, opts)?;
    let mut crossings = Vec::new();
    let mut z_prev = c.state.q[3 * tip + 2];
    let mut iters = 0;
    for _ in 0..(periods * steps_per_period as f64) as usize {
        iters += stepper.step(&mut c.model, &mut c.state, dt)?.iterations;
        let z = c.state.q[3 * tip + 2];
        if z_prev.signum() != z.signum() && z != 0.0 {
            crossings.push(c.state.t - dt * z / (z - z_prev));
        }
        z_prev = z;
    }
    if crossings.len() < 7 {
        return Err(RefError::Measure(format!(
            "only {} zero crossings of the tip",
            crossings.len()
        )));
    }
    let crossings = crossings[2..].to_vec();
    let k = crossings.len();
    Ok(PeriodResult {
        measured: 2.0 * (crossings[k - 1] - crossings[0]) / (k - 1) as f64,
        exact,
        crossings,
        newton_iterations: iters,
    })
}
