//! Mid-edge bending against plate theory on the three rectangle patterns (the set-ups of
//! `chute::verify::midedge_cases`, shared with `chute validate`, which also runs the finer
//! meshes and shows the hinges' numbers beside them).
use chute::verify::midedge_cases::{
    cylinder_density, cylinder_reference, observed_order, plate_deflection, plate_pressure,
    plate_reference, Law, PATTERNS, PLATE,
};

#[test]
fn cylinder_energy_on_every_pattern() {
    // Nodes on the cylinder, edge angles relaxed: the faces' chord-vs-arc error is
    // O((ℓ/R)²) = 2.5e-3 at ℓ = 5 cm, R = 1 m.
    let (ell, r): (f64, f64) = (0.05, 1.0);
    let reference = cylinder_reference(r);
    for (pattern, name) in PATTERNS {
        for axis_x in [true, false] {
            let e = cylinder_density(pattern, ell, r, axis_x).unwrap();
            let err = (e - reference).abs() / reference;
            println!("cylinder {name} axis_x {axis_x}: {e:.6e} vs {reference:.6e}: {err:.2e}");
            assert!(err < (ell / r).powi(2), "{name}: {e} vs {reference}");
        }
    }
}

#[test]
fn simply_supported_plate_converges_at_second_order_on_every_pattern() {
    // Navier centre deflection with D = E h³/(12(1 − ν²)); meshes 8 × 8 and 16 × 16. The
    // error is ≈ 3.2 (1/n)² on every pattern (chute validate's ladder to 32 × 32), so the
    // 16 × 16 mesh must be within 4/n² and the refinement must show order 2 ± 0.3.
    let p = plate_pressure();
    let reference = plate_reference(p, PLATE.stiffness());
    for (pattern, name) in PATTERNS {
        let w = [8, 16].map(|n| plate_deflection(pattern, n, Law::Midedge, p).unwrap());
        let e = w.map(|w| (w - reference) / reference);
        let order = observed_order(e[0], e[1]);
        println!("plate {name}: errors {e:?}, order {order:.3}");
        assert!(e[1].abs() < 4.0 / 256.0, "{name}: {e:?}");
        assert!((order - 2.0).abs() < 0.3, "{name}: order {order}");
    }
}
