//! `viewer.html` in a real browser: a short round-parachute run (shell canopy, 12 lines, a
//! payload) writes its viewer, which headless Debian `chromium` (WebGL through SwiftShader)
//! opens offline, with the network cut when we may (`unshare -n` as root), at two times.
//! Checked: the canvas reports the frame nearest the requested time and the mesh's triangle
//! count, the canopy region of the screenshots is drawn and differs between the two times, and
//! the page logs no exception or unexpected console message.
//!
//! Without chromium this test FAILS (install it with `apt-get install chromium`) unless
//! `CHUTE_NO_BROWSER=1`. With `CHUTE_SAVE_DOC_IMAGES=docs/img` it also saves the screenshot
//! and the run's 3-D snapshot there (the README's and docs/outputs.md's pictures).

use crate::common::image::{distance, fraction, Image};

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `chromium` on the PATH, or why the test cannot run.
fn find_chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join("chromium"))
        .find(|p| p.is_file())
}

/// Whether `unshare -n` works here (it needs root): the browser then has no network at all.
fn can_cut_network() -> bool {
    Command::new("unshare")
        .args(["-n", "true"])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// What one headless load produced.
struct Load {
    stdout: String,
    stderr: String,
}

/// Open `url` in headless chromium with `args`, in a fresh profile, network cut if possible;
/// killed after 90 s.
fn chromium(browser: &Path, profile: &Path, url: &str, args: &[String]) -> Load {
    let flags = [
        "--headless",
        "--no-sandbox",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-gpu-sandbox",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--no-first-run",
        "--disable-quic",
        "--enable-logging=stderr",
        "--v=0",
        "--virtual-time-budget=5000",
    ];
    let mut cmd = if can_cut_network() {
        let mut c = Command::new("unshare");
        c.arg("-n").arg(browser);
        c
    } else {
        eprintln!("note: not root, so the network is not cut (the page makes no requests anyway)");
        Command::new(browser)
    };
    let _ = std::fs::remove_dir_all(profile);
    cmd.args(flags)
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .arg(url)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("chromium starts");
    let start = Instant::now();
    // Read the pipes on threads so a chatty browser cannot block on a full pipe.
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let t_out = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut out, &mut s).ok();
        s
    });
    let t_err = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut err, &mut s).ok();
        s
    });
    loop {
        if child.try_wait().expect("wait").is_some() {
            break;
        }
        if start.elapsed() > Duration::from_secs(90) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish in 90 s on {url}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    Load {
        stdout: t_out.join().unwrap(),
        stderr: t_err.join().unwrap(),
    }
}

/// The attribute `name` of the first element that starts with `tag_start` in `dom`.
fn attribute(dom: &str, tag_start: &str, name: &str) -> Option<String> {
    let at = dom.find(tag_start)?;
    let tag = &dom[at..at + dom[at..].find('>')?];
    let key = format!("{name}=\"");
    let v = tag.find(&key)? + key.len();
    Some(tag[v..v + tag[v..].find('"')?].to_string())
}

/// The console messages of the page itself (not chromium's own pages).
fn page_console(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.contains(":CONSOLE") && l.contains("source: file://"))
        .collect()
}

/// Frame times from canopy.pvd and the triangle count of the first frame, read here
/// directly (not with chute's reader, which the viewer itself uses).
fn frames_and_triangles(run: &Path) -> (Vec<f64>, usize) {
    let pvd = std::fs::read_to_string(run.join("canopy.pvd")).unwrap();
    let times: Vec<f64> = pvd
        .split("timestep=\"")
        .skip(1)
        .map(|s| s[..s.find('"').unwrap()].parse().unwrap())
        .collect();
    let vtu = std::fs::read_to_string(run.join("frames/frame_000000.vtu")).unwrap();
    let types = &vtu[vtu.find("Name=\"types\"").unwrap()..];
    let types = &types[types.find('>').unwrap() + 1..types.find("</DataArray>").unwrap()];
    let triangles = types.split_whitespace().filter(|&w| w == "5").count();
    (times, triangles)
}

