//! Every force of the engine passes the checks of `engine::conformance` (finite-difference
//! gradient and Jacobians, force-only path, declared symmetry, history round trip): one
//! `force_conformance!` line per force, and further lines for the configurations where a
//! law is most delicate (flow edge-on to a triangle or reversing through it, hinges near
//! flat and folded, rest angles across the branch cut).
//!
//! Tolerances are those of `engine::conformance` (FD error < 1e-6 relative to the largest
//! analytic entry with h = 1e-6; identities to 1e-12): a correct derivative passes by orders
//! of magnitude, a missing term (∂n̂/∂x, a factor 2) fails by O(1).
mod contact;
mod fixtures;
mod membranes;
#[path = "../common/mesh.rs"]
mod mesh;
mod rods;

use engine::aero::{
    AddedMass, Fabric, Fluid, IncidenceCurve, IncidencePressure, InflationPressure, LinearDrag,
    NodeDrag, PressureDrag, TriangleDrag,
};
use engine::conformance::Case;
use engine::force::Force;
use engine::force_conformance;
use engine::loads::{DofForces, Gravity, PlanarEdgeMoment, PointForces};
use engine::rod::{Pull, RestSchedule, Scheduled, Stretch, TriggeredPull};
use engine::shell::{Hinge, HingeBending};
use fixtures::*;
use membranes::*;
use nalgebra::{Rotation3, Unit, Vector3};
use std::f64::consts::PI;

// Drag. Nodes and triangles displaced by up to 0.4 of the 1 m spacing: sheared, tilted and
// stretched triangles; velocities up to 10 m/s against a wind of a few m/s.
/// Linear drag on 3 of 4 free nodes, displaced by up to 2 m.
fn linear_drag_case(air: Fluid) -> Case {
    Case::new(
        LinearDrag::new(&[0, 2, 3], &[0.3, 1.0, 2.5], &air),
        vec![0.0; 12],
    )
    .perturb(2.0)
    .velocities(10.0)
}

force_conformance!(linear_drag, linear_drag_case(windy()));
// A wind that varies with height: the wind at each element's height, exact dU/dz.
force_conformance!(linear_drag_sheared, linear_drag_case(sheared()));
force_conformance!(node_drag_sheared, node_drag_case(sheared()));
force_conformance!(node_drag_power_law, node_drag_case(power_law()));
force_conformance!(node_drag_log_law, node_drag_case(log_law()));

/// Node drag on 4 of 5 free nodes, displaced by up to 2 m.
fn node_drag_case(air: Fluid) -> Case {
    Case::new(
        NodeDrag::new(&[0, 1, 2, 4], &[0.4, 1.1, 0.1, 0.7], 1.75, &air),
        vec![0.0; 15],
    )
    .perturb(2.0)
    .velocities(10.0)
    .trials(20)
}

/// The drag laws on triangles of the 3 × 3 grid.
#[derive(Clone, Copy)]
enum Law {
    Triangle,
    Pressure,
    Inflation,
    Incidence,
}

/// A `C_N(α)` that changes sign (0 at 0 and 25°), steep enough that the draws reach the
/// bound `|C_1| ≤ C_p` on the grid as well as leeward panels pushed in (`m < 0`).
fn incidence_curve() -> IncidenceCurve {
    let (a, c) = (
        [-90.0, -25.0, -12.0, 0.0, 12.0, 25.0, 90.0],
        [0.6, 0.0, 0.3, 0.0, -0.3, 0.0, -0.6],
    );
    IncidenceCurve::try_from_degrees(&a, &c).expect("odd, covers ±90°")
}

/// `force`, made permeable with `fabric` if any.
fn through<F: Force + 'static>(
    force: F,
    fabric: Option<Fabric>,
    with_fabric: fn(F, Fabric) -> F,
) -> Box<dyn Force> {
    Box::new(match fabric {
        Some(fabric) => with_fabric(force, fabric),
        None => force,
    })
}

