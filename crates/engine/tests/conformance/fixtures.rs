//! Meshes, rods and fluids the conformance cases are built on.
use std::sync::Arc;

use engine::aero::{Fabric, Fluid, Profile, WindProfile, WindTable};
use engine::conformance::Rng;
use engine::rod::{RodNetwork, RodSpec, Section};
use engine::shell::{install, MidedgeBending, PlateBending, ShellMaterial, TriMesh};
use engine::{DofLayout, Force, Model};
use nalgebra::Vector3;

use crate::mesh::alternating_faces;

/// A fluid with a wind of a few m/s in every direction (drag acts on `v − U∞`).
pub fn windy() -> Fluid {
    Fluid {
        wind: [1.5, -2.0, 0.7],
        ..Fluid::air()
    }
}

/// [`windy`] air whose density falls by e every 0.8 m (`ρ = 1.225 exp(−z/0.8)`): over the
/// ±0.4–2 m of the random draws ρ changes by a factor 1.6–12, so the `∂ρ/∂z` terms are
/// of the size of every other Jacobian entry.
pub fn stratified() -> Fluid {
    Fluid {
        profile: Profile::Exponential { scale_height: 0.8 },
        ..windy()
    }
}

/// [`stratified`] air whose wind turns and changes by 2–3 m/s per metre of height (a table
/// with rows inside the draws' heights, ±0.4–2 m), so the shear terms `(∂F/∂u) dU/dz` are of
/// the size of every other Jacobian entry, beside the density's.
pub fn sheared() -> Fluid {
    let rows = [
        [-3.0, -4.0, 1.0],
        [-1.0, 1.5, -2.0],
        [0.3, 4.0, 2.5],
        [1.2, 2.0, 5.0],
        [3.0, -1.0, 3.0],
    ];
    let table = WindTable::try_new(&rows).expect("a valid table");
    Fluid {
        wind_profile: WindProfile::Table(Arc::new(table)),
        ..stratified()
    }
}

/// [`windy`] air under the power law `U ∝ h^0.3` over a ground 3 m below the origin.
pub fn power_law() -> Fluid {
    Fluid {
        wind_profile: WindProfile::Power {
            reference_height: 3.0,
            exponent: 0.3,
            ground: -3.0,
        },
        ..windy()
    }
}

/// [`windy`] air under the logarithmic law (roughness 0.1 m) over a ground 3 m below the
/// origin.
pub fn log_law() -> Fluid {
    Fluid {
        wind_profile: WindProfile::Log {
            reference_height: 3.0,
            roughness: 0.1,
            ground: -3.0,
        },
        ..windy()
    }
}

/// A fabric that lets a large share of the normal flow through at the draws' speeds: at
/// 10 m/s, `a = μh/k ≈ 20 Pa·s/m` and `b = ρ C_F h/√k ≈ 13 kg/m³` give `u_p ≈ 2 m/s`.
pub fn leaky() -> Fabric {
    Fabric::new(1e-4, 9e-11, 1.0)
}

/// An `n × n`-node grid of side `side` (m) in the plane z = 0, cells split along
/// alternating diagonals: `(triangles, q)`.
pub fn grid(n: usize, side: f64) -> (Vec<[usize; 3]>, Vec<f64>) {
    let faces = alternating_faces(n);
    let h = side / (n - 1) as f64;
    let q = (0..n * n)
        .flat_map(|k| [(k % n) as f64 * h, (k / n) as f64 * h, 0.0])
        .collect();
    (faces, q)
}

/// Take the force named `name` out of `model`.
pub fn take(model: &mut Model, name: &str) -> Box<dyn Force> {
    let i = model
        .forces
        .iter()
        .position(|f| f.name() == name)
        .unwrap_or_else(|| panic!("no force `{name}`"));
    model.forces.remove(i)
}

/// A 4 × 4-node shell with a curved rest shape (the unit square perturbed by ±0.05 m) and
/// its forces: `(model, q_rest)`.
pub fn shell() -> (Model, Vec<f64>) {
    let (faces, flat) = grid(4, 1.0);
    let mut rng = Rng::new(7);
    let q_rest: Vec<f64> = flat.iter().map(|x| x + rng.symmetric(0.05)).collect();
    let mesh = TriMesh::from_q(faces, &q_rest, 16).expect("valid mesh");
    let mat = ShellMaterial {
        youngs_modulus: 1e9,
        thickness: 1e-3,
        density: 1000.0,
    };
    let mut model = Model::new(DofLayout::new(16, 0));
    install(&mesh, &mat, &mut model, &q_rest).expect("mesh fits");
    (model, q_rest)
}

/// First twist DOF of the rod network (the layout has spare twists before it).
pub const TWIST_OFFSET: usize = 2;

