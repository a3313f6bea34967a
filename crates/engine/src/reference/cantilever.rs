//! Clamped DER cantilevers and their static analytic references: small-deflection tip load
//! (`δ = P L³/3EI`) and self-weight (`δ = q L⁴/8EI`), the large-deflection elastica of
//! Bisshopp & Drucker (1945), and the circular arc of radius `EI/M` under an end moment.
use super::RefError;
use crate::loads::{Gravity, PlanarEdgeMoment, PointForces};
use crate::rod::{RodHandles, RodNetwork, RodSpec, Section};
use crate::{DofLayout, EngineError, Model, NewtonOptions, State, StaticSolver};

/// Young's modulus of the steel-like reference rod (Pa).
pub const STEEL_E: f64 = 200e9;
/// Shear modulus of the reference rod, `E / (2 (1 + ν))` with ν = 0.3 (Pa).
pub const STEEL_G: f64 = 200e9 / 2.6;
/// Density of the reference rod (kg/m³).
pub const STEEL_RHO: f64 = 7850.0;
/// Standard gravity used by the reference problems (m/s²).
pub const G: f64 = 9.81;

/// Bisshopp & Drucker (1945), "Large deflection of cantilever beams", Q. Appl. Math. 3,
/// Table 1: for a vertical tip load with `α = P L²/EI`, the tip's vertical deflection `w/L`
/// and horizontal shortening `(L − x_tip)/L`. Rows `(α, w/L, (L − x)/L)`.
pub const BISSHOPP_DRUCKER: [(f64, f64, f64); 4] = [
    (1.0, 0.30172, 0.05643),
    (2.0, 0.49346, 0.16064),
    (5.0, 0.71379, 0.38763),
    (10.0, 0.81061, 0.55500),
];

/// A straight cantilever along +x, clamped at its first edge.
pub struct Cantilever {
    /// The rod network (one rod).
    pub net: RodNetwork,
    /// Model with the rod's forces and masses installed, clamp applied.
    pub model: Model,
    /// State at rest in the straight configuration.
    pub state: State,
    /// Handles of the installed rod (twist DOFs, rest lengths).
    pub handles: RodHandles,
    /// Number of nodes.
    pub n: usize,
    /// Edge length (m).
    pub l: f64,
}

impl Cantilever {
    /// Tip node index.
    pub fn tip(&self) -> usize {
        self.n - 1
    }
    /// Displacement of node `i` along axis `k` from the configuration `q0` (m).
    pub fn disp(&self, i: usize, k: usize, q0: &[f64]) -> f64 {
        self.state.q[3 * i + k] - q0[3 * i + k]
    }
    /// Static equilibrium in `steps` load increments with [`static_opts`].
    pub fn solve_static(&mut self, steps: usize) -> Result<(), RefError> {
        let mut s = StaticSolver::new(&self.model, static_opts())?;
        s.solve(&mut self.model, &mut self.state, steps)?;
        Ok(())
    }
}

/// Cantilever of free length `length` (m) with `n` nodes. The clamp fixes nodes 0 and 1 and
/// the first twist; the continuum clamp section is the midpoint of that edge (the discrete
/// moment–curvature balance at node 1 acts over the Voronoi cell [l/2, 3l/2]), so the nodes
/// are placed at `x_k = (k − ½) l` with `l = L/(n − 1.5)`, putting the clamp section at x = 0
/// and the tip at x = L.
pub fn cantilever(
    n: usize,
    length: f64,
    spec: impl Fn(Vec<usize>) -> RodSpec,
) -> Result<Cantilever, EngineError> {
    let l = length / (n as f64 - 1.5);
    let layout = DofLayout::new(n, n - 1);
    let mut q = vec![0.0; layout.len()];
    for k in 0..n {
        q[3 * k] = (k as f64 - 0.5) * l;
    }
    let mut net = RodNetwork::new();
    net.add_rod(spec((0..n).collect()));
    let mut model = Model::new(layout);
    let handles = net.install(&mut model, &q, 0)?;
    net.clamp_end(&mut model, 0, true, 0);
    Ok(Cantilever {
        net,
        model,
        state: State::at_rest(q),
        handles,
        n,
        l,
    })
}

