//! The steady descent: a shape that falls at one velocity `V` and turns at one rate `Ω` about
//! the vertical, solved by Newton in the frame that falls and turns with it.
//!
//! With `rᵢ = xᵢ − x_h` from the held node `h`, node `i` moves at `vᵢ = V + Ω ẑ × rᵢ` and
//! accelerates at `aᵢ = −Ω² (rᵢ)_horizontal` (twist rates 0), and the equations are
//! `R = F(q, v) − M a = 0` on every free DOF. The physics is unchanged by a translation and
//! by a turn about the vertical, so the unknowns leave those out: every free DOF but the held
//! node's three and one horizontal coordinate of the node farthest from it (the gauge of the
//! turn), plus `V` and `Ω`. The system is square; its exact Jacobian is factorised by sparse
//! LU. A body without a horizontal extent (all nodes on the vertical through `h`) has no turn
//! to solve for: `Ω = 0` and no gauge.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::Col;

use super::{Linearized, StabilityError};
use crate::model::Model;
use crate::stepper::convergence::STALL_FACTOR;

/// The pseudo-time of the angles' pseudo-inertia in the Newton matrix (s).
const TWIST_TAU: f64 = 1.0;

/// How the equilibrium is solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyOptions {
    /// Converged when `‖R‖∞` on the free DOFs is at most this (N).
    pub tolerance_n: f64,
    /// Also converged when a Newton update is at most this (m, m/s, rad/s) while `‖R‖∞` is
    /// within 1,000 times the tolerance: the residual is the forces' round-off (a body
    /// far from the origin, stiff rods), as in the step solver.
    pub step_tolerance: f64,
    /// Newton iterations at most.
    pub max_iterations: usize,
    /// The node whose position is held (the payload, or any node of the canopy).
    pub hold: usize,
}

impl SteadyOptions {
    /// The step solver's default tolerances, `10⁻⁹ (1 N + m g)` for total mass `m` and its
    /// step tolerance, 50 iterations, holding `hold`.
    pub fn recommended(model: &Model, gravity: f64, hold: usize) -> Self {
        Self {
            tolerance_n: 1e-9 * (1.0 + model.total_mass() * gravity),
            step_tolerance: crate::NewtonOptions::default().step_tol,
            max_iterations: 50,
            hold,
        }
    }
}

/// A steady descent.
#[derive(Debug, Clone, PartialEq)]
pub struct Steady {
    /// Positions (the held node where it was given).
    pub q: Vec<f64>,
    /// Velocities `V + Ω ẑ × rᵢ` of the nodes, twist rates 0.
    pub v: Vec<f64>,
    /// The held node's velocity `V` (m/s).
    pub velocity: [f64; 3],
    /// The turn rate `Ω` about the vertical (rad/s, positive anticlockwise seen from above).
    pub spin: f64,
    /// `‖R‖∞` on the free DOFs at the solution (N).
    pub residual_n: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// The unknowns' layout and the held node's position.
struct Layout {
    /// Held node.
    hold: usize,
    /// Translational DOFs of the model.
    nt: usize,
    /// Free rows that are unknown positions, in column order.
    position_cols: Vec<usize>,
    /// Whether `Ω` is an unknown (there is a gauge).
    spin: bool,
}

/// A trial point: positions, `V`, `Ω`.
#[derive(Clone)]
struct Point {
    q: Vec<f64>,
    vel: [f64; 3],
    spin: f64,
}

impl Layout {
    fn r(&self, q: &[f64], i: usize) -> [f64; 3] {
        [0, 1, 2].map(|k| q[3 * i + k] - q[3 * self.hold + k])
    }

    /// Node velocities and accelerations at `p`.
    fn motion(&self, p: &Point) -> (Vec<f64>, Vec<f64>) {
        let n = p.q.len();
        let (mut v, mut a) = (vec![0.0; n], vec![0.0; n]);
        for i in 0..self.nt / 3 {
            let r = self.r(&p.q, i);
            let w = p.spin;
            let vi = [p.vel[0] - w * r[1], p.vel[1] + w * r[0], p.vel[2]];
            let ai = [-w * w * r[0], -w * w * r[1], 0.0];
            v[3 * i..3 * i + 3].copy_from_slice(&vi);
            a[3 * i..3 * i + 3].copy_from_slice(&ai);
        }
        (v, a)
    }

