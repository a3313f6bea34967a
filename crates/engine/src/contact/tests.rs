//! The contact pieces against finite differences and brute force, on random configurations.

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use super::ad::{variables, V};
use super::barrier::{pair, project_psd, Barrier};
use super::distance::{edge_edge, of_pair, point_triangle, Pair};

fn random_points(rng: &mut StdRng) -> [f64; 12] {
    std::array::from_fn(|_| rng.random_range(-1.0..1.0))
}

fn points(x: &[f64; 12]) -> [V<f64>; 4] {
    std::array::from_fn(|k| [x[3 * k], x[3 * k + 1], x[3 * k + 2]])
}

/// Central differences of the squared distance of `kind` (step 1e-6 on unit-size
/// coordinates: truncation ~1e-12, round-off ~1e-10 relative) against the AD gradient, and
/// of the AD gradient against the AD Hessian.
fn check_derivatives(kind: Pair, x: &[f64; 12]) {
    let d = of_pair(kind, &variables(x));
    let h = 1e-6;
    for i in 0..12 {
        let (mut xp, mut xm) = (*x, *x);
        xp[i] += h;
        xm[i] -= h;
        let fp = of_pair(kind, &variables(&xp));
        let fm = of_pair(kind, &variables(&xm));
        let scale = 1.0 + d.g.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        let fd = (fp.v - fm.v) / (2.0 * h);
        assert!(
            (fd - d.g[i]).abs() < 1e-6 * scale,
            "{kind:?} ∂{i}: {fd} vs {}",
            d.g[i]
        );
        let hscale = 1.0 + d.h.iter().flatten().fold(0.0f64, |m, g| m.max(g.abs()));
        for j in 0..12 {
            let fd = (fp.g[j] - fm.g[j]) / (2.0 * h);
            assert!(
                (fd - d.h[i][j]).abs() < 1e-5 * hscale,
                "{kind:?} ∂²{i}{j}: {fd} vs {}",
                d.h[i][j]
            );
        }
    }
}

type PairOut = (f64, [f64; 12], [f64; 144]);

/// Central differences (step 1e-7) of a pair's energy against its gradient `g` and of its
/// gradient against its Hessian `h` at `x0`.
fn check_pair(
    x0: &[f64; 12],
    energy: impl Fn(&[f64; 12]) -> PairOut,
    (g, h): ([f64; 12], [f64; 144]),
) {
    let step = 1e-7;
    for i in 0..12 {
        let (mut xp, mut xm) = (*x0, *x0);
        xp[i] += step;
        xm[i] -= step;
        let ((ep, gp, _), (em, gm, _)) = (energy(&xp), energy(&xm));
        let fd = (ep - em) / (2.0 * step);
        assert!(
            (fd - g[i]).abs() < 1e-6 * (1.0 + g[i].abs()),
            "∂{i}: {fd} vs {}",
            g[i]
        );
        for j in 0..12 {
            let fd = (gp[j] - gm[j]) / (2.0 * step);
            let want = h[12 * i + j];
            assert!(
                (fd - want).abs() < 1e-5 * (1.0 + want.abs()),
                "∂²{i}{j}: {fd} vs {want}"
            );
        }
    }
}

#[test]
fn every_feature_pair_has_its_exact_gradient_and_hessian() {
    let mut rng = StdRng::seed_from_u64(7);
    let kinds = [
        Pair::PointPoint(0, 2),
        Pair::PointLine(0, 1, 3),
        Pair::PointLine(3, 0, 1),
        Pair::PointPlane,
        Pair::LineLine,
    ];
    for _ in 0..20 {
        let x = random_points(&mut rng);
        for kind in kinds {
            check_derivatives(kind, &x);
        }
    }
}

/// The squared distance between two convex sets sampled densely (a 200 × 200 barycentric grid
/// on a triangle, 2000 points on each edge) is at least the true one and exceeds it by at most
/// the sampling step's share.
#[test]
fn the_picked_pair_is_the_true_distance() {
    let mut rng = StdRng::seed_from_u64(11);
    for _ in 0..30 {
        let x = points(&random_points(&mut rng));
        let (_, d) = point_triangle(&x);
        let mut best = f64::MAX;
        let n = 200;
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let q: [f64; 3] = std::array::from_fn(|k| {
                    x[1][k] + u * (x[2][k] - x[1][k]) + v * (x[3][k] - x[1][k])
                });
                best = best.min((0..3).map(|k| (x[0][k] - q[k]).powi(2)).sum());
            }
        }
        assert!(
            d <= best + 1e-12 && best.sqrt() - d.sqrt() < 2e-2,
            "{d} vs {best}"
        );
        let (_, d) = edge_edge(&x);
        let mut best = f64::MAX;
        let m = 2000;
        for i in 0..=m {
            let s = i as f64 / m as f64;
            let a: [f64; 3] = std::array::from_fn(|k| x[0][k] + s * (x[1][k] - x[0][k]));
            // The nearest point of the second edge to `a`, exactly.
            let e: [f64; 3] = std::array::from_fn(|k| x[3][k] - x[2][k]);
            let t = ((0..3).map(|k| (a[k] - x[2][k]) * e[k]).sum::<f64>()
                / (0..3).map(|k| e[k] * e[k]).sum::<f64>())
            .clamp(0.0, 1.0);
            best = best.min((0..3).map(|k| (a[k] - x[2][k] - t * e[k]).powi(2)).sum());
        }
        assert!(
            d <= best + 1e-12 && best.sqrt() - d.sqrt() < 2e-3,
            "{d} vs {best}"
        );
    }
}