/// `law` on the 3 × 3 grid of side 2 m in `air`, through `fabric` if any: nodes by up to
/// 0.4 m, velocities up to 10 m/s, 20 draws.
fn grid_drag_case(law: Law, air: Fluid, fabric: Option<Fabric>) -> Case {
    let (tris, q) = grid(3, 2.0);
    let force = match law {
        Law::Triangle => through(
            TriangleDrag::new(&tris, 1.75, 0.5, &air),
            fabric,
            TriangleDrag::with_fabric,
        ),
        Law::Pressure => through(
            PressureDrag::new(&tris, &q, 1.75, &air),
            fabric,
            PressureDrag::with_fabric,
        ),
        Law::Inflation => through(
            InflationPressure::new(&tris, &q, 1.4, &air),
            fabric,
            InflationPressure::with_fabric,
        ),
        Law::Incidence => through(
            IncidencePressure::new(&tris, &q, 1.4, incidence_curve(), &air),
            fabric,
            IncidencePressure::with_fabric,
        ),
    };
    Case::boxed(force, q)
        .perturb(0.4)
        .velocities(10.0)
        .trials(20)
}

/// [`grid_drag_case`] with velocities up to 5 m/s, then one triangle's normal flow set to one
/// of `speeds` (m/s) in each of `trials` draws. The triangle law sees the flow through the
/// triangle's mean velocity (triangle 3), pressure drag at each node (triangle 5).
fn reversing_case(
    law: Law,
    air: Fluid,
    fabric: Option<Fabric>,
    speeds: &'static [f64],
    trials: usize,
) -> Case {
    let (tris, _) = grid(3, 2.0);
    let wind = air.wind;
    let case = grid_drag_case(law, air, fabric).velocities(5.0);
    let case = match law {
        Law::Triangle => case.adjust(move |rng, q, v| {
            set_mean_normal_speed(q, v, tris[3], wind, pick(rng, speeds));
        }),
        Law::Pressure => case.adjust(move |rng, q, v| {
            set_node_normal_speeds(q, v, tris[5], wind, pick(rng, speeds));
        }),
        Law::Inflation | Law::Incidence => panic!("no reversing case for a canopy pressure"),
    };
    case.trials(trials)
}

/// One `force_conformance!` per row `name: law, air, fabric` of the drag matrix.
macro_rules! drag_matrix {
    ($($name:ident: $law:ident, $air:ident, $fabric:expr;)*) => {
        $(force_conformance!($name, grid_drag_case(Law::$law, $air(), $fabric));)*
    };
}

// Height-dependent air (drag at each element's own height, exact ∂ρ/∂z) and permeable
// fabric (the leakage split by the implicit function theorem), on the same draws.
force_conformance!(node_drag, node_drag_case(windy()));
force_conformance!(node_drag_stratified, node_drag_case(stratified()));
drag_matrix! {
    triangle_drag: Triangle, windy, None;
    pressure_drag: Pressure, windy, None;
    // Inflation pressure: triangles tilted and stretched, flow from every side (σ is fixed
    // at rest, so the draws also reach panels whose inside faces away from the flow).
    inflation_pressure: Inflation, windy, None;
    inflation_pressure_permeable_stratified: Inflation, stratified, Some(leaky());
    inflation_pressure_stratified: Inflation, stratified, None;
    // Incidence pressure: committed at one draw (axis, α, ĉ and each kᵢ from there),
    // evaluated at another; permeable panels on both sides of m = 0.
    incidence_pressure: Incidence, windy, None;
    incidence_pressure_permeable_stratified: Incidence, stratified, Some(leaky());
    // The 1976 atmosphere varies too gently (ρ′/ρ ≈ 1e-4 /m) for a check relative to the
    // largest Jacobian entry to see its ∂ρ/∂z term above round-off; its gradients are
    // checked against differences of ρ(z) and μ(z) in `physics::atmosphere`.
    triangle_drag_stratified: Triangle, stratified, None;
    triangle_drag_permeable: Triangle, windy, Some(leaky());
    triangle_drag_permeable_stratified: Triangle, stratified, Some(leaky());
    pressure_drag_stratified: Pressure, stratified, None;
    pressure_drag_permeable: Pressure, windy, Some(leaky());
    pressure_drag_permeable_stratified: Pressure, stratified, Some(leaky());
    triangle_drag_sheared: Triangle, sheared, None;
    triangle_drag_permeable_sheared: Triangle, sheared, Some(leaky());
    pressure_drag_sheared: Pressure, sheared, Some(leaky());
    // The inflation pressure sees only the vertical relative speed, which a horizontal wind's
    // shear leaves alone: this row checks the law's other terms in a sheared wind.
    inflation_pressure_sheared: Inflation, sheared, Some(leaky());
    incidence_pressure_sheared: Incidence, sheared, None;
}

