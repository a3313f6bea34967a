//! The 3-D pictures, by their pixels: the oblique view's canopy is coloured by height (both
//! ends of the colour map appear), the top view differs from the side views, load sites and
//! the payload are marked only when the scene says where they are, and velocity.png draws the
//! terminal line and band only when terminal velocity was reached.

use crate::common::image::{distance, fraction, saturated, Image};

use chute::output::plots::{
    final_shape_plot, velocity_plot, wrinkle_plot, ColourBy, ShapeScene, TerminalMark, PLOT_SIZE,
    SHAPE_SIZE, WRINKLES_PNG,
};
use chute::output::scene3d::{viridis, LOAD_SITE_RGB, MEMBRANE_STATE_RGB, PAYLOAD_RGB};
use chute::output::vtk::point_roles;

/// Nodes, triangles, segments and load sites.
pub(crate) type Model = (Vec<[f64; 3]>, Vec<[usize; 3]>, Vec<[usize; 2]>, Vec<usize>);

/// A dome of 6 rings × 16 sectors (z from 9 to 10 m) with 4 lines to a payload at z = 6 m.
pub(crate) fn dome() -> Model {
    let (rings, sectors) = (6, 16);
    let mut x = vec![[0.0, 0.0, 10.0]];
    for r in 1..=rings {
        let phi = r as f64 / rings as f64 * 1.2;
        for s in 0..sectors {
            let th = s as f64 / sectors as f64 * std::f64::consts::TAU;
            x.push([phi.sin() * th.cos(), phi.sin() * th.sin(), 9.0 + phi.cos()]);
        }
    }
    let idx = |r: usize, s: usize| {
        if r == 0 {
            0
        } else {
            1 + (r - 1) * sectors + s % sectors
        }
    };
    let mut tri = vec![];
    for r in 0..rings {
        for s in 0..sectors {
            if r == 0 {
                tri.push([0, idx(1, s), idx(1, s + 1)]);
            } else {
                tri.push([idx(r, s), idx(r + 1, s), idx(r + 1, s + 1)]);
                tri.push([idx(r, s), idx(r + 1, s + 1), idx(r, s + 1)]);
            }
        }
    }
    x.push([0.0, 0.0, 6.0]);
    let payload = x.len() - 1;
    let sites: Vec<usize> = (0..4).map(|k| idx(rings, 4 * k)).collect();
    let seg = sites.iter().map(|&s| [s, payload]).collect();
    (x, tri, seg, sites)
}

/// Panels of shape.png (inset from their borders): oblique, top, side x–z, side y–z.
const OBLIQUE: (u32, u32, u32, u32) = (20, 80, 750, 700);
const TOP: (u32, u32, u32, u32) = (790, 80, 1380, 700);
const SIDE_XZ: (u32, u32, u32, u32) = (20, 760, 680, 1280);

fn near(c: (u8, u8, u8), tol: u8) -> impl Fn([u8; 3]) -> bool {
    move |p| distance(p, [c.0, c.1, c.2]) <= tol
}

fn render(scene: &ShapeScene<'_>) -> Image {
    let dir = tempfile::tempdir().unwrap();
    let path = final_shape_plot(dir.path(), 1.0, scene).unwrap();
    let img = Image::read(&path);
    assert_eq!((img.width, img.height), SHAPE_SIZE);
    if let Ok(keep) = std::env::var("CHUTE_KEEP_PLOTS") {
        std::fs::copy(&path, std::path::Path::new(&keep).join("shape-3d-test.png")).unwrap();
    }
    img
}

