//! viewer.html without a browser: what is embedded is exactly what the run directory holds
//! (frames, mesh, node roles, time series, summary), decimation above the cap, escaping, bad
//! run directories, `chute view` through the binary; and atomic writes honour the umask.
//! (The page itself is tested in a real browser in viewer_browser.rs.)

use std::fs;
use std::path::Path;

use crate::common::{assert_contains, assert_exit};

use chute::output::run_dir::frame_selection;
use chute::output::viewer::{base64, viewer_html, write_viewer, write_viewer_capped, VIEWER_HTML};
use chute::output::vtk::{point_roles, VtkSeries, ROLE_LINE, ROLE_LOAD_SITE, ROLE_PAYLOAD};
use chute::output::{write_atomic, Sample, TimeSeriesWriter};
use proptest::prelude::*;

fn b64_decode(s: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let mut out = Vec::new();
    for chunk in s.as_bytes().chunks(4) {
        let n = chunk.iter().filter(|&&c| c != b'=').count();
        let mut acc = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            acc |= u32::from(if c == b'=' { 0 } else { val(c) }) << (18 - 6 * k);
        }
        out.extend(acc.to_be_bytes()[1..n].iter().copied());
    }
    out
}

fn f32s(s: &str) -> Vec<f32> {
    b64_decode(s)
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn u32s(s: &str) -> Vec<u32> {
    b64_decode(s)
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn base64_matches_rfc_4648_vectors() {
    let cases = [
        ("", ""),
        ("f", "Zg=="),
        ("fo", "Zm8="),
        ("foo", "Zm9v"),
        ("foob", "Zm9vYg=="),
        ("fooba", "Zm9vYmE="),
        ("foobar", "Zm9vYmFy"),
    ];
    for (plain, encoded) in cases {
        assert_eq!(base64(plain.as_bytes()), encoded);
    }
    let bytes: Vec<u8> = (0..=255).collect();
    assert_eq!(b64_decode(&base64(&bytes)), bytes);
}

/// Node positions of frame k: two triangles, two lines to a payload, falling and bending.
fn positions(k: usize) -> Vec<[f64; 3]> {
    positions_below(k, 0.0)
}

/// [`positions`] `depth` metres lower.
fn positions_below(k: usize, depth: f64) -> Vec<[f64; 3]> {
    let t = k as f64 * 0.1;
    let z = -t - depth;
    vec![
        [0.0, 0.0, z],
        [1.0, 0.0, z],
        [1.0, 1.0, 0.2 * t + z],
        [0.0, 1.0, z],
        [0.5, 0.5, -2.0 + z],
    ]
}

const TRIANGLES: [[usize; 3]; 2] = [[0, 1, 2], [0, 2, 3]];
const SEGMENTS: [[usize; 2]; 2] = [[0, 4], [2, 4]];

/// A run directory with `frames` frames, a 50-row time series and a summary named `name`.
fn fake_run(dir: &Path, frames: usize, name: &str) {
    fake_run_below(dir, frames, name, 0.0);
}

/// [`fake_run`] with every node `depth` metres lower.
fn fake_run_below(dir: &Path, frames: usize, name: &str, depth: f64) {
    let mut vtk = VtkSeries::new(dir).unwrap();
    vtk.set_roles(point_roles(5, &[0, 1, 2, 3], &[0, 2], Some(4)));
    for k in 0..frames {
        let x = positions_below(k, depth);
        let v = vec![[0.0, 0.0, -(k as f64)]; 5];
        vtk.write_frame(
            0.1 * k as f64,
            &x,
            &v,
            &TRIANGLES,
            &SEGMENTS,
            &[[0.0; 3]; 2],
        )
        .unwrap();
    }
    let mut ts = TimeSeriesWriter::create(&dir.join("timeseries.csv")).unwrap();
    for i in 0..50 {
        let t = i as f64 * 0.01;
        ts.push(&Sample {
            t_s: t,
            vz_mps: -t,
            extended_height_m: 0.5 + t,
            ..Sample::default()
        })
        .unwrap();
    }
    ts.finish().unwrap();
    let summary = serde_json::json!({ "scenario_name": name, "reached_terminal": false });
    fs::write(dir.join("summary.json"), summary.to_string()).unwrap();
    fs::write(
        dir.join("scenario.resolved.toml"),
        format!("name = {name:?}\n"),
    )
    .unwrap();
}

/// Absolute positions per frame: the Float32 offsets plus each frame's origin.
fn absolute(frames: &serde_json::Value) -> Vec<Vec<[f64; 3]>> {
    let n = frames["nodes"].as_u64().unwrap() as usize;
    let off = f32s(frames["positions"].as_str().unwrap());
    let origins: Vec<[f64; 3]> = serde_json::from_value(frames["origins"].clone()).unwrap();
    assert_eq!(off.len(), origins.len() * 3 * n);
    origins
        .iter()
        .enumerate()
        .map(|(k, o)| {
            (0..n)
                .map(|i| [0, 1, 2].map(|c| o[c] + f64::from(off[3 * (n * k + i) + c])))
                .collect()
        })
        .collect()
}

/// The JSON data block of a viewer page.
fn data_of(html: &str) -> serde_json::Value {
    let open = "<script type=\"application/json\" id=\"chute-data\">";
    let start = html.find(open).expect("data block") + open.len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end]).expect("data is JSON")
}