// Inflation pressure at the canopy's speed: held from one draw (in stratified air with a
// vertical wind), evaluated at another; no velocity Jacobian.
force_conformance!(inflation_pressure_canopy_speed, {
    let (tris, q) = grid(3, 2.0);
    let law = InflationPressure::new(&tris, &q, 1.4, &stratified()).with_canopy_speed();
    Case::new(law, q).perturb(0.4).velocities(10.0).trials(20)
});

// The air's added mass: committed at one random draw (its lagged M_a, weights and P_n
// from there, in air whose density varies with height), evaluated at another; its velocity
// Jacobian is all low-rank part.
force_conformance!(added_mass, {
    let (tris, q) = grid(3, 2.0);
    let v = vec![0.5; q.len()];
    Case::new(AddedMass::new(&tris, &q, &v, &stratified()), q)
        .perturb(0.4)
        .velocities(10.0)
        .trials(20)
});

// One triangle sees the flow at normal speed s: exactly edge-on (s = 0), grazing, and on
// either side of a reversal. The law is smooth there (F ∝ (N·u)³ N/(A³|u|_ε)).
force_conformance!(
    triangle_drag_edge_on_and_reversing,
    reversing_case(
        Law::Triangle,
        windy(),
        None,
        &[0.0, 1e-6, -1e-6, 1e-3, -1e-3, 0.3, -0.3],
        14
    )
);
// Through a reversal of the normal flow the leaky law is C¹ (φ ≈ κ s³ near s = 0).
force_conformance!(
    triangle_drag_permeable_reversing,
    reversing_case(
        Law::Triangle,
        stratified(),
        Some(leaky()),
        &[0.0, 1e-3, -1e-3, 0.3, -0.3, 4.0, -4.0],
        14
    )
);
// Every node of one triangle at normal speed ±s: |s| s has a kink in its second derivative
// at 0, so central differences are exact only while h·|∂s/∂dof| < |s|; |s| ≥ 1e-3 with
// h = 1e-6 keeps that.
force_conformance!(
    pressure_drag_reversing,
    reversing_case(Law::Pressure, windy(), None, &[1e-2, -1e-2, 1e-3, -1e-3], 8)
);
force_conformance!(
    pressure_drag_permeable_reversing,
    reversing_case(
        Law::Pressure,
        stratified(),
        Some(leaky()),
        &[1e-2, -1e-2, 1e-3, -1e-3],
        8
    )
);

