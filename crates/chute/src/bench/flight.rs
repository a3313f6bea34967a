//! The whole-flight and robustness rungs of `chute bench` (docs/performance.md): `flight-1k`, the
//! report's 4-site canopy at its converged mesh flying 10 s at the report's 1 ms step with
//! default settings (the real-time target: ≤ 10 s wall), and `cross-613`, the report's Kevlar
//! canopy on the 613-node cross mesh under the DisMech pressure drag at dt = 1e-2 s (the case
//! on which modified Newton used to give up and halve the step; target: no halving).

use super::{case, Case};

/// `flight-1k`: 1,225 nodes (edge 0.125 m, the scenario's default), 10,000 steps from rest,
/// no warm-up: the whole flight is the measurement.
pub fn flight() -> Case {
    case(
        "flight-1k",
        "shell",
        &["canopy.edge_length_m=0.125"],
        0,
        10_000,
    )
}

/// `large-canopy` (only by `--case`): a 30-gore flat circular canopy of a troop
/// parachute's size (radius 5.3 m, 0.6 m edges, 30 lines of 7.77 m, 1,600 N) in
/// `round-fabric`'s fabric and inflation pressure, its first 3 s from the flat start at
/// dt = 1 ms: the hardest opening measured (docs/performance.md §Targets).
pub fn large_canopy() -> Case {
    case(
        "large-canopy",
        "round",
        &[
            "canopy.radius_m=5.3",
            "canopy.edge_length_m=0.6",
            "load.weight_n=1600",
            "load.rim_site_count=30",
            "lines.length_m=7.77",
        ],
        0,
        3_000,
    )
}

/// `cross-613`: 0.25 m cells split into four triangles through a centre node (613 nodes),
/// pressure drag, the corner point forces of the scenario, 1 s at dt = 1e-2 s from rest.
pub fn cross() -> Case {
    case(
        "cross-613",
        "shell",
        &[
            "canopy.mesh_pattern=cross",
            "canopy.edge_length_m=0.25",
            "fluid.shell_drag=pressure",
            "time.dt_s=1e-2",
        ],
        0,
        100,
    )
}