/// A short run of the bundled round parachute on a coarse mesh (~2 s of wall time).
fn short_run(dir: &Path) -> PathBuf {
    let out = dir.join("run");
    let scenario = repo().join("scenarios/round-parachute.toml");
    let o = crate::common::chute_command()
        .arg("run")
        .arg(&scenario)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .args(["--set", "time.duration_s=1.0"])
        .args(["--set", "canopy.edge_length_m=0.3"])
        .args(["--set", "lines.segments=4"])
        .args(["--set", "output.snapshots_s=[0.5]"])
        .output()
        .expect("chute runs");
    assert!(
        o.status.success(),
        "chute run failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.join("viewer.html").is_file(), "no viewer.html");
    out
}

/// `chromium`, or `None` with `CHUTE_NO_BROWSER=1` (the test is skipped, saying so); without
/// either the test fails, saying how to install it.
fn browser_or_skip() -> Option<PathBuf> {
    let browser = find_chromium();
    if browser.is_none() {
        if std::env::var("CHUTE_NO_BROWSER").as_deref() == Ok("1") {
            eprintln!("skipped: chromium is not installed and CHUTE_NO_BROWSER=1");
            return None;
        }
        panic!(
            "chromium is not installed; install it with `apt-get update && apt-get install -y \
             chromium` (Debian), or set CHUTE_NO_BROWSER=1 to skip this test"
        );
    }
    browser
}

/// The fraction of the two shots' joint canopy box whose pixels differ visibly.
fn changed_fraction(a: &Shot, b: &Shot) -> f64 {
    let (x, y) = (a.bbox, b.bbox);
    let union = (x.0.min(y.0), x.1.min(y.1), x.2.max(y.2), x.3.max(y.3));
    let (ra, rb) = (a.image.region(union), b.image.region(union));
    let differ = ra.iter().zip(&rb).filter(|(p, q)| distance(**p, **q) > 24);
    differ.count() as f64 / ra.len() as f64
}

/// The most frequent colour (the background of the 3-D view in its half of the page).
fn most_common(pixels: &[[u8; 3]]) -> [u8; 3] {
    let mut counts = std::collections::HashMap::new();
    for p in pixels {
        *counts.entry(*p).or_insert(0usize) += 1;
    }
    counts.into_iter().max_by_key(|&(_, n)| n).unwrap().0
}

struct Shot {
    drawn_time: f64,
    triangles: usize,
    bbox: (u32, u32, u32, u32),
    image: Image,
}

/// Load the viewer at `#t=t`: the DOM (at a 900×700 window) and then a screenshot at exactly
/// the viewport the DOM was laid out in, so the canopy box the page reports applies to it.
fn load_at(browser: &Path, dir: &Path, viewer: &Path, t: f64) -> Shot {
    let url = format!("file://{}#t={t}", viewer.display());
    let profile = dir.join(format!("profile-{t}"));
    let dom_load = chromium(
        browser,
        &profile,
        &url,
        &["--window-size=900,700".into(), "--dump-dom".into()],
    );
    let dom = &dom_load.stdout;
    assert!(
        dom.contains("id=\"scene\""),
        "no page dumped:\n{}",
        dom_load.stderr
    );
    let body_error = attribute(dom, "<body", "data-error");
    assert!(
        body_error.is_none(),
        "the page reported an error: {body_error:?}"
    );
    let console = page_console(&dom_load.stderr);
    assert!(
        console
            .iter()
            .any(|l| l.contains("chute-viewer: drew t = ")),
        "the viewer's console line is missing, so console capture cannot be trusted:\n{}",
        dom_load.stderr
    );
    for line in &console {
        assert!(
            line.contains("\"chute-viewer: drew t = ") && !line.contains("Uncaught"),
            "unexpected console message: {line}"
        );
    }
    let canvas = "<canvas id=\"scene\"";
    let get = |name: &str| {
        attribute(dom, canvas, name).unwrap_or_else(|| panic!("canvas lacks {name}:\n{dom}"))
    };
    let drawn_time: f64 = get("data-drawn-time").parse().unwrap();
    let triangles: usize = get("data-drawn-triangles").parse().unwrap();
    let b: Vec<u32> = get("data-canopy-bbox")
        .split(',')
        .map(|v| v.parse::<i64>().unwrap().max(0) as u32)
        .collect();
    let viewport = attribute(dom, "<body", "data-viewport").expect("body data-viewport");
    let png = dir.join(format!("viewer-{t}.png"));
    let shot = chromium(
        browser,
        &profile,
        &url,
        &[
            format!("--window-size={}", viewport.replace('x', ",")),
            format!("--screenshot={}", png.display()),
        ],
    );
    for line in page_console(&shot.stderr) {
        assert!(
            line.contains("\"chute-viewer: drew t = "),
            "unexpected console message: {line}"
        );
    }
    let image = Image::read(&png);
    assert_eq!(
        format!("{}x{}", image.width, image.height),
        viewport,
        "the screenshot is not of the viewport the page was laid out in"
    );
    Shot {
        drawn_time,
        triangles,
        bbox: (b[0], b[1], b[2], b[3]),
        image,
    }
}

#[test]
fn viewer_draws_the_requested_times_in_a_real_browser() {
    let Some(browser) = browser_or_skip() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let run = short_run(dir.path());
    let html = std::fs::read_to_string(run.join("viewer.html")).unwrap();
    for needle in [
        "src=\"http",
        "href=\"http",
        "fetch(",
        "XMLHttpRequest",
        "import ",
    ] {
        assert!(
            !html.contains(needle),
            "viewer.html refers outside itself: {needle}"
        );
    }
    let (times, mesh_triangles) = frames_and_triangles(&run);
    assert_eq!(times.len(), 21, "frames every 0.05 s over 1 s");
    assert!(mesh_triangles > 50, "{mesh_triangles} triangles");
    let interval = times[1] - times[0];
    // Between frames, so the viewer has to pick the nearest one.
    let requested = [0.21, 0.87];
    let shots: Vec<Shot> = requested
        .iter()
        .map(|&t| load_at(&browser, dir.path(), &run.join("viewer.html"), t))
        .collect();
    for (shot, &t) in shots.iter().zip(&requested) {
        let nearest = times
            .iter()
            .copied()
            .min_by(|a, b| (a - t).abs().total_cmp(&(b - t).abs()))
            .unwrap();
        assert_eq!(shot.drawn_time, nearest, "drawn time for #t={t}");
        assert!((shot.drawn_time - t).abs() <= 0.5 * interval + 1e-12);
        assert_eq!(shot.triangles, mesh_triangles, "triangles drawn at #t={t}");
        // The canopy box holds the canopy: mostly not the background.
        let (x0, y0, x1, y1) = shot.bbox;
        assert!(x1 > x0 + 20 && y1 > y0 + 10, "canopy box {:?}", shot.bbox);
        let background = most_common(&shot.image.region((
            0,
            0,
            shot.image.width / 2,
            shot.image.height,
        )));
        let drawn = fraction(&shot.image.region(shot.bbox), |p| {
            distance(p, background) > 24
        });
        assert!(
            drawn > 0.4,
            "#t={t}: only {drawn:.2} of the canopy box is drawn"
        );
        eprintln!(
            "#t={t}: drew t = {} s, {} triangles, canopy box {:?} {drawn:.2} drawn",
            shot.drawn_time, shot.triangles, shot.bbox
        );
    }
    // The canopy changes between the two times (shape and height colours).
    let changed = changed_fraction(&shots[0], &shots[1]);
    assert!(
        changed > 0.1,
        "only {changed:.3} of the canopy region changed"
    );
    eprintln!("{changed:.3} of the canopy region differs between the two times");
    if let Ok(target) = std::env::var("CHUTE_SAVE_DOC_IMAGES") {
        let target = repo().join(target);
        std::fs::create_dir_all(&target).unwrap();
        let last = requested[1];
        std::fs::copy(
            dir.path().join(format!("viewer-{last}.png")),
            target.join("viewer.png"),
        )
        .unwrap();
        std::fs::copy(
            run.join("snapshot_0.5s.png"),
            target.join("snapshot-3d.png"),
        )
        .unwrap();
        eprintln!(
            "saved viewer.png and snapshot-3d.png in {}",
            target.display()
        );
    }
}

/// `chute steady`'s `modes.html` in a real browser: the 4-site canopy's modes (its lateral
/// instability first) after a 2 s transient. Checked as the run viewer: the frame nearest the
/// requested time is drawn with every triangle, and two modes look different.
#[test]
fn modes_page_draws_the_modes_in_a_real_browser() {
    let Some(browser) = browser_or_skip() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("steady");
    let mut cmd = crate::common::chute_command();
    cmd.arg("steady")
        .arg(repo().join("scenarios/report-shell-4-sites.toml"))
        .arg("--out")
        .arg(&out);
    for set in [
        "fluid.shell_drag=pressure",
        "time.dt_s=1e-2",
        "shell.membrane=springs",
        "shell.bending=hinge",
        "canopy.edge_length_m=0.5",
        "time.duration_s=2",
    ] {
        cmd.args(["--set", set]);
    }
    let o = cmd.output().expect("chute runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let page = out.join("modes.html");
    // Mode 1 a quarter into its cycle, mode 2 at its start (24 frames per cycle).
    let requested = [0.25, 1.0];
    let shots: Vec<Shot> = requested
        .iter()
        .map(|&t| load_at(&browser, dir.path(), &page, t))
        .collect();
    for (shot, &t) in shots.iter().zip(&requested) {
        assert!(
            (shot.drawn_time - t).abs() < 1e-12,
            "drew {} for #t={t}",
            shot.drawn_time
        );
        // The 6 m × 3 m canopy at 0.5 m: 13 × 7 nodes, 12 × 6 cells of 2 triangles.
        assert_eq!(shot.triangles, 144, "triangles drawn at #t={t}");
    }
    let changed = changed_fraction(&shots[0], &shots[1]);
    assert!(
        changed > 0.02,
        "only {changed:.3} of the canopy region differs between modes"
    );
}

/// A dispersion's `footprint.html` in a real browser: the quick bundled dispersion's page,
/// rendered headless to a screenshot, shows its landings (blue dots) and its ellipses (the
/// 1σ one red) in their colours, and logs nothing.
#[test]
fn footprint_page_draws_the_landings_in_a_real_browser() {
    let Some(browser) = browser_or_skip() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let study = repo().join("studies/dispersion-quick.toml");
    let study = study.display().to_string();
    crate::common::chute_ok(dir.path(), &["study", &study, "--out", "quick", "-j", "2"]);
    let out = dir.path().join("quick");
    let png = dir.path().join("footprint-shot.png");
    let load = chromium(
        &browser,
        &dir.path().join("profile"),
        &format!("file://{}", out.join("footprint.html").display()),
        &[
            "--window-size=800,800".into(),
            format!("--screenshot={}", png.display()),
        ],
    );
    let image = Image::read(&png);
    let near =
        |c: [u8; 3]| fraction(&image.pixels, |p| distance(p, c) < 40) * image.pixels.len() as f64;
    // Four dots of 3.5 px radius: about 150 pixels; the 1σ ellipse: a 2 px outline.
    let (dots, ring) = (near([0x1f, 0x4f, 0xd1]), near([0xc8, 0x1e, 0x1e]));
    assert!(
        dots > 60.0,
        "{dots} landing pixels; stderr: {}",
        load.stderr
    );
    assert!(ring > 60.0, "{ring} 1σ-ellipse pixels");
    assert!(page_console(&load.stderr).is_empty(), "{}", load.stderr);
    let _ = load.stdout;
}