#[test]
fn embedded_frames_are_the_run_directory_s() {
    let dir = tempfile::tempdir().unwrap();
    fake_run(dir.path(), 4, "fake");
    let report = write_viewer(dir.path()).unwrap();
    assert_eq!(
        (
            report.frames_total,
            report.frames_embedded,
            report.triangles
        ),
        (4, 4, 2)
    );
    let html = fs::read_to_string(dir.path().join(VIEWER_HTML)).unwrap();
    assert_eq!(report.bytes, html.len());
    assert!(
        !html.contains("/*CHUTE_"),
        "a template slot was left unfilled"
    );
    assert!(html.contains("function drawScene") && html.contains("#legend-bar"));
    let d = data_of(&html);
    let f = &d["frames"];
    assert_eq!(f["nodes"], 5);
    assert_eq!(
        f["times"],
        serde_json::json!([0.0, 0.1, 0.2, 0.30000000000000004])
    );
    assert_eq!(u32s(f["triangles"].as_str().unwrap()), [0, 1, 2, 0, 2, 3]);
    assert_eq!(u32s(f["segments"].as_str().unwrap()), [0, 4, 2, 4]);
    let roles = b64_decode(f["roles"].as_str().unwrap());
    assert_eq!(roles, [ROLE_LOAD_SITE, 0, ROLE_LOAD_SITE, 0, ROLE_PAYLOAD]);
    let pos = absolute(f);
    assert_eq!(pos.len(), 4);
    for (k, frame) in pos.iter().enumerate() {
        for (got, want) in frame.iter().zip(positions(k)) {
            for c in 0..3 {
                assert!(
                    (got[c] - want[c]).abs() < 1e-6,
                    "frame {k}: {got:?} vs {want:?}"
                );
            }
        }
    }
    let speeds = f32s(f["speeds"].as_str().unwrap());
    assert_eq!(speeds.len(), 20);
    assert_eq!(speeds[3 * 5 + 4], 3.0);
    let s = &d["series"];
    assert_eq!(s["rows"], 50);
    let h = f32s(s["h"].as_str().unwrap());
    assert_eq!(h.len(), 50);
    assert_eq!(h[10], (0.5 + 0.1_f64) as f32);
    assert_eq!(d["name"], "fake");
    assert_eq!(d["scenario_toml"], "name = \"fake\"\n");
}

#[test]
fn positions_keep_their_precision_far_from_the_origin() {
    let dir = tempfile::tempdir().unwrap();
    let depth = 1.0e4;
    fake_run_below(dir.path(), 3, "far", depth);
    let (html, _) = viewer_html(dir.path(), 1 << 20).unwrap();
    let pos = absolute(&data_of(&html)["frames"]);
    // Float32 of z = -1e4 m alone would be off by up to 5e-4 m; offsets from the frame's
    // centre (at most ~1.2 m) are good to ~1e-7 m.
    for (k, frame) in pos.iter().enumerate() {
        for (got, want) in frame.iter().zip(positions_below(k, depth)) {
            assert!(
                (got[2] - want[2]).abs() < 1e-6,
                "frame {k}: {} vs {}",
                got[2],
                want[2]
            );
        }
    }
}

#[test]
fn frames_above_the_cap_are_decimated_keeping_first_and_last() {
    let dir = tempfile::tempdir().unwrap();
    fake_run(dir.path(), 25, "fake");
    // 5 nodes × 16 bytes per frame; room for 6 frames.
    let report = write_viewer_capped(dir.path(), 6 * 80).unwrap();
    assert_eq!(report.frames_total, 25);
    let d = data_of(&fs::read_to_string(&report.path).unwrap());
    let times: Vec<f64> = serde_json::from_value(d["frames"]["times"].clone()).unwrap();
    assert!(times.len() <= 6, "{times:?}");
    assert_eq!(times.len(), report.frames_embedded);
    assert_eq!(times[0], 0.0);
    assert!((times[times.len() - 1] - 2.4).abs() < 1e-12, "{times:?}");
    let pos = absolute(&d["frames"]);
    assert_eq!(pos.len(), times.len());
    let k = (times[1] / 0.1).round() as usize;
    assert!(
        (pos[1][0][2] - positions(k)[0][2]).abs() < 1e-6,
        "frame {k}'s positions"
    );
    let notes = d["notes"].to_string();
    assert!(notes.contains("of 25 frames embedded"), "{notes}");
}

