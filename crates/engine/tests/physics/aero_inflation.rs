//! The inflation-pressure law against its closed forms: the pressure is the same on every
//! panel whatever its angle to the flow, and on a uniform flow the resultant over any surface
//! is `Δp` times the vector area bounded by its rim (Σ N_t telescopes to ½ ∮ x × dx), so a
//! dome whose rim stays in a plane feels exactly the flat canopy's force, normal to the rim's
//! plane, whatever the flow's horizontal part. Only the descent `w = max(0, −u_z)` inflates.
//! Exact identities: round-off tolerance.
use engine::aero::{resultant, Fluid, InflationPressure, Profile, TriangleDrag};
use engine::force::Force;
use engine::reference::sheet;
use engine::DofLayout;
use rand::{rngs::StdRng, Rng, SeedableRng};

const CP: f64 = 1.4;

/// A 2 × 1 m sheet at z = 0 (5 × 3 nodes) whose interior nodes are lifted by random heights
/// up to 0.8 m and moved sideways by up to 0.2 m; the rim stays on the rectangle.
fn dome(rng: &mut StdRng) -> (sheet::Sheet, Vec<f64>) {
    let s = sheet::sheet(5, 3, 2.0, 1.0, 0.0);
    let mut q = s.q.clone();
    for p in q.chunks_mut(3) {
        let rim = p[0].abs() < 1e-12
            || (p[0] - 2.0).abs() < 1e-12
            || p[1].abs() < 1e-12
            || (p[1] - 1.0).abs() < 1e-12;
        if !rim {
            p[0] += rng.random_range(-0.2..0.2);
            p[1] += rng.random_range(-0.2..0.2);
            p[2] += rng.random_range(0.0..0.8);
        }
    }
    (s, q)
}

fn uniform(n: usize, vel: [f64; 3]) -> Vec<f64> {
    (0..n).flat_map(|_| vel).collect()
}