// Rods: the three-rod network with a joint, nodes displaced by up to 0.3 m, twists up to
// ±3 rad, committed at one random configuration (frames time-parallel transported there,
// reference twists on their branch) and evaluated at another.
fn rod_case(name: &str) -> Case {
    let (mut model, q) = rods();
    let n_pos = 3 * model.layout.n_nodes;
    let n = q.len();
    Case::boxed(take(&mut model, name), q)
        .perturb_dofs(0..n_pos, 0.3)
        .perturb_dofs(n_pos..n, 3.0)
}
force_conformance!(rod_stretch, rod_case("rod-stretch"));
force_conformance!(rod_bend_twist, rod_case("rod-bend-twist"));
// Pulled lines: rest lengths on a schedule, evaluated (t = 0) mid-ramp of a pull, during a
// held lengthening and mid-ramp of a controller's command; the force stays −∇E at fixed t.
force_conformance!(rod_stretch_pulled, {
    let (edges, q) = (
        vec![[0, 1], [1, 2], [2, 3], [3, 4]],
        vec![
            0.0, 0.0, 0.0, 1.0, 0.2, 0.0, 2.0, 0.0, 0.3, 3.0, 0.1, -0.2, 3.5, 1.0, 0.0,
        ],
    );
    let pull = |start: f64, ramp: f64, shorten: f64, hold| Pull {
        start,
        ramp,
        shorten,
        hold,
    };
    let triggered = |ramp: f64, shorten: f64| TriggeredPull {
        pull: pull(f64::INFINITY, ramp, shorten, None),
        source: 0,
        fired: None,
    };
    let schedules = vec![
        RestSchedule {
            pulls: vec![pull(-0.5, 2.0, 0.6, None)],
            command_ramp: 1.0,
            triggered: vec![],
        },
        RestSchedule {
            pulls: vec![pull(-2.0, 0.0, -0.3, Some(5.0))],
            command_ramp: 0.0,
            // Fired mid-ramp, and one not fired (it must add nothing).
            triggered: vec![triggered(0.2, 0.1), triggered(0.0, 0.5)],
        },
    ];
    let part = |schedule, share| Some(Scheduled { schedule, share });
    let scheduled = vec![part(0, 0.4), part(0, 0.6), None, part(1, 1.0)];
    let mut f = Stretch::with_schedules(
        "rod-stretch",
        &edges,
        vec![1.1, 0.9, 1.3, 1.2],
        vec![300.0, 200.0, 250.0, 400.0],
        schedules,
        scheduled,
    );
    let fired = [-0.5, -0.6, 3.0, f64::INFINITY, 0.0, 0.0];
    let history: Vec<f64> = [0.1, 0.3, -0.4, 0.0, 0.0, 0.0]
        .into_iter()
        .chain(fired)
        .collect();
    f.restore_history(&history).unwrap();
    Case::new(f, q).perturb(0.3)
});

// Shells: a 4 × 4 mesh with a curved rest shape, nodes displaced by up to 0.13 m (40 % of
// the spacing).
fn shell_case(name: &str) -> Case {
    let (mut model, q) = shell();
    Case::boxed(take(&mut model, name), q).perturb(0.13)
}
force_conformance!(shell_stretch, shell_case("shell-stretch"));
force_conformance!(shell_bend, shell_case("shell-bend"));

// Constant-strain triangles on the curved 4 × 4 rest shape: nodes displaced by up to 40 %
// of the spacing, then a large homogeneous stretch (0.6–1.6, with shear and inversion of
// some triangles' strain sign), rotation and shift.
force_conformance!(
    shell_cst,
    Case::new(cst().0, cst().1)
        .perturb(0.13)
        .adjust(|rng, q, _| large_deformation(rng, q))
);

// Fabric (orthotropic, warp at 30° and tilted out of the plane), the same draws; with no
// compression (ε_r = 1e-2) most triangles are wrinkled or slack in some draws.
force_conformance!(
    shell_fabric,
    Case::new(fabric(None).0, fabric(None).1)
        .perturb(0.13)
        .adjust(|rng, q, _| large_deformation(rng, q))
);
force_conformance!(
    shell_fabric_no_compression,
    Case::new(fabric(Some(EPS_R)).0, fabric(Some(EPS_R)).1)
        .perturb(0.13)
        .adjust(|rng, q, _| large_deformation(rng, q))
        .trials(12)
);
// One no-compression triangle with its elastic stress placed on both sides of and at the
// transitions (principal values in units of their smoothing width): taut/wrinkled (s₂ near
// 0 with s₁ large)
// and wrinkled/slack and the fully smoothed corner (s₁ near 0).
force_conformance!(
    fabric_wrinkle_transitions,
    Case::new(fabric_triangle().0, fabric_triangle().1)
        .adjust(|rng, q, _| {
            let near = [-4.0, -1.0, -0.2, 0.0, 0.2, 1.0, 4.0];
            if rng.uniform(0.0, 1.0) < 0.5 {
                set_elastic_stress(rng, q, &[5.0, 10.0], &near);
            } else {
                set_elastic_stress(rng, q, &near, &[-10.0, -4.0, -1.0]);
            }
        })
        .trials(30)
);

