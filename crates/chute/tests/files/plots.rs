//! PNG plots: files exist, are PNGs of the documented size, and nothing temporary remains.
//! (Drawing any text fails in plotters' ab_glyph backend when no font is registered, so a
//! successful render also shows the embedded font works.)

use std::fs;
use std::path::Path;

use chute::output::plots::{
    final_shape_plot, height_plot, snapshot_file_name, snapshot_plot, velocity_plot, ShapeScene,
    TerminalMark, PLOT_SIZE, SHAPE_SIZE,
};

/// Width and height from the PNG signature + IHDR chunk.
fn png_size(path: &Path) -> (u32, u32) {
    let b = fs::read(path).unwrap();
    assert_eq!(&b[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    assert_eq!(&b[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes(b[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

/// Nodes, triangles and segments.
type Mesh = (Vec<[f64; 3]>, Vec<[usize; 3]>, Vec<[usize; 2]>);

/// The dome of the 3-D picture tests (6 rings × 16 sectors, four lines to a payload).
fn canopy() -> Mesh {
    let (x, tri, seg, _sites) = crate::plots_3d::dome();
    (x, tri, seg)
}

#[test]
fn plots_are_pngs_of_the_right_size() {
    let dir = tempfile::tempdir().unwrap();
    let (v_t, tau) = (5.0, 5.0 / 9.81);
    let t: Vec<f64> = (0..=2000).map(|i| i as f64 * 2.5e-3).collect();
    let vz: Vec<f64> = t.iter().map(|&t| -v_t * (t / tau).tanh()).collect();
    let h: Vec<f64> = t.iter().map(|&t| 1.0 + 0.3 * (1.0 - (-t).exp())).collect();
    let vel = dir.path().join("velocity.png");
    let mark = TerminalMark::Reached {
        v_mps: -v_t,
        time_to_terminal_s: Some(tau * 0.98_f64.atanh()),
    };
    velocity_plot(&vel, &t, &vz, &mark).unwrap();
    let hgt = dir.path().join("height.png");
    height_plot(&hgt, &t, &h).unwrap();
    let (x, tri, seg) = canopy();
    let scene = ShapeScene::new(&x, &tri, &seg);
    let shape = final_shape_plot(dir.path(), 5.0, &scene).unwrap();
    let snap = snapshot_plot(dir.path(), 2.5, &scene).unwrap();
    assert!(snap.ends_with("snapshot_2.5s.png"));
    for (p, size) in [
        (&vel, PLOT_SIZE),
        (&hgt, PLOT_SIZE),
        (&shape, SHAPE_SIZE),
        (&snap, SHAPE_SIZE),
    ] {
        assert_eq!(png_size(p), size, "{}", p.display());
        assert!(
            fs::metadata(p).unwrap().len() > 5_000,
            "suspiciously small {}",
            p.display()
        );
    }
    if let Ok(keep) = std::env::var("CHUTE_KEEP_PLOTS") {
        for p in [&vel, &hgt, &shape, &snap] {
            fs::copy(p, Path::new(&keep).join(p.file_name().unwrap())).unwrap();
        }
    }
    assert_eq!(
        fs::read_dir(dir.path()).unwrap().count(),
        4,
        "temporary files left"
    );
}

#[test]
fn plots_without_data_fail_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let none = TerminalMark::NotReached { reason: "test" };
    assert!(velocity_plot(&dir.path().join("v.png"), &[], &[], &none).is_err());
    assert!(final_shape_plot(dir.path(), 0.0, &ShapeScene::new(&[], &[], &[])).is_err());
    let bad = ShapeScene::new(&[[0.0; 3]], &[[0, 1, 2]], &[]);
    assert!(final_shape_plot(dir.path(), 0.0, &bad).is_err());
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn snapshot_names() {
    assert_eq!(snapshot_file_name(2.5), "snapshot_2.5s.png");
    assert_eq!(snapshot_file_name(10.0), "snapshot_10s.png");
    assert_eq!(snapshot_file_name(0.1234), "snapshot_0.123s.png");
    assert_eq!(snapshot_file_name(0.0), "snapshot_0s.png");
}