/// Rod A along x (rectangular), rod B leaving node 2 along y, rod C arriving at node 2
/// from below; 9 nodes, 8 edges, rest shape gently curved so that κ̄ ≠ 0. At node 2 edges
/// enter the bend–twist stencils reversed (all four sign combinations occur).
/// `(model, q_rest)`.
pub fn rods() -> (Model, Vec<f64>) {
    let pts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.1, 0.0],
        [2.0, 0.0, 0.15],
        [3.0, -0.1, 0.1],
        [4.0, 0.0, 0.0],
        [2.1, 1.0, 0.2],
        [2.0, 2.0, 0.1],
        [1.9, -0.2, -2.0],
        [2.0, 0.1, -1.0],
    ];
    let rect = Section::Rectangle {
        width: 0.08,
        height: 0.02,
    };
    let mut net = RodNetwork::new();
    net.add_rod(
        RodSpec::new(vec![0, 1, 2, 3, 4], rect, 2e5, 8e4, 1.0).with_first_director([0.0, 1.0, 0.0]),
    );
    net.add_rod(RodSpec::new(
        vec![2, 5, 6],
        Section::Circle { radius: 0.03 },
        3e5,
        1e5,
        1.0,
    ));
    net.add_rod(RodSpec::new(vec![7, 8, 2], rect, 1e5, 5e4, 1.0));
    let layout = DofLayout::new(pts.len(), TWIST_OFFSET + net.n_edges() + 1);
    let mut q = vec![0.0; layout.len()];
    for (i, p) in pts.iter().enumerate() {
        q[3 * i..3 * i + 3].copy_from_slice(p);
    }
    let mut model = Model::new(layout);
    let h = net
        .install(&mut model, &q, TWIST_OFFSET)
        .expect("valid network");
    // 3 in-rod pairs on A, 1 on B, 1 on C; at node 2 the 4 edge ends give 6 pairs, one
    // of them in-rod (A), so 5 joint pairs.
    assert_eq!(h.n_bend_twist, 3 + 1 + 1 + 5);
    (model, q)
}

/// Unit normal of triangle `t` at `q`.
pub fn normal(q: &[f64], t: [usize; 3]) -> [f64; 3] {
    let p = |i: usize| Vector3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2]);
    let n = (p(t[1]) - p(t[0])).cross(&(p(t[2]) - p(t[0]))).normalize();
    [n.x, n.y, n.z]
}

/// Shift the velocities of triangle `t`'s nodes along its normal so that the relative mean
/// velocity (`wind` subtracted) has normal component exactly `s` (m/s).
pub fn set_mean_normal_speed(q: &[f64], v: &mut [f64], t: [usize; 3], wind: [f64; 3], s: f64) {
    let n = normal(q, t);
    let cur: f64 = (0..3)
        .map(|k| {
            let u = (v[3 * t[0] + k] + v[3 * t[1] + k] + v[3 * t[2] + k]) / 3.0;
            (u - wind[k]) * n[k]
        })
        .sum();
    for &i in &t {
        for k in 0..3 {
            v[3 * i + k] += (s - cur) * n[k];
        }
    }
}

/// Give every node of triangle `t` the relative normal velocity `s` (m/s).
pub fn set_node_normal_speeds(q: &[f64], v: &mut [f64], t: [usize; 3], wind: [f64; 3], s: f64) {
    let n = normal(q, t);
    for &i in &t {
        let cur: f64 = (0..3).map(|k| (v[3 * i + k] - wind[k]) * n[k]).sum();
        for k in 0..3 {
            v[3 * i + k] += (s - cur) * n[k];
        }
    }
}

/// One of `values`, uniformly.
pub fn pick(rng: &mut Rng, values: &[f64]) -> f64 {
    values[(rng.next_u64() % values.len() as u64) as usize]
}

/// Mid-edge bending on the `n × n`-node grid of side `side` (m) with rest shape `q_rest`
/// (ν = 0.3, E h³ of a 1 mm, 1 GPa sheet); the edge angles follow the nodes in `q`:
/// `(force, q_rest with ψ = 0 appended)`.
pub fn midedge(n: usize, q_rest: Vec<f64>) -> (MidedgeBending, Vec<f64>) {
    let (faces, _) = grid(n, 1.0);
    let mesh = TriMesh::from_q(faces, &q_rest, n * n).expect("valid mesh");
    let plate = PlateBending {
        youngs_modulus: 1e9,
        poisson_ratio: 0.3,
        thickness: 1e-3,
    };
    let force = MidedgeBending::new("shell-midedge", &mesh, &q_rest, &plate, 3 * n * n);
    let mut q = q_rest;
    q.resize(3 * n * n + mesh.edges.len(), 0.0);
    (force, q)
}

/// The 4 × 4 unit grid perturbed by ±0.05 m (the hinge shells' curved rest shape).
pub fn bumpy_grid() -> Vec<f64> {
    let (_, flat) = grid(4, 1.0);
    let mut rng = Rng::new(7);
    flat.iter().map(|x| x + rng.symmetric(0.05)).collect()
}

/// The 4 × 4 unit grid wrapped onto a cylinder of radius `r` (m) about the y axis, and
/// twisted by `twist` (rad/m) about x: a strongly curved rest shape.
pub fn rolled_grid(r: f64, twist: f64) -> Vec<f64> {
    let (_, flat) = grid(4, 1.0);
    flat.chunks(3)
        .flat_map(|p| {
            let (x, y) = (p[0] - 0.5, p[1] - 0.5);
            let phi = x / r;
            [r * phi.sin(), y, r * (1.0 - phi.cos()) + twist * x * y]
        })
        .collect()
}