/// A steel-like round rod of radius `r` (m): E = 200 GPa, ν = 0.3, ρ = 7850 kg/m³.
pub fn round(r: f64) -> impl Fn(Vec<usize>) -> RodSpec {
    move |nodes| {
        RodSpec::new(
            nodes,
            Section::Circle { radius: r },
            STEEL_E,
            STEEL_G,
            STEEL_RHO,
        )
    }
}

/// Bending stiffness `EI = E π r⁴/4` of the round reference rod (N·m²).
pub fn ei_round(r: f64) -> f64 {
    Section::Circle { radius: r }.ei1(STEEL_E)
}

/// Static solver options for the cantilevers: the default tolerances with the force scale of
/// the rod's weight (`reference_acceleration` = [`G`]; the axial round-off floor of a stiff
/// steel rod, EA·1e-16/l ≈ 1e-7 N, is above any tighter absolute force tolerance; the step
/// criterion then certifies convergence) and up to 40 iterations.
pub fn static_opts() -> NewtonOptions {
    NewtonOptions {
        max_iterations: 40,
        reference_acceleration: G,
        ..Default::default()
    }
}

/// A simulated value and its analytic reference (same units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compared {
    /// Simulated value.
    pub simulated: f64,
    /// Analytic reference.
    pub reference: f64,
}

impl Compared {
    /// Signed relative error `simulated/reference − 1`.
    pub fn rel_error(&self) -> f64 {
        self.simulated / self.reference - 1.0
    }
}

/// Tip deflection (m) of a round cantilever (`n` nodes, length `length`, radius `r`) under
/// a vertical tip load chosen so that `δ/L = defl_ratio`, against `P L³/3EI`.
pub fn tip_load(n: usize, length: f64, r: f64, defl_ratio: f64) -> Result<Compared, RefError> {
    let mut c = cantilever(n, length, round(r))?;
    let ei = ei_round(r);
    let p = 3.0 * ei * defl_ratio / (length * length);
    c.model
        .add_force(PointForces::new(&[c.tip()], &[[0.0, 0.0, -p]]));
    let q0 = c.state.q.clone();
    c.solve_static(1)?;
    Ok(Compared {
        simulated: -c.disp(c.tip(), 2, &q0),
        reference: p * length.powi(3) / (3.0 * ei),
    })
}

/// Tip deflection (m) of a round cantilever under its own weight `q = ρ A g` (lumped to the
/// nodes), against `q L⁴/8EI`.
pub fn self_weight(n: usize, length: f64, r: f64) -> Result<Compared, RefError> {
    let mut c = cantilever(n, length, round(r))?;
    let nodes: Vec<usize> = (0..c.n).collect();
    let masses: Vec<f64> = nodes.iter().map(|&i| c.model.node_mass(i)).collect();
    c.model
        .add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -G]));
    let q0 = c.state.q.clone();
    c.solve_static(1)?;
    let q = STEEL_RHO * Section::Circle { radius: r }.area() * G;
    Ok(Compared {
        simulated: -c.disp(c.tip(), 2, &q0),
        reference: q * length.powi(4) / (8.0 * ei_round(r)),
    })
}

/// Large-deflection elastica under a vertical tip load `P = α EI/L²`, solved in `4α` load
/// increments. Returns the tip's `(w/L, (L − x_tip)/L)` (compare with
/// [`BISSHOPP_DRUCKER`]).
pub fn elastica(n: usize, length: f64, r: f64, alpha: f64) -> Result<(f64, f64), RefError> {
    let mut c = cantilever(n, length, round(r))?;
    let p = alpha * ei_round(r) / (length * length);
    c.model
        .add_force(PointForces::new(&[c.tip()], &[[0.0, 0.0, -p]]));
    c.solve_static(((4.0 * alpha) as usize).max(1))?;
    let tip = c.tip();
    Ok((
        -c.state.q[3 * tip + 2] / length,
        (length - c.state.q[3 * tip]) / length,
    ))
}

/// Result of the end-moment problem.
#[derive(Debug, Clone, Copy)]
pub struct ArcResult {
    /// Radius (m) of the circle through the first free node, the middle node and the tip.
    pub radius: f64,
    /// Continuum radius `EI/M` (m).
    pub exact: f64,
    /// Worst |distance to that circle's centre / (EI/M) − 1| over all nodes.
    pub worst_node: f64,
    /// Last edge's turning angle / π − 1 (it should turn by exactly π).
    pub tip_angle_err: f64,
}