proptest! {
    #[test]
    fn frame_selection_fits_and_keeps_the_ends(total in 1usize..3000, per in 1usize..100, cap in 0usize..50_000) {
        let keep = frame_selection(total, per, cap);
        let fit = (cap / per).max(2);
        prop_assert!(keep.len() <= total && keep.len() <= fit);
        prop_assert_eq!(keep[0], 0);
        prop_assert_eq!(*keep.last().unwrap(), total - 1);
        prop_assert!(keep.windows(2).all(|w| w[0] < w[1]));
        if total * per <= cap {
            prop_assert_eq!(keep.len(), total);
        }
    }
}

#[test]
fn markup_in_names_cannot_end_the_data_block() {
    let dir = tempfile::tempdir().unwrap();
    let name = "</script><script>alert(1)</script><!--";
    fake_run(dir.path(), 2, name);
    let (html, _) = viewer_html(dir.path(), 1 << 20).unwrap();
    assert_eq!(
        html.matches("</script>").count(),
        2,
        "only the two real closing tags"
    );
    assert!(!html.contains("<script>alert"));
    assert_eq!(data_of(&html)["name"], name);
    assert!(html.contains("<title>&lt;/script&gt;"));
}

#[test]
fn bad_run_directories_are_named_errors() {
    let dir = tempfile::tempdir().unwrap();
    let e = viewer_html(dir.path(), 1 << 20).unwrap_err().to_string();
    assert!(e.contains("not a run directory"), "{e}");
    fake_run(dir.path(), 3, "fake");
    let frame = dir.path().join("frames/frame_000002.vtu");
    let text = fs::read_to_string(&frame).unwrap();
    fs::write(&frame, text.replace("0 2 3", "0 3 2")).unwrap();
    let e = viewer_html(dir.path(), 1 << 20).unwrap_err().to_string();
    assert_contains(&e, &["frame_000002.vtu", "differs"]);
    fs::write(&frame, "<VTKFile>").unwrap();
    let e = viewer_html(dir.path(), 1 << 20).unwrap_err().to_string();
    assert_contains(&e, &["frame_000002.vtu", "Points"]);
}

#[test]
fn frames_without_roles_still_view_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    fake_run(dir.path(), 2, "fake");
    for k in 0..2 {
        let f = dir.path().join(format!("frames/frame_{k:06}.vtu"));
        let text = fs::read_to_string(&f).unwrap();
        let start = text
            .find("<DataArray type=\"UInt8\" Name=\"role\"")
            .unwrap();
        let end = start + text[start..].find("</DataArray>").unwrap() + "</DataArray>".len();
        fs::write(&f, format!("{}{}", &text[..start], &text[end..])).unwrap();
    }
    let d = data_of(&viewer_html(dir.path(), 1 << 20).unwrap().0);
    assert!(d["frames"]["roles"].is_null());
    assert!(d["notes"].to_string().contains("no node roles"));
}

#[test]
fn node_roles() {
    let r = point_roles(6, &[0, 1, 2], &[2, 9], Some(5));
    assert_eq!(
        r,
        [0, 0, ROLE_LOAD_SITE, ROLE_LINE, ROLE_LINE, ROLE_PAYLOAD]
    );
}

#[test]
fn chute_view_writes_the_viewer_or_says_why_not() {
    let dir = tempfile::tempdir().unwrap();
    let view = |d: &Path| {
        crate::common::chute_command()
            .arg("view")
            .arg(d)
            .output()
            .unwrap()
    };
    let o = view(&dir.path().join("missing"));
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("is not a directory"));
    let o = view(dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a run directory"));
    fake_run(dir.path(), 3, "fake");
    let o = view(dir.path());
    assert_exit(&o, 0);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_contains(&out, &["viewer.html", "3 of 3 frames"]);
    assert!(dir.path().join(VIEWER_HTML).is_file());
    // A summary that is not text is a file chute did not write: bad input (2), named.
    fs::write(dir.path().join("summary.json"), [0xff, 0xfe, 0x00, 0x81]).unwrap();
    let o = view(dir.path());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_exit(&o, 2);
    assert_contains(&err, &["summary.json", "not UTF-8"]);
}

#[cfg(unix)]
#[test]
fn atomic_writes_honour_the_umask() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    // A plain create gets 0666 minus the umask: atomic writes must get the same.
    let plain = dir.path().join("plain");
    fs::File::create(&plain).unwrap();
    let atomic = dir.path().join("atomic");
    write_atomic(&atomic, b"x").unwrap();
    let mode = |p: &Path| fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&atomic), mode(&plain));
    assert_ne!(
        mode(&atomic),
        0o600,
        "tempfile's private default leaked through"
    );
}