#[test]
fn dome_with_a_flat_rim_feels_the_projected_area_from_any_flow_direction() {
    let rho = Fluid::air().density;
    let mut rng = StdRng::seed_from_u64(7);
    for trial in 0..10 {
        let (s, q) = dome(&mut rng);
        let law = InflationPressure::new(&s.tris, &s.q, CP, &Fluid::air());
        let vel = [
            rng.random_range(-6.0..6.0),
            rng.random_range(-6.0..6.0),
            rng.random_range(-6.0..-0.5),
        ];
        let w2 = vel[2] * vel[2];
        let f = resultant(
            &law,
            &DofLayout::new(s.n_nodes, 0),
            &q,
            &uniform(s.n_nodes, vel),
        );
        // Rectangle 2 m × 1 m: vector area (0, 0, 2); Δp = C_p ½ ρ w², w = −u_z.
        let want = [0.0, 0.0, CP * 0.5 * rho * w2 * 2.0];
        for k in 0..3 {
            assert!(
                (f[k] - want[k]).abs() <= 1e-12 * want[2],
                "trial {trial}: {f:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn a_side_panel_edge_on_to_the_descent_keeps_its_pressure_unlike_the_panel_law() {
    // The flat sheet (σ fixed flat) turned vertical, its normal along −y, descending at
    // 5 m/s: the report law's normal drag vanishes edge-on, the inflation pressure pushes the
    // panel outwards along σ N with the full ½ ρ C_p w² A, as on the side of a deep canopy.
    let s = sheet::sheet(3, 2, 2.0, 1.0, 0.0);
    let layout = DofLayout::new(s.n_nodes, 0);
    let q: Vec<f64> = s.q.chunks(3).flat_map(|p| [p[0], 0.0, p[1]]).collect();
    let v = uniform(s.n_nodes, [0.0, 0.0, -5.0]);
    let rho = Fluid::air().density;
    let infl = InflationPressure::new(&s.tris, &s.q, CP, &Fluid::air());
    let f = resultant(&infl, &layout, &q, &v);
    let want = CP * 0.5 * rho * 25.0 * 2.0;
    assert!((f[1] + want).abs() <= 1e-12 * want, "{f:?} vs −{want}");
    assert!(
        f[0].abs() <= 1e-12 * want && f[2].abs() <= 1e-12 * want,
        "{f:?}"
    );
    let panel = TriangleDrag::new(&s.tris, CP, 0.0, &Fluid::air());
    let g = resultant(&panel, &layout, &q, &v);
    assert!(
        g.iter().all(|x| x.abs() < 1e-9),
        "report law edge-on: {g:?}"
    );
}

#[test]
fn a_horizontal_wind_or_a_rising_canopy_does_not_inflate() {
    // At rest in a 2 m/s crosswind (the start of a drop in wind), and rising at 1 m/s: no
    // descent through the air, no pressure (the report law would push on the rising sheet).
    let s = sheet::sheet(3, 2, 2.0, 1.0, 0.0);
    let layout = DofLayout::new(s.n_nodes, 0);
    let windy = Fluid {
        wind: [0.0, 2.0, 0.0],
        ..Fluid::air()
    };
    let at_rest = uniform(s.n_nodes, [0.0, 0.0, 0.0]);
    let f = resultant(
        &InflationPressure::new(&s.tris, &s.q, CP, &windy),
        &layout,
        &s.q,
        &at_rest,
    );
    assert_eq!(f, [0.0; 3]);
    let rising = uniform(s.n_nodes, [0.3, 0.0, 1.0]);
    let infl = InflationPressure::new(&s.tris, &s.q, CP, &Fluid::air());
    assert_eq!(resultant(&infl, &layout, &s.q, &rising), [0.0; 3]);
}

#[test]
fn orientation_is_fixed_at_rest_so_flipping_a_triangle_changes_nothing() {
    // The same sheet with every triangle's node order reversed (normals pointing down): σ
    // flips with it, so the force is identical, and it points up (the inside faces −z).
    let s = sheet::sheet(3, 2, 2.0, 1.0, 0.0);
    let flipped: Vec<[usize; 3]> = s.tris.iter().map(|t| [t[0], t[2], t[1]]).collect();
    let layout = DofLayout::new(s.n_nodes, 0);
    let v = uniform(s.n_nodes, [0.0, 0.0, -3.0]);
    let a = resultant(
        &InflationPressure::new(&s.tris, &s.q, CP, &Fluid::air()),
        &layout,
        &s.q,
        &v,
    );
    let b = resultant(
        &InflationPressure::new(&flipped, &s.q, CP, &Fluid::air()),
        &layout,
        &s.q,
        &v,
    );
    assert_eq!(a, b);
    assert!(a[2] > 0.0, "{a:?}");
}

#[test]
fn the_canopy_speed_is_the_panel_speed_of_a_uniform_motion_and_a_fold_moving_alone_keeps_it() {
    // Moving together, every triangle's own speed is the canopy's: the same force. One node
    // then moving down alone changes each panel's own speed but barely the canopy's: the
    // held law keeps its pressure (the panel law's rises on the panels round that node).
    let mut rng = StdRng::seed_from_u64(3);
    let (s, q) = dome(&mut rng);
    let layout = DofLayout::new(s.n_nodes, 0);
    let mut v = uniform(s.n_nodes, [1.0, -2.0, -5.0]);
    let own = InflationPressure::new(&s.tris, &s.q, CP, &Fluid::air());
    let mut held = InflationPressure::new(&s.tris, &s.q, CP, &Fluid::air()).with_canopy_speed();
    held.begin_step(&q, &v, 1e-3);
    let (a, b) = (
        resultant(&own, &layout, &q, &v),
        resultant(&held, &layout, &q, &v),
    );
    for k in 0..3 {
        assert!((a[k] - b[k]).abs() <= 1e-12 * a[2].abs(), "{a:?} vs {b:?}");
    }
    v[3 * 7 + 2] = -25.0;
    let (c, d) = (
        resultant(&own, &layout, &q, &v),
        resultant(&held, &layout, &q, &v),
    );
    assert!(
        c[2] > 1.5 * a[2],
        "the panel law feels the node: {c:?} vs {a:?}"
    );
    assert_eq!(b, d, "held over the step");
}

#[test]
fn the_canopy_speeds_lag_coupling_completes_its_jacobian() {
    let mut rng = StdRng::seed_from_u64(5);
    let stratified = Fluid {
        profile: Profile::Exponential { scale_height: 0.8 },
        wind: [1.0, 2.0, 0.0],
        ..Fluid::air()
    };
    for (trial, air) in [Fluid::air(), stratified].into_iter().enumerate() {
        let (s, q) = dome(&mut rng);
        let v: Vec<f64> = (0..q.len())
            .map(|d| rng.random_range(-3.0..3.0) - if d % 3 == 2 { 6.0 } else { 0.0 })
            .collect();
        let mut law = InflationPressure::new(&s.tris, &s.q, CP, &air).with_canopy_speed();
        super::aero_incidence::assert_lag_coupling_completes(
            &mut law,
            &q,
            &v,
            &format!("air {trial}"),
        );
    }
}