/// A round cantilever bent by a pure end moment `M = π EI / s` on its last edge (`s` the
/// arc length from the clamp section to that edge's midpoint), so that the last edge turns
/// by π: the continuum solution is a half circle of radius `EI/M`. Solved in 20 increments.
pub fn end_moment(n: usize, length: f64, r: f64) -> Result<ArcResult, RefError> {
    let mut c = cantilever(n, length, round(r))?;
    let ei = ei_round(r);
    // The last edge sits (n−1) l from the clamp section (edge midpoint to edge midpoint).
    let arc = (c.n - 2) as f64 * c.l;
    let m = std::f64::consts::PI * ei / arc;
    let tip = c.tip();
    c.model.add_force(PlanarEdgeMoment::new(tip - 1, tip, m));
    c.solve_static(20)?;
    let p = |i: usize| [c.state.q[3 * i], c.state.q[3 * i + 2]];
    let (centre, radius) = circle(p(1), p(n / 2), p(tip));
    let exact = ei / m;
    let mut worst = 0.0f64;
    for i in 0..c.n {
        let d = ((p(i)[0] - centre[0]).powi(2) + (p(i)[1] - centre[1]).powi(2)).sqrt();
        worst = worst.max((d / exact - 1.0).abs());
    }
    let e = [p(tip)[0] - p(tip - 1)[0], p(tip)[1] - p(tip - 1)[1]];
    let phi = e[1].atan2(e[0]).rem_euclid(std::f64::consts::TAU);
    Ok(ArcResult {
        radius,
        exact,
        worst_node: worst,
        tip_angle_err: phi / std::f64::consts::PI - 1.0,
    })
}

/// Circumcentre and radius of three points in a plane (m).
pub fn circle(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> ([f64; 2], f64) {
    let d = 2.0 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]));
    let s = |p: [f64; 2]| p[0] * p[0] + p[1] * p[1];
    let ux = (s(a) * (b[1] - c[1]) + s(b) * (c[1] - a[1]) + s(c) * (a[1] - b[1])) / d;
    let uz = (s(a) * (c[0] - b[0]) + s(b) * (a[0] - c[0]) + s(c) * (b[0] - a[0])) / d;
    ([ux, uz], ((a[0] - ux).powi(2) + (a[1] - uz).powi(2)).sqrt())
}

/// The inextensible elastica under a vertical tip load `α = P L²/EI`, to ~1e-10: the tip's
/// `(w/L, (L − x_tip)/L)`, for convergence studies where the 5 digits of
/// [`BISSHOPP_DRUCKER`] are too few. With θ(s) the slope angle (down from +x) and s ∈ [0, 1]
/// the arc length over L, moment balance gives `θ'' = −α cos θ`, `θ(0) = 0` (clamp) and
/// `θ'(1) = 0` (no tip moment). The clamp curvature `θ'(0) ∈ [0, α]` is found by bisection
/// (shooting with classical RK4, 4000 steps, error ~h⁴ ≈ 1e-14); then `w = ∫ sin θ ds`,
/// `1 − x_tip = 1 − ∫ cos θ ds`.
pub fn elastica_exact(alpha: f64) -> (f64, f64) {
    const STEPS: usize = 4000;
    // State (θ, θ', ∫sin θ, ∫cos θ); returns the state at s = 1.
    let shoot = |k0: f64| {
        let f = |y: [f64; 4]| [y[1], -alpha * y[0].cos(), y[0].sin(), y[0].cos()];
        let h = 1.0 / STEPS as f64;
        let mut y = [0.0, k0, 0.0, 0.0];
        for _ in 0..STEPS {
            let add = |a: [f64; 4], b: [f64; 4], c: f64| std::array::from_fn(|i| a[i] + c * b[i]);
            let k1 = f(y);
            let k2 = f(add(y, k1, 0.5 * h));
            let k3 = f(add(y, k2, 0.5 * h));
            let k4 = f(add(y, k3, h));
            y = std::array::from_fn(|i| {
                y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
        }
        y
    };
    let (mut lo, mut hi) = (0.0, alpha);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if shoot(mid)[1] < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let y = shoot(0.5 * (lo + hi));
    (y[2], 1.0 - y[3])
}