#[test]
fn a_point_over_a_face_is_measured_to_its_plane_and_beside_it_to_an_edge() {
    let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let over = [[0.2, 0.3, 0.5], tri[0], tri[1], tri[2]];
    assert_eq!(point_triangle(&over), (Pair::PointPlane, 0.25));
    let beside = [[0.5, -0.4, 0.3], tri[0], tri[1], tri[2]];
    let (kind, d) = point_triangle(&beside);
    assert_eq!(kind, Pair::PointLine(0, 1, 2));
    assert!((d - 0.25).abs() < 1e-15);
    let crossing = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, -0.5, 0.2],
        [0.5, 0.5, 0.2],
    ];
    let (kind, d) = edge_edge(&crossing);
    assert_eq!(kind, Pair::LineLine);
    assert!((d - 0.04).abs() < 1e-15);
}

/// b, b′, b″ against central differences; all three vanish at d̂ (C² activation); the energy
/// grows without bound as the distance closes.
#[test]
fn the_barrier_is_c2_at_its_threshold_and_unbounded_at_contact() {
    let b = Barrier {
        d_hat: 1e-2,
        kappa: 3.0,
    };
    for d in [1e-6, 1e-4, 3e-3, 9e-3] {
        let h = 1e-7 * d;
        let [_, b1, b2] = b.eval(d);
        let (p, m) = (b.eval(d + h), b.eval(d - h));
        assert!(
            ((p[0] - m[0]) / (2.0 * h) - b1).abs() < 1e-6 * b1.abs().max(1.0),
            "{d}"
        );
        assert!(
            ((p[1] - m[1]) / (2.0 * h) - b2).abs() < 1e-5 * b2.abs().max(1.0),
            "{d}"
        );
    }
    assert_eq!(b.eval(1e-2), [0.0; 3]);
    let near = b.eval(1e-2 * (1.0 - 1e-6));
    assert!(near[0].abs() < 1e-15 && near[1].abs() < 1e-10 && near[2].abs() < 1e-4);
    assert!(b.eval(1e-12)[0] > b.eval(1e-8)[0] && b.eval(1e-8)[0] > b.eval(1e-4)[0]);
}

/// A pair's gradient and Hessian against differences of its energy and gradient, and the
/// projection: its eigenvalues are ≥ 0, and a definite matrix is left as it is.
#[test]
fn a_pair_has_the_derivatives_of_its_energy_and_a_definite_projection() {
    let barrier = Barrier {
        d_hat: 0.09,
        kappa: 1.0,
    };
    let x0 = [0.2, 0.3, 0.15, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let (e, g, h) = pair(&barrier, Pair::PointPlane, &x0, None).expect("active at 0.15 m");
    assert!(e > 0.0);
    check_pair(
        &x0,
        |x| pair(&barrier, Pair::PointPlane, x, None).unwrap(),
        (g, h),
    );
    let mut p = h;
    project_psd(&mut p);
    let eig = nalgebra::SymmetricEigen::new(nalgebra::SMatrix::<f64, 12, 12>::from_row_slice(&p));
    assert!(eig
        .eigenvalues
        .iter()
        .all(|&l| l > -1e-12 * eig.eigenvalues.amax()));
    let mut definite = [0.0; 144];
    for i in 0..12 {
        definite[13 * i] = 1.0 + i as f64;
    }
    let before = definite;
    project_psd(&mut definite);
    assert_eq!(definite, before);
    assert!(pair(
        &barrier,
        Pair::PointPlane,
        &{
            let mut far = x0;
            far[2] = 0.31;
            far
        },
        None
    )
    .is_none());
}

/// The triangles and edges of an `n × n` grid of nodes numbered row by row from `first`:
/// two triangles per cell, its two sides and one diagonal as edges.
fn add_grid(s: &mut super::broad::Surface, n: usize, first: usize) {
    let id = |i: usize, j: usize| first + i * n + j;
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            s.triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            s.triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            s.edges
                .extend([[id(i, j), id(i + 1, j)], [id(i, j), id(i, j + 1)]]);
            s.edges.push([id(i, j), id(i + 1, j + 1)]);
        }
    }
}