    /// `lin` updated to `p`, and `R = F − M a` on its free rows.
    fn eval(&self, model: &Model, p: &Point, t: f64, lin: &mut Linearized) -> Vec<f64> {
        let (v, a) = self.motion(p);
        lin.update(model, &p.q, &v, t);
        lin.dof_of
            .iter()
            .map(|&d| lin.force[d] - model.mass[d] * a[d])
            .collect()
    }
}

/// Row of DOF `d` among `lin`'s free rows.
fn row_of(lin: &Linearized, d: usize) -> Option<usize> {
    lin.dof_of.iter().position(|&x| x == d)
}

/// The unknowns for `model` held at `hold`, from positions `q`.
fn layout(model: &Model, lin: &Linearized, q: &[f64], hold: usize) -> Layout {
    let nt = 3 * model.layout.n_nodes;
    let mut l = Layout {
        hold,
        nt,
        position_cols: Vec::new(),
        spin: false,
    };
    let mut held: Vec<usize> = (0..3).filter_map(|k| row_of(lin, 3 * hold + k)).collect();
    let far = (0..nt / 3)
        .map(|i| (i, l.r(q, i)))
        .max_by(|a, b| a.1[0].hypot(a.1[1]).total_cmp(&b.1[0].hypot(b.1[1])));
    let extent = (0..nt / 3)
        .map(|i| l.r(q, i).iter().map(|x| x * x).sum::<f64>().sqrt())
        .fold(0.0, f64::max);
    // A body on the vertical through `h` (a payload below one canopy node) has no turn.
    if let Some((g, r)) = far.filter(|(_, r)| r[0].hypot(r[1]) > 1e-3 * extent) {
        // The coordinate most along the turn's motion ẑ × r = (−r_y, r_x).
        let k = if r[0].abs() >= r[1].abs() { 1 } else { 0 };
        if let Some(row) = row_of(lin, 3 * g + k) {
            held.push(row);
            l.spin = true;
        }
    }
    l.position_cols = (0..lin.n_free).filter(|r| !held.contains(r)).collect();
    l
}

/// The Newton matrix's pattern: the position columns' rows, then dense columns for `V`
/// (and `Ω`).
fn pattern(lin: &Linearized, l: &Layout) -> (Vec<usize>, Vec<usize>) {
    let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
    for &r in &l.position_cols {
        row_idx.extend_from_slice(&lin.row_idx[lin.col_ptr[r]..lin.col_ptr[r + 1]]);
        col_ptr.push(row_idx.len());
    }
    for _ in 0..3 + usize::from(l.spin) {
        row_idx.extend(0..lin.n_free);
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx)
}

/// `∂R/∂(unknowns)` at `p` on [`pattern`] (module docs).
fn jacobian(lin: &Linearized, l: &Layout, p: &Point, model: &Model) -> Vec<f64> {
    let n = lin.n_free;
    let w = p.spin;
    let mut vals = Vec::new();
    for &col in &l.position_cols {
        let d = lin.dof_of[col];
        let range = lin.col_ptr[col]..lin.col_ptr[col + 1];
        vals.extend_from_slice(&lin.k[range.clone()]);
        if d >= l.nt {
            // A rod's uniform twist between ends free to turn (a suspension line) costs no
            // energy: a pseudo-inertia M/τ² on the angles keeps the matrix regular. It changes
            // the update, not the equations, so Newton still converges on them (linearly, at
            // the ratio of this term to the twist stiffness, where that is not zero).
            let base = vals.len() - range.len();
            for (j, k) in range.enumerate() {
                if lin.row_idx[k] == col {
                    vals[base + j] -= model.mass[d] / (TWIST_TAU * TWIST_TAU);
                }
            }
            continue;
        }
        if w == 0.0 {
            continue;
        }
        // vᵢ depends on xᵢ through Ω ẑ × rᵢ: ∂v_y/∂x = Ω, ∂v_x/∂y = −Ω (the same node's
        // columns share a pattern); aᵢ through −Ω² rᵢ: −M ∂a/∂x = Ω² M on x and y.
        let node = d / 3;
        let (other, sign) = match d % 3 {
            0 => (3 * node + 1, w),
            1 => (3 * node, -w),
            _ => continue,
        };
        let base = vals.len() - range.len();
        if let Some(oc) = row_of(lin, other) {
            for (j, k) in (lin.col_ptr[oc]..lin.col_ptr[oc + 1]).enumerate() {
                vals[base + j] += sign * lin.c[k];
            }
        }
        for (j, k) in range.enumerate() {
            if lin.row_idx[k] == col {
                vals[base + j] += w * w * model.mass[d];
            }
        }
    }
    let mut dense = vec![0.0; (3 + usize::from(l.spin)) * n];
    for (col, &d) in lin.dof_of.iter().enumerate() {
        if d >= l.nt {
            continue;
        }
        let r = l.r(&p.q, d / 3);
        // ∂vᵢ/∂V_c = e_c; ∂vᵢ/∂Ω = ẑ × rᵢ; −M ∂aᵢ/∂Ω = 2 Ω M rᵢ (horizontal).
        let dv_dspin = [-r[1], r[0], 0.0][d % 3];
        for k in lin.col_ptr[col]..lin.col_ptr[col + 1] {
            let row = lin.row_idx[k];
            dense[(d % 3) * n + row] += lin.c[k];
            if l.spin {
                dense[3 * n + row] += lin.c[k] * dv_dspin;
            }
        }
        if l.spin && d % 3 < 2 {
            dense[3 * n + col] += 2.0 * w * model.mass[d] * r[d % 3];
        }
    }
    vals.extend_from_slice(&dense);
    vals
}

/// A model that can fall as a whole, with a node to hold.
fn check(model: &Model, opts: &SteadyOptions) -> Result<(), StabilityError> {
    let fixed = model.fixed.iter().filter(|&&f| f).count();
    if fixed > 0 {
        return Err(StabilityError::FixedDofs(fixed));
    }
    let n_nodes = model.layout.n_nodes;
    if opts.hold >= n_nodes {
        return Err(StabilityError::NoSuchNode {
            node: opts.hold,
            n_nodes,
        });
    }
    Ok(())
}

/// The steady descent of `model` nearest to positions `q` and common node velocity
/// `velocity` (a run's state near terminal speed), at time `t`.
pub fn steady_descent(
    model: &Model,
    q: &[f64],
    velocity: [f64; 3],
    t: f64,
    opts: &SteadyOptions,
) -> Result<Steady, StabilityError> {
    check(model, opts)?;
    let mut p = Point {
        q: q.to_vec(),
        vel: velocity,
        spin: 0.0,
    };
    let mut lin = Linearized::jacobians_at(model, q, &vec![0.0; q.len()], t);
    let mut trial_lin = Linearized::jacobians_at(model, q, &vec![0.0; q.len()], t);
    let l = layout(model, &lin, q, opts.hold);
    let (col_ptr, row_idx) = pattern(&lin, &l);
    let n = lin.n_free;
    let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
    let symbolic = SymbolicLu::try_new(sym).map_err(|e| StabilityError::Singular(e.to_string()))?;
    let mut r = l.eval(model, &p, t, &mut lin);
    let norm = |r: &[f64]| r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut res = norm(&r);
    let mut iterations = 0;
    while res > opts.tolerance_n {
        if iterations == opts.max_iterations {
            return Err(StabilityError::NotConverged {
                iterations,
                residual: res,
                tolerance: opts.tolerance_n,
            });
        }
        iterations += 1;
        let vals = jacobian(&lin, &l, &p, model);
        let lu = Lu::try_new_with_symbolic(symbolic.clone(), SparseColMatRef::new(sym, &vals))
            .map_err(|e| StabilityError::Singular(format!("{e:?}")))?;
        let mut delta = Col::<f64>::from_fn(n, |i| -r[i]);
        lu.solve_in_place(delta.as_mat_mut());
        if delta.iter().any(|x| !x.is_finite()) {
            return Err(StabilityError::Singular(
                "the Newton matrix is singular: a mechanism (a slack line, a flat membrane without tension)".into(),
            ));
        }
        let size = delta.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let Some(next) = damped_step(model, &l, &lu, &p, &delta, t, &mut trial_lin) else {
            // Within the stall band no update can be told from round-off (as in the step
            // solver): the residual is the forces' round-off floor.
            if res <= STALL_FACTOR * opts.tolerance_n {
                break;
            }
            return Err(StabilityError::NotConverged {
                iterations,
                residual: res,
                tolerance: opts.tolerance_n,
            });
        };
        (p, r) = next;
        std::mem::swap(&mut lin, &mut trial_lin);
        res = norm(&r);
        if size <= opts.step_tolerance && res <= STALL_FACTOR * opts.tolerance_n {
            break;
        }
    }
    let (v, _) = l.motion(&p);
    Ok(Steady {
        q: p.q,
        v,
        velocity: p.vel,
        spin: p.spin,
        residual_n: res,
        iterations,
    })
}

/// The Newton update `delta` from `p`, damped by Deuflhard's natural monotonicity test: a
/// fraction λ of it is taken when the simplified Newton correction there, `J⁻¹ R` with the
/// same factors, is shorter than `(1 − λ/4)` of the update (P. Deuflhard, *Newton Methods for
/// Nonlinear Problems*, Springer 2004, §3.3). A residual test would refuse the steps a falling
/// body needs: a small turn of a stiff canopy, linearised, stretches it by the turn squared,
/// which raises `‖R‖` by orders of magnitude that the next iteration removes at once. The
/// point taken and its residual (`trial` holds its linearisation), or `None` when even a
/// thousandth of the update fails the test (no equilibrium near).
fn damped_step(
    model: &Model,
    l: &Layout,
    lu: &Lu<usize, f64>,
    p: &Point,
    delta: &Col<f64>,
    t: f64,
    trial: &mut Linearized,
) -> Option<(Point, Vec<f64>)> {
    let m = l.position_cols.len();
    let size = delta.norm_l2();
    let mut step = 1.0;
    loop {
        let mut point = p.clone();
        for (j, &row) in l.position_cols.iter().enumerate() {
            point.q[trial.dof_of[row]] += step * delta[j];
        }
        for c in 0..3 {
            point.vel[c] += step * delta[m + c];
        }
        if l.spin {
            point.spin += step * delta[m + 3];
        }
        let tr = l.eval(model, &point, t, trial);
        let mut bar = Col::<f64>::from_fn(tr.len(), |i| -tr[i]);
        lu.solve_in_place(bar.as_mat_mut());
        if bar.norm_l2() < (1.0 - step / 4.0) * size {
            return Some((point, tr));
        }
        if step < 1e-3 {
            return None;
        }
        step *= 0.5;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prelude::*;
    use crate::rod::Stretch;

    /// A soft sheet (springs, hinges) under gravity, pressure drag and corner loads.
    fn soft_sheet() -> (Model, Vec<f64>) {
        let s = crate::reference::sheet::sheet(4, 3, 1.0, 0.8, 0.0);
        let mesh = TriMesh::from_q(s.tris.clone(), &s.q, s.n_nodes).unwrap();
        let mut model = Model::new(DofLayout::new(s.n_nodes, 0));
        let mat = ShellMaterial {
            youngs_modulus: 1e6,
            thickness: 1e-3,
            density: 500.0,
        };
        crate::shell::install(&mesh, &mat, &mut model, &s.q).unwrap();
        let nodes: Vec<usize> = (0..s.n_nodes).collect();
        let masses: Vec<f64> = nodes.iter().map(|&i| model.mass[3 * i]).collect();
        model.add_force(Gravity::new(&nodes, &masses, [0.0, 0.0, -9.81]));
        model.add_force(PressureDrag::new(&s.tris, &s.q, 1.75, &Fluid::air()));
        model.add_force(PointForces::new(&[0, 3, 8, 11], &[[0.0, 0.0, -0.5]; 4]));
        let q =
            s.q.iter()
                .enumerate()
                .map(|(i, x)| x + 0.02 * ((i as f64 * 0.7548776662).fract() - 0.5))
                .collect();
        (model, q)
    }

    /// A canopy node (drag, light) and a payload (heavy, small drag) on a spring fall at
    /// `V² = 2 g Σm / (ρ C_D Σ A)`, the spring carrying `m₂ g − ½ ρ C_D A₂ V²` (closed form).
    #[test]
    fn a_payload_under_a_drag_node_falls_at_the_closed_form_speed() {
        let fluid = Fluid::air();
        let (m1, m2, a1, a2, cd, k) = (0.5, 8.0, 4.0, 0.1, 1.2, 2e4);
        let q = vec![0.0, 0.0, 0.0, 0.0, 0.0, -3.0];
        let mut model = Model::new(DofLayout::new(2, 0));
        model.add_node_mass(0, m1);
        model.add_node_mass(1, m2);
        model.add_force(Gravity::new(&[0, 1], &[m1, m2], [0.0, 0.0, -9.81]));
        model.add_force(NodeDrag::new(&[0, 1], &[a1, a2], cd, &fluid));
        model.add_force(Stretch::new("line", &[[0, 1]], &q, vec![k]));
        let opts = SteadyOptions::recommended(&model, 9.81, 1);
        // From a taut line (a slack one is a mechanism: no Newton matrix), as after a flight.
        let start = vec![0.0, 0.0, 0.0, 0.0, 0.0, -3.01];
        let s = steady_descent(&model, &start, [0.0, 0.0, -4.0], 0.0, &opts).unwrap();
        let rho = fluid.density;
        let v = (2.0 * 9.81 * (m1 + m2) / (rho * cd * (a1 + a2))).sqrt();
        assert!(
            (s.velocity[2] + v).abs() < 1e-9 * v,
            "{} vs {v}",
            s.velocity[2]
        );
        let tension = m2 * 9.81 - 0.5 * rho * cd * a2 * v * v;
        // The stretch law's force is k (l/l̄ − 1) (N): l = l̄ (1 + T/k).
        let l = s.q[2] - s.q[5];
        assert!((l - 3.0 * (1.0 + tension / k)).abs() < 1e-9, "{l}");
    }

    /// The Newton matrix is the derivative of `R` in every unknown, with a turn.
    #[test]
    fn the_newton_matrix_is_the_residual_derivative() {
        let (model, q) = soft_sheet();
        let lin0 = Linearized::at(&model, &q, &vec![0.0; q.len()], 0.0);
        let l = layout(&model, &lin0, &q, 5);
        assert!(l.spin);
        let p = Point {
            q,
            vel: [0.4, -0.2, -3.0],
            spin: 0.7,
        };
        let mut lin = Linearized::at(&model, &p.q, &vec![0.0; p.q.len()], 0.0);
        let r0 = l.eval(&model, &p, 0.0, &mut lin);
        let (col_ptr, row_idx) = pattern(&lin, &l);
        let vals = jacobian(&lin, &l, &p, &model);
        let n = lin.n_free;
        let m = l.position_cols.len();
        let h = 1e-6;
        let mut probe = Linearized::at(&model, &p.q, &vec![0.0; p.q.len()], 0.0);
        for col in 0..n {
            let mut shifted = |s: f64| {
                let mut t = p.clone();
                if col < m {
                    t.q[lin.dof_of[l.position_cols[col]]] += s;
                } else if col < m + 3 {
                    t.vel[col - m] += s;
                } else {
                    t.spin += s;
                }
                l.eval(&model, &t, 0.0, &mut probe)
            };
            let (rp, rm) = (shifted(h), shifted(-h));
            let mut exact = vec![0.0; n];
            for k in col_ptr[col]..col_ptr[col + 1] {
                exact[row_idx[k]] += vals[k];
            }
            let scale = exact.iter().fold(1e-3f64, |a, x| a.max(x.abs()));
            for row in 0..n {
                let fd = (rp[row] - rm[row]) / (2.0 * h);
                assert!(
                    (fd - exact[row]).abs() < 1e-5 * scale,
                    "∂R[{row}]/∂u[{col}] (of {m} positions): {fd} vs {}",
                    exact[row]
                );
            }
        }
        assert!(r0.iter().any(|x| x.abs() > 0.0));
    }
}
