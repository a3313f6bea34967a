//! Shared set-up for the rod tests: a clamped cantilever and two small test-only loads.
#![allow(dead_code)]
use engine::rod::{RodHandles, RodNetwork, RodSpec, Section};
use engine::{DofLayout, EvalInput, Force, JacobianKind, LocalBlocks, Model, NewtonOptions, State};

/// A straight cantilever along +x, clamped at its first edge.
pub struct Cantilever {
    pub net: RodNetwork,
    pub model: Model,
    pub state: State,
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
    /// Displacement of node `i` from its initial position.
    pub fn disp(&self, i: usize, k: usize, q0: &[f64]) -> f64 {
        self.state.q[3 * i + k] - q0[3 * i + k]
    }
}

/// Cantilever of free length `length` with `n` nodes. The clamp fixes nodes 0 and 1 and the
/// first twist; the continuum clamp section is the midpoint of that edge (the discrete
/// moment–curvature balance at node 1 acts over the Voronoi cell [l/2, 3l/2]), so the nodes
/// are placed at `x_k = (k − ½) l` with `l = L/(n − 1.5)`, putting the clamp section at x = 0
/// and the tip at x = L.
pub fn cantilever(n: usize, length: f64, spec: impl Fn(Vec<usize>) -> RodSpec) -> Cantilever {
    let l = length / (n as f64 - 1.5);
    let layout = DofLayout::new(n, n - 1);
    let mut q = vec![0.0; layout.len()];
    for k in 0..n {
        q[3 * k] = (k as f64 - 0.5) * l;
    }
    let mut net = RodNetwork::new();
    net.add_rod(spec((0..n).collect()));
    let mut model = Model::new(layout);
    let handles = net.install(&mut model, &q, 0).unwrap();
    net.clamp_end(&mut model, 0, true, 0);
    Cantilever {
        net,
        model,
        state: State::at_rest(q),
        handles,
        n,
        l,
    }
}

/// A steel-like round rod of radius `r` (E = 200 GPa, ν = 0.3, ρ = 7850 kg/m³).
pub fn round(r: f64) -> impl Fn(Vec<usize>) -> RodSpec {
    move |nodes| {
        RodSpec::new(
            nodes,
            Section::Circle { radius: r },
            200e9,
            200e9 / 2.6,
            7850.0,
        )
    }
}

/// Static solver options: the default tolerances (the axial round-off floor of a stiff
/// steel rod, EA·1e-16/l ≈ 1e-7 N, is above any tighter absolute force tolerance; the step
/// criterion then certifies convergence), and *no* line search: the first Newton step from
/// a straight rod stretches the edges by O(slope²) and raises ‖R‖ by EA·slope²/2 (≈ 800 N
/// here), which the residual-norm backtracking rejects until it stalls, although the full
/// steps converge quadratically (4 iterations).
pub fn static_opts() -> NewtonOptions {
    NewtonOptions {
        max_iterations: 40,
        ..Default::default()
    }
}

/// Constant generalised forces on single DOFs (N or N·m), honouring the load scale.
pub struct DofForces {
    dofs: Vec<usize>,
    values: Vec<f64>,
    scale: f64,
}

impl DofForces {
    pub fn new(dofs: Vec<usize>, values: Vec<f64>) -> Self {
        Self {
            dofs,
            values,
            scale: 1.0,
        }
    }
}

impl Force for DofForces {
    fn name(&self) -> &str {
        "dof-forces"
    }
    fn stencil_size(&self) -> usize {
        1
    }
    fn stencils(&self) -> &[usize] {
        &self.dofs
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::CONSTANT
    }
    fn evaluate(&self, _input: &EvalInput<'_>, out: &mut LocalBlocks) {
        for (f, v) in out.f.iter_mut().zip(&self.values) {
            *f = self.scale * v;
        }
    }
    fn conservative(&self) -> bool {
        true
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        Some(
            -self.scale
                * self
                    .dofs
                    .iter()
                    .zip(&self.values)
                    .map(|(&d, v)| v * q[d])
                    .sum::<f64>(),
        )
    }
    fn set_load_scale(&mut self, s: f64) {
        self.scale = s;
    }
}

/// A conservative end moment `M` (N·m) about −y on the edge `a → b`, for motion in the x–z
/// plane: potential `−M φ`, `φ = atan2(e_z, e_x)` the edge's angle (unwrapped by history).
/// A planar moment is conservative and follows the edge, so this is the exact load of the
/// end-moment problem (a follower couple of two forces would only approximate it).
pub struct PlanarEdgeMoment {
    st: [usize; 6],
    moment: f64,
    scale: f64,
    phi_prev: f64,
}

impl PlanarEdgeMoment {
    pub fn new(a: usize, b: usize, moment: f64) -> Self {
        Self {
            st: [3 * a, 3 * a + 1, 3 * a + 2, 3 * b, 3 * b + 1, 3 * b + 2],
            moment,
            scale: 1.0,
            phi_prev: 0.0,
        }
    }
    fn angle(&self, q: &[f64]) -> (f64, f64, f64) {
        let ex = q[self.st[3]] - q[self.st[0]];
        let ez = q[self.st[5]] - q[self.st[2]];
        let raw = ez.atan2(ex);
        let tau = std::f64::consts::TAU;
        (raw - tau * ((raw - self.phi_prev) / tau).round(), ex, ez)
    }
}

impl Force for PlanarEdgeMoment {
    fn name(&self) -> &str {
        "planar-edge-moment"
    }
    fn stencil_size(&self) -> usize {
        6
    }
    fn stencils(&self) -> &[usize] {
        &self.st
    }
    fn jacobian_kind(&self) -> JacobianKind {
        JacobianKind::ELASTIC
    }
    fn evaluate(&self, input: &EvalInput<'_>, out: &mut LocalBlocks) {
        let (_, x, z) = self.angle(input.q);
        let m = self.scale * self.moment;
        let r2 = x * x + z * z;
        // ∇φ in (x, z) and its Hessian.
        let g = [-z / r2, x / r2];
        let h = [
            [2.0 * x * z / (r2 * r2), (z * z - x * x) / (r2 * r2)],
            [(z * z - x * x) / (r2 * r2), -2.0 * x * z / (r2 * r2)],
        ];
        let comp = [0usize, 2];
        out.f.fill(0.0);
        out.dfdq.fill(0.0);
        for i in 0..2 {
            out.f[3 + comp[i]] = m * g[i];
            out.f[comp[i]] = -m * g[i];
            for j in 0..2 {
                let v = m * h[i][j];
                out.dfdq[(3 + comp[i]) * 6 + 3 + comp[j]] = v;
                out.dfdq[comp[i] * 6 + comp[j]] = v;
                out.dfdq[(3 + comp[i]) * 6 + comp[j]] = -v;
                out.dfdq[comp[i] * 6 + 3 + comp[j]] = -v;
            }
        }
    }
    fn conservative(&self) -> bool {
        true
    }
    fn energy(&self, q: &[f64]) -> Option<f64> {
        Some(-self.scale * self.moment * self.angle(q).0)
    }
    fn commit(&mut self, q: &[f64]) {
        self.phi_prev = self.angle(q).0;
    }
    fn set_load_scale(&mut self, s: f64) {
        self.scale = s;
    }
}