// Mid-edge bending: the same curved 4 × 4 mesh (nodes by up to 40 % of the spacing, edge
// angles by up to ±0.6 rad), committed and evaluated at independent draws.
fn midedge_case(q_rest: Vec<f64>, amp: f64) -> Case {
    let (force, q) = midedge(4, q_rest);
    Case::new(force, q)
        .perturb_dofs(0..48, amp)
        .perturb_dofs(48..48 + 33, 0.6)
}
force_conformance!(shell_midedge, midedge_case(bumpy_grid(), 0.13));
// Strongly curved rest shapes: rolled to R = 0.4 m (hinges near 50°) and twisted, and
// folded tight (R = 0.2 m: dihedral angles near 100°), small perturbations about them.
force_conformance!(
    shell_midedge_rolled,
    midedge_case(rolled_grid(0.4, 0.5), 0.05)
);
force_conformance!(
    shell_midedge_folded,
    midedge_case(rolled_grid(0.2, 0.0), 0.02)
);

/// One hinge with edge on the x axis, wing A in the z = 0 plane and wing B rotated by one of
/// `alphas` about the edge (θ = α), randomly rotated, translated and scaled so that no
/// coordinate is special; rest angle `rest`.
fn hinge_case(alphas: &'static [f64], rest: f64) -> Case {
    let hinge = Hinge {
        edge: [0, 1],
        opposite: [2, 3],
        faces: [0, 1],
    };
    let force = HingeBending::with_rest_angles("bend", &[hinge], vec![rest], vec![2.5]);
    Case::new(force, vec![0.0; 12]).adjust(move |rng, q, _| {
        let alpha = pick(rng, alphas);
        let pts = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.3, 0.8, 0.0),
            Vector3::new(0.6, -1.1 * alpha.cos(), -1.1 * alpha.sin()),
        ];
        let axis = Vector3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0));
        let rot = Rotation3::from_axis_angle(&Unit::new_normalize(axis), rng.uniform(0.0, 6.0));
        let shift = Vector3::new(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0), 0.5);
        let scale = rng.uniform(0.5, 2.0);
        for (k, x) in pts.iter().enumerate() {
            let y = rot * (x * scale) + shift;
            q[3 * k..3 * k + 3].copy_from_slice(y.as_slice());
        }
    })
}
force_conformance!(hinge_flat, hinge_case(&[0.0], 0.3));
force_conformance!(hinge_nearly_flat, hinge_case(&[1e-5], -0.2));
force_conformance!(hinge_folded, hinge_case(&[PI - 1e-3, -(PI - 1e-3)], 0.0));
// Rest angle across the branch cut: θ − θ̄ is wrapped.
force_conformance!(
    hinge_rest_across_cut,
    hinge_case(&[PI - 1e-3], -(PI - 2e-3))
);
force_conformance!(hinge_bent, hinge_case(&[1.3], 0.4));

// Loads.
force_conformance!(
    gravity,
    Case::new(
        Gravity::new(&[0, 2], &[0.5, 1.5], [0.3, 0.0, -9.81]),
        vec![0.0; 9]
    )
    .perturb(2.0)
    .velocities(3.0)
);
force_conformance!(
    point_forces,
    Case::new(PointForces::new(&[1], &[[2.0, -1.0, 4.0]]), vec![0.0; 6]).perturb(2.0)
);
force_conformance!(
    dof_forces,
    Case::new(
        DofForces::new(vec![1, 4], vec![2.5, -7.0]),
        vec![0.3, -1.2, 0.7, 2.0, 0.1]
    )
    .perturb(1.0)
);
// An edge of length 0.3–3 m at any angle (all four quadrants of φ), any y extent; M up
// to ±50 N·m.
force_conformance!(
    planar_edge_moment,
    Case::new(PlanarEdgeMoment::new(0, 1, -37.0), vec![0.0; 6]).adjust(|rng, q, _| {
        let (len, phi) = (rng.uniform(0.3, 3.0), rng.symmetric(3.1));
        let a = [rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0)];
        let b = [
            a[0] + len * phi.cos(),
            a[1] + rng.symmetric(1.0),
            a[2] + len * phi.sin(),
        ];
        q[..3].copy_from_slice(&a);
        q[3..].copy_from_slice(&b);
    })
);

// Contact: the barrier of every pair kind, with its exact Hessian (the projected one is not a
// derivative; its projection is checked in `contact::tests`).
force_conformance!(self_contact, {
    let (f, q) = contact::self_contact(false);
    Case::new(f, q).perturb(0.2).trials(12)
});