/// A crumpled sheet (a 9 × 9 grid of unit cells, nodes moved randomly by up to a cell): every
/// point–triangle and edge–edge pair closer than the reach, found by brute force over all
/// pairs, is a candidate, and the candidates are far fewer than all pairs.
#[test]
fn the_broad_phase_finds_every_pair_within_reach() {
    use super::broad::{candidates, Candidate, Surface};
    let mut rng = StdRng::seed_from_u64(3);
    let n = 10;
    let mut x = Vec::new();
    for i in 0..n {
        for j in 0..n {
            x.extend([
                i as f64 + rng.random_range(-0.5..0.5),
                j as f64 + rng.random_range(-0.5..0.5),
                rng.random_range(-1.0..1.0),
            ]);
        }
    }
    let mut s = Surface::default();
    add_grid(&mut s, n, 0);
    s.points = (0..n * n).collect();
    let reach = 0.3;
    let found: std::collections::HashSet<Candidate> =
        candidates(&s, &x, reach).into_iter().collect();
    let at =
        |ids: [usize; 4]| -> [V<f64>; 4] { ids.map(|k| [x[3 * k], x[3 * k + 1], x[3 * k + 2]]) };
    let (mut close, mut all) = (0, 0);
    for &p in &s.points {
        for t in &s.triangles {
            if t.contains(&p) {
                continue;
            }
            all += 1;
            let ids = [p, t[0], t[1], t[2]];
            if point_triangle(&at(ids)).1 < reach * reach {
                close += 1;
                assert!(found.contains(&Candidate::PointTriangle(ids)), "{ids:?}");
            }
        }
    }
    for (i, a) in s.edges.iter().enumerate() {
        for b in &s.edges[i + 1..] {
            if a.iter().any(|k| b.contains(k)) {
                continue;
            }
            all += 1;
            let ids = [a[0], a[1], b[0], b[1]];
            if edge_edge(&at(ids)).1 < reach * reach {
                close += 1;
                assert!(found.contains(&Candidate::EdgeEdge(ids)), "{ids:?}");
            }
        }
    }
    assert!(close > 20, "the crumple brings {close} pairs within reach");
    assert!(
        found.len() < all / 20,
        "{} candidates of {all} pairs",
        found.len()
    );
}

/// Nearly parallel edges: the mollified energy has the derivatives of its value (FD), and it
/// joins the unmollified one with a continuous gradient where |ea × eb|² crosses εx.
#[test]
fn the_edge_mollifier_is_smooth_and_exact() {
    let barrier = Barrier {
        d_hat: 0.04,
        kappa: 1.0,
    };
    // Edge a along x; edge b 0.1 above it, turned by angle θ about z, crossing over a's middle.
    let at = |theta: f64| -> [f64; 12] {
        let (c, s) = (theta.cos(), theta.sin());
        [
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            0.5 - 0.5 * c,
            -0.5 * s,
            0.1,
            0.5 + 0.5 * c,
            0.5 * s,
            0.1,
        ]
    };
    let eps = 1e-3; // |ea|² |eb|² = 1
    let energy = |x: &[f64; 12]| pair(&barrier, Pair::LineLine, x, Some(eps)).unwrap();
    let x0 = at(0.02); // c = sin²θ = 4e-4 < εx: mollified
    let (_, g, h) = energy(&x0);
    check_pair(&x0, energy, (g, h));
    // Across c = εx (θ = asin √εx) the energy and its gradient are continuous.
    let theta = eps.sqrt().asin();
    let (below, above) = (energy(&at(theta - 1e-9)), energy(&at(theta + 1e-9)));
    assert!((below.0 - above.0).abs() < 1e-9 * above.0.abs());
    for i in 0..12 {
        assert!(
            (below.1[i] - above.1[i]).abs() < 1e-6 * (1.0 + above.1[i].abs()),
            "∂{i}"
        );
    }
    // Exactly parallel (measured from an endpoint, the line–line formula being 0/0), the
    // energy is zero: the endpoints' own pairs hold such edges apart.
    let parallel = at(0.0);
    let (kind, d) = edge_edge(&points(&parallel));
    assert!(
        kind != Pair::LineLine && (d - 0.01).abs() < 1e-15,
        "{kind:?} {d}"
    );
    let (e, g, _) = pair(&barrier, kind, &parallel, Some(eps)).unwrap();
    assert!(e == 0.0 && g.iter().all(|v| v.is_finite()));
}

