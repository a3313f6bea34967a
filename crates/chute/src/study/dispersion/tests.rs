use std::path::{Path, PathBuf};

use super::super::draw::{Distribution, Sampler};
use super::super::Study;

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

/// A study of `drop-wind.toml` with this `[dispersion]` body.
fn study(body: &str) -> Result<Study, String> {
    let text = format!("name = \"d\"\nbase = \"drop-wind.toml\"\n{body}");
    Study::from_str(&text, "d.toml", &scenarios()).map_err(|e| e.to_string())
}

const TWO: &str = "[dispersion]\nsamples = 20\nseed = 5\nlatin_hypercube = true\n\
    [[dispersion.vary]]\nkey = \"load.weight_n\"\n\
    normal = { mean = 100.0, std_dev = 5.0, lo = 90.0, hi = 115.0 }\n\
    [[dispersion.vary]]\nkey = \"fluid.wind_mps[1]\"\ntriangular = { lo = -2.0, mode = 0.0, hi = 3.0 }\n";

#[test]
fn each_sample_is_a_case_with_its_drawn_values() {
    let st = study(TWO).unwrap();
    assert_eq!(st.cases.len(), 20);
    let dists = [
        Distribution::try_normal(100.0, 5.0, 90.0, 115.0).unwrap(),
        Distribution::try_triangular(-2.0, 0.0, 3.0).unwrap(),
    ];
    let sampler = Sampler {
        seed: 5,
        samples: 20,
        latin_hypercube: true,
    };
    for (i, c) in st.cases.iter().enumerate() {
        assert_eq!(c.name, format!("sample-{i:05}"));
        let drawn = sampler.draw(i, &dists);
        // The case's scenario holds exactly the drawn numbers; the vector keeps the base's
        // other components (5 m/s along x).
        let s = st.scenario(c, &[]).unwrap();
        assert_eq!(s.load.weight_n, drawn[0]);
        assert_eq!(s.fluid.wind_mps, [5.0, drawn[1], 0.0]);
    }
}

#[test]
fn bad_dispersions_are_refused_naming_the_entry() {
    let one = |vary: &str| {
        study(&format!(
            "[dispersion]\nsamples = 4\nseed = 1\n[[dispersion.vary]]\n{vary}\n"
        ))
        .unwrap_err()
    };
    let cases = [
        ("key = \"load.weight_nn\"\nuniform = { lo = 1.0, hi = 2.0 }", "load.weight_nn"),
        ("key = \"load.weight_n\"\nnormal = { mean = 100.0, std_dev = -1.0 }", "negative"),
        (
            "key = \"load.weight_n\"\nnormal = { mean = 100.0, std_dev = 1.0, lo = 101.0 }",
            "strictly inside",
        ),
        (
            "key = \"load.weight_n\"\nuniform = { lo = 1.0, hi = 2.0 }\ntriangular = { lo = 0.0, mode = 1.0, hi = 2.0 }",
            "exactly one",
        ),
        ("key = \"fluid.wind_mps[3]\"\nuniform = { lo = 1.0, hi = 2.0 }", "3 components"),
        ("key = \"load.weight_n[0]\"\nuniform = { lo = 1.0, hi = 2.0 }", "not a list"),
        ("key = \"load.weight_n\"\nuniform = { lo = -5.0, hi = -1.0 }", "load.weight_n"),
        ("key = \"fluid.wind_mps[+0]\"\nuniform = { lo = 1.0, hi = 2.0 }", "must be a number"),
    ];
    for (vary, what) in cases {
        let e = one(vary);
        assert!(e.contains(what), "{vary}: {e}");
    }
    let e = study("[dispersion]\nsamples = 0\nseed = 1\nvary = []\n").unwrap_err();
    assert!(e.contains("dispersion.samples"), "{e}");
    // One sample has no footprint.
    let e = study(&TWO.replace("samples = 20", "samples = 1")).unwrap_err();
    assert!(e.contains("give 2 to"), "{e}");
    // A shared override of a drawn key would be replaced by the draw.
    let e =
        study(&TWO.replace("seed = 5\n", "seed = 5\nset = [\"load.weight_n=50\"]\n")).unwrap_err();
    assert!(
        e.contains("dispersion.set") && e.contains("draws `load.weight_n`"),
        "{e}"
    );
    let e = study(&format!("{TWO}[grid]\n\"load.weight_n\" = [1.0]\n")).unwrap_err();
    assert!(e.contains("one of"), "{e}");
}

#[test]
fn zero_spread_gives_identical_cases() {
    let st = study(
        "[dispersion]\nsamples = 6\nseed = 9\n[[dispersion.vary]]\nkey = \"load.weight_n\"\n\
         uniform = { lo = 120.0, hi = 120.0 }\n",
    )
    .unwrap();
    assert!(st
        .cases
        .iter()
        .all(|c| c.set == vec!["load.weight_n=120.0".to_string()]));
}

/// `set` reaches every sample before its draws, and a vector key the base leaves unset starts
/// from zeros (the release point).
#[test]
fn shared_overrides_and_an_unset_vector_key() {
    let st = study(
        "[dispersion]\nsamples = 3\nseed = 2\nset = [\"canopy.edge_length_m=0.35\"]\n\
         [[dispersion.vary]]\nkey = \"canopy.release_point_m[1]\"\nuniform = { lo = -5.0, hi = 5.0 }\n",
    )
    .unwrap();
    assert_eq!(
        st.dispersion,
        Some(vec!["canopy.release_point_m[1]".to_string()])
    );
    for c in &st.cases {
        assert_eq!(c.set[0], "canopy.edge_length_m=0.35");
        let s = st.scenario(c, &[]).unwrap();
        assert_eq!(s.canopy.edge_length_m, 0.35);
        let [x, y] = s.canopy.release_point_m.unwrap();
        assert!(x == 0.0 && (-5.0..=5.0).contains(&y), "{x} {y}");
    }
    // A shared override the base refuses is the dispersion's error, naming the key.
    let bad = study(
        "[dispersion]\nsamples = 3\nseed = 2\nset = [\"canopy.edge_length_m=-1\"]\n\
         [[dispersion.vary]]\nkey = \"load.weight_n\"\nuniform = { lo = 90.0, hi = 110.0 }\n",
    )
    .unwrap_err();
    assert!(bad.contains("canopy.edge_length_m"), "{bad}");
}

/// A component is named one way in the outputs however the file spells it, and a study-wide
/// override of a drawn key (or of the vector a drawn component belongs to) is refused.
#[test]
fn drawn_keys_are_named_one_way_and_not_overridden() {
    let st = study(&TWO.replace("fluid.wind_mps[1]", "fluid.wind_mps [01]")).unwrap();
    assert_eq!(
        st.dispersion,
        Some(vec![
            "load.weight_n".to_string(),
            "fluid.wind_mps[1]".to_string()
        ])
    );
    for set in ["fluid.wind_mps=[0, 4, 0]", "load.weight_n=40"] {
        let e = st
            .scenario(&st.cases[0], &[set.to_string()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("--set") && e.contains("draws"), "{e}");
    }
    assert!(st
        .scenario(&st.cases[0], &["fluid.drag_coefficient=1.2".into()])
        .is_ok());
}
