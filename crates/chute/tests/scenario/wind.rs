//! `[wind]`: the laws' heights above the ground, the table file (read at load, its errors
//! at their line, recorded by digest) and the rules between the wind's keys.

use std::path::Path;

use chute::scenario::Scenario;

/// `drop-1000m` (released at 1 000 m over ground at 0 m) with `wind` appended.
fn dropped(dir: &Path, wind: &str, set: &[&str]) -> Result<Scenario, String> {
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/drop-1000m.toml");
    let text = std::fs::read_to_string(base).unwrap() + wind;
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let file = dir.join("s.toml");
    Scenario::from_str_with_name(&text, &file.to_string_lossy(), &set).map_err(|e| e.to_string())
}

const TABLE: &str = "\n[wind]\nprofile = \"table\"\nfile = \"w.csv\"\n";

#[test]
fn the_power_law_is_referred_to_the_ground() {
    let dir = tempfile::tempdir().unwrap();
    let wind = "\n[wind]\nprofile = \"power\"\nexponent = 0.2\nreference_height_m = 10.0\n";
    let s = dropped(dir.path(), wind, &["fluid.wind_mps=[3,4,0]"]).unwrap();
    let air = chute::resolve::air(&s);
    // The model's z = 0 is 1 000 m above the ground: 10 m above it is z = −990.
    assert_eq!(air.wind_at(-990.0).velocity, [3.0, 4.0, 0.0]);
    let top = air.wind_at(0.0).velocity[0];
    assert!((top - 3.0 * 100f64.powf(0.2)).abs() < 1e-12, "{top}");
    assert_eq!(air.wind_at(-1000.0).velocity, [0.0; 3]);
}

#[test]
fn a_table_is_read_once_at_its_altitudes_and_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let csv = "altitude_m,vx_mps,vy_mps\n0,1,0\n500, 4, -1\n1200,6,-2\n";
    std::fs::write(dir.path().join("w.csv"), csv).unwrap();
    let s = dropped(dir.path(), TABLE, &["canopy.edge_length_m=0.5"]).unwrap();
    let air = chute::resolve::air(&s);
    // Altitude 500 m is the model's z = −500.
    assert_eq!(air.wind_at(-500.0).velocity, [4.0, -1.0, 0.0]);
    assert_eq!(air.wind_at(-2000.0).velocity, [1.0, 0.0, 0.0]);
    let files = s.input_files();
    assert!(
        files
            .iter()
            .any(|(k, p)| *k == "wind.file" && p.ends_with("w.csv")),
        "{files:?}"
    );
    // The run records the bytes the loader parsed, even when the file changes afterwards.
    std::fs::write(dir.path().join("w.csv"), "changed").unwrap();
    let built = chute::build::build(&s).unwrap();
    let digest = chute::study::inputs::bytes_digest(csv.as_bytes());
    assert!(built.input_digests.contains(&("wind.file", digest)));
}

#[test]
fn a_bad_table_is_refused_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "altitude,vx,vy\n0,1,0\n9,1,0\n",
            "w.csv:1",
            "altitude_m,vx_mps,vy_mps",
        ),
        (
            "altitude_m,vx_mps,vy_mps\n0,1,0\n0,2,0\n",
            "w.csv:3",
            "not above",
        ),
        (
            "altitude_m,vx_mps,vy_mps\n0,1,0\n5,x,0\n",
            "w.csv:3",
            "vx_mps = `x`",
        ),
        (
            "altitude_m,vx_mps,vy_mps\n0,1,0\n",
            "w.csv:1",
            "at least two",
        ),
        (
            "altitude_m,vx_mps,vy_mps\n0,1,0\n5,1\n",
            "w.csv:3",
            "fields",
        ),
    ];
    for (csv, at, why) in cases {
        std::fs::write(dir.path().join("w.csv"), csv).unwrap();
        let e = dropped(dir.path(), TABLE, &[]).unwrap_err();
        assert!(
            e.contains("wind.file") && e.contains(at) && e.contains(why),
            "{csv:?}: {e}"
        );
    }
}

#[test]
fn a_table_gives_the_whole_wind() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("w.csv"),
        "altitude_m,vx_mps,vy_mps\n0,1,0\n9,1,0\n",
    )
    .unwrap();
    let e = dropped(dir.path(), TABLE, &["fluid.wind_mps=[2,0,0]"]).unwrap_err();
    assert!(e.contains("fluid.wind_mps") && e.contains("table"), "{e}");
}