/// The additive CCD bound, on straight-line motions: along the path up to the returned step
/// (sampled every 1/2000), the pair's distance never falls below the fraction s of its start;
/// a point shot through a triangle stops short of the plane; a motion that never closes the
/// pair gets the whole step.
#[test]
fn the_ccd_step_keeps_every_pair_apart() {
    use super::ccd::{max_step, Stencil};
    let s = 0.2;
    let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let x = [[0.2, 0.2, 0.5], tri[0], tri[1], tri[2]];
    let mut dx = [[0.0; 3]; 4];
    dx[0] = [0.0, 0.0, -1.0]; // reaches the plane at t = 0.5
    let t = max_step(Stencil::PointTriangle, &x, &dx, s, 1.0);
    assert!(t > 0.3 && t < 0.5, "{t}");
    assert!(
        0.5 - t >= s * 0.5 - 1e-12,
        "stays {} from the plane",
        0.5 - t
    );
    dx[0] = [1.0, 0.0, 0.0]; // sideways: never closer than its start
    assert_eq!(max_step(Stencil::PointTriangle, &x, &dx, s, 1.0), 1.0);
    let mut rng = StdRng::seed_from_u64(5);
    for case in 0..200 {
        let x = points(&random_points(&mut rng));
        let dx = points(&random_points(&mut rng)).map(|p| p.map(|c| 2.0 * c));
        for kind in [
            Stencil::PointTriangle,
            Stencil::EdgeEdge,
            Stencil::PointEdge,
        ] {
            let dist = |y: &[V<f64>; 4]| match kind {
                Stencil::PointTriangle => point_triangle(y).1.sqrt(),
                Stencil::EdgeEdge => edge_edge(y).1.sqrt(),
                Stencil::PointEdge => super::distance::point_edge(y).1.sqrt(),
            };
            let d0 = dist(&x);
            let t = max_step(kind, &x, &dx, s, 1.0);
            assert!((0.0..=1.0).contains(&t));
            for k in 0..=2000 {
                let tk = t * k as f64 / 2000.0;
                let y = std::array::from_fn(|i| std::array::from_fn(|c| x[i][c] + tk * dx[i][c]));
                assert!(
                    dist(&y) >= s * d0 * (1.0 - 1e-9),
                    "case {case} {kind:?} at {tk} of {t}"
                );
            }
        }
    }
}

/// Two 4 × 4 sheets, one 0.5 m above the other: apart, no crossing; one node of the upper
/// sheet pushed 0.5 m below the lower one, its edges pierce it; a segment through the middle
/// of a triangle, along its plane, and past its edge, decided exactly.
#[test]
fn a_sheet_pushed_through_another_is_a_crossing() {
    use super::broad::Surface;
    use super::intersect::{first_crossing, segment_crosses_triangle};
    let n = 5;
    let mut s = Surface::default();
    let mut x = Vec::new();
    for (sheet, z) in [(0, 0.0), (1, 0.5)] {
        for i in 0..n {
            for j in 0..n {
                x.extend([i as f64, j as f64, z]);
            }
        }
        add_grid(&mut s, n, sheet * n * n);
    }
    assert_eq!(first_crossing(&s, &x), None);
    let pushed = n * n + 2 * n + 2; // the upper sheet's middle node
    x[3 * pushed + 2] = -0.5;
    let (e, t) = first_crossing(&s, &x).expect("the pushed node's edges pierce the lower sheet");
    // Either an edge at the pushed node through a lower triangle, or a lower edge through a
    // triangle at the pushed node (the first in edge order).
    let (edge, tri) = (s.edges[e], s.triangles[t]);
    let lower = |k: &usize| *k < n * n;
    assert!(
        (edge.contains(&pushed) && tri.iter().all(lower))
            || (tri.contains(&pushed) && edge.iter().all(lower)),
        "{edge:?} {tri:?}"
    );
    let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert!(segment_crosses_triangle(
        [0.2, 0.2, 1.0],
        [0.2, 0.2, -1.0],
        tri
    ));
    assert!(!segment_crosses_triangle(
        [0.7, 0.7, 1.0],
        [0.7, 0.7, -1.0],
        tri
    ));
    assert!(!segment_crosses_triangle(
        [0.1, 0.1, 0.0],
        [0.3, 0.1, 0.0],
        tri
    ));
    assert!(
        segment_crosses_triangle([0.2, 0.2, 0.0], [0.2, 0.2, -1.0], tri),
        "touching"
    );
}