#[test]
fn oblique_view_is_coloured_by_height_and_differs_from_the_top_view() {
    let (x, tri, seg, sites) = dome();
    let canopy: Vec<usize> = (0..x.len() - 1).collect();
    let roles = point_roles(x.len(), &canopy, &sites, Some(x.len() - 1));
    let scene = ShapeScene {
        roles: &roles,
        ..ShapeScene::new(&x, &tri, &seg)
    };
    let img = render(&scene);
    let oblique = img.region(OBLIQUE);
    let coloured = fraction(&oblique, |p| saturated(p, 40));
    assert!(coloured > 0.08, "oblique view: {coloured:.3} coloured");
    // Height colours: the shaded top end (yellow) and bottom end (purple) of viridis appear.
    let top_end = viridis(1.0);
    let yellowish = |p: [u8; 3]| {
        let s = f64::from(p[0]) / f64::from(top_end.0);
        s > 0.3
            && (0..3).all(|c| {
                (f64::from(p[c]) - s * f64::from([top_end.0, top_end.1, top_end.2][c])).abs() < 30.0
            })
    };
    assert!(
        fraction(&oblique, yellowish) > 0.005,
        "no top-of-canopy colour"
    );
    let purple = |p: [u8; 3]| p[2] > p[1] + 30 && p[0] > p[1] + 20;
    assert!(
        fraction(&oblique, purple) > 0.001,
        "no bottom-of-canopy colour"
    );
    // From above the dome fills its panel; from the side it is a thin band above the lines.
    let top = img.region(TOP);
    let side = img.region(SIDE_XZ);
    let (top_cov, side_cov) = (
        fraction(&top, |p| saturated(p, 40)),
        fraction(&side, |p| saturated(p, 40)),
    );
    assert!(
        top_cov > 2.0 * side_cov,
        "top {top_cov:.3} vs side {side_cov:.3}"
    );
    let n = top.len().min(side.len());
    let differ = fraction(
        &top[..n]
            .iter()
            .zip(&side[..n])
            .map(|(a, b)| {
                if distance(*a, *b) > 30 {
                    [255, 0, 0]
                } else {
                    [0, 0, 0]
                }
            })
            .collect::<Vec<_>>(),
        |p| p[0] == 255,
    );
    assert!(
        differ > 0.2,
        "top and side views differ in only {differ:.3} of the pixels"
    );
    // Markers: 4 load sites (magenta dots) and the payload (a black square).
    assert!(
        oblique
            .iter()
            .filter(|&&p| near(LOAD_SITE_RGB, 12)(p))
            .count()
            > 4 * 30
    );
    assert!(oblique.iter().filter(|&&p| near(PAYLOAD_RGB, 3)(p)).count() > 150);
}

#[test]
fn markers_need_roles() {
    let (x, tri, seg, sites) = dome();
    let canopy: Vec<usize> = (0..x.len() - 1).collect();
    let roles = point_roles(x.len(), &canopy, &sites, Some(x.len() - 1));
    let bare = render(&ShapeScene::new(&x, &tri, &seg)).region(OBLIQUE);
    let marked = render(&ShapeScene {
        roles: &roles,
        ..ShapeScene::new(&x, &tri, &seg)
    })
    .region(OBLIQUE);
    let count = |px: &[[u8; 3]], c, tol| px.iter().filter(|&&p| near(c, tol)(p)).count();
    assert_eq!(count(&bare, LOAD_SITE_RGB, 12), 0);
    assert!(count(&marked, LOAD_SITE_RGB, 12) > 4 * 30);
    // The payload square is 15 × 15 pixels of its colour (text and edges have a few).
    let (b, m) = (count(&bare, PAYLOAD_RGB, 3), count(&marked, PAYLOAD_RGB, 3));
    assert!(m > b + 150, "payload pixels: {m} marked vs {b} bare");
}

#[test]
fn speed_colouring_needs_velocities() {
    let (x, tri, seg, _) = dome();
    let scene = ShapeScene {
        colour_by: ColourBy::Speed,
        ..ShapeScene::new(&x, &tri, &seg)
    };
    let dir = tempfile::tempdir().unwrap();
    let e = final_shape_plot(dir.path(), 0.0, &scene).unwrap_err();
    assert!(e.to_string().contains("velocity"), "{e}");
    let v: Vec<[f64; 3]> = x.iter().map(|p| [0.0, 0.0, -p[2]]).collect();
    let scene = ShapeScene {
        velocities: &v,
        ..scene
    };
    let img = render(&scene);
    assert!(fraction(&img.region(OBLIQUE), |p| saturated(p, 40)) > 0.08);
}

#[test]
fn membrane_state_colours_each_triangle_and_needs_one_state_per_triangle() {
    let (x, tri, seg, _) = dome();
    let dir = tempfile::tempdir().unwrap();
    let bad = [0u8; 3];
    let scene = ShapeScene {
        cell_state: &bad,
        ..ShapeScene::new(&x, &tri, &seg)
    };
    let e = wrinkle_plot(dir.path(), 0.0, &scene).unwrap_err();
    assert!(e.to_string().contains("one state per triangle"), "{e}");
    // The inner third taut, the middle wrinkled, the rim slack (16 sectors per ring, the
    // centre ring one triangle each, then two).
    let state: Vec<u8> = (0..tri.len())
        .map(|k| [0, 0, 0, 1, 1, 2][(k + 16) / 32])
        .collect();
    let scene = ShapeScene {
        cell_state: &state,
        ..scene
    };
    let path = wrinkle_plot(dir.path(), 1.0, &scene).unwrap();
    assert!(path.ends_with(WRINKLES_PNG));
    let img = Image::read(&path);
    let top = img.region(TOP);
    // Each state's colour, dimmed by the shading (0.35–1 of it), covers its share.
    let shaded = |c: (u8, u8, u8)| {
        move |p: [u8; 3]| {
            let s = f64::from(p[0].max(p[1]).max(p[2])) / f64::from(c.0.max(c.1).max(c.2));
            s > 0.3
                && [c.0, c.1, c.2]
                    .iter()
                    .zip(p)
                    .all(|(&a, b)| (s * f64::from(a) - f64::from(b)).abs() < 25.0)
        }
    };
    let share: Vec<f64> = MEMBRANE_STATE_RGB
        .iter()
        .map(|&c| fraction(&top, shaded(c)))
        .collect();
    assert!(share.iter().all(|&f| f > 0.01), "state shares {share:?}");
    // Seen from above, rings 4–5 (wrinkled) cover 2.4× the area of the rim ring (slack).
    assert!(share[1] > 1.5 * share[2], "{share:?}");
    // Nothing is coloured by height: no viridis yellow.
    assert_eq!(fraction(&top, near((253, 231, 37), 20)), 0.0);
}

#[test]
fn rod_canopy_is_drawn_in_colour_without_a_top_view() {
    let x: Vec<[f64; 3]> = (0..21)
        .map(|i| {
            let s = i as f64 / 20.0 - 0.5;
            [2.0 * s, 0.0, -0.5 * (1.0 - 4.0 * s * s)]
        })
        .collect();
    let seg: Vec<[usize; 2]> = (0..20).map(|i| [i, i + 1]).collect();
    let img = render(&ShapeScene::new(&x, &[], &seg));
    assert!(fraction(&img.region(OBLIQUE), |p| saturated(p, 40)) > 0.002);
    assert!(fraction(&img.region(SIDE_XZ), |p| saturated(p, 40)) > 0.002);
}

fn line_red(p: [u8; 3]) -> bool {
    p[0] > 200 && p[1] < 60 && p[2] < 60
}

fn band_green(p: [u8; 3]) -> bool {
    distance(p, [204, 255, 204]) <= 8
}

#[test]
fn velocity_plot_draws_terminal_line_and_band_only_when_reached() {
    let dir = tempfile::tempdir().unwrap();
    let t: Vec<f64> = (0..=1000).map(|i| i as f64 * 1e-3).collect();
    let vz: Vec<f64> = t.iter().map(|&t| -5.0 * (t / 0.5).tanh()).collect();
    let path = dir.path().join("v.png");
    let reached = TerminalMark::Reached {
        v_mps: -5.0 * 2.0_f64.tanh(),
        time_to_terminal_s: Some(0.6),
    };
    velocity_plot(&path, &t, &vz, &reached).unwrap();
    let img = Image::read(&path);
    assert_eq!((img.width, img.height), PLOT_SIZE);
    let all = img.region((0, 0, img.width, img.height));
    assert!(all.iter().filter(|&&p| line_red(p)).count() > 200);
    assert!(all.iter().filter(|&&p| band_green(p)).count() > 1000);
    let not = TerminalMark::NotReached {
        reason: "vz still changing: std 6.5 %, trend 11 % of |v_t| (limit 1 %)",
    };
    velocity_plot(&path, &t, &vz, &not).unwrap();
    let all = Image::read(&path).region((0, 0, img.width, img.height));
    assert_eq!(
        all.iter().filter(|&&p| line_red(p)).count(),
        0,
        "a terminal line"
    );
    assert_eq!(
        all.iter().filter(|&&p| band_green(p)).count(),
        0,
        "a ±2 % band"
    );
    let note = all
        .iter()
        .filter(|&&p| distance(p, [150, 40, 0]) <= 20)
        .count();
    assert!(
        note > 100,
        "the 'not reached' note is missing ({note} pixels)"
    );
}
