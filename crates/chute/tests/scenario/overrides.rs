//! `--set` overrides: TOML values, plain strings, order, and new sections.

use chute::scenario::{LoadMode, Scenario, SiteSet, Sites};

const BASE: &str = "[model]\nkind = \"shell\"\n[load]\nweight_n = 200\nmode = \"mass\"\n";

fn with(set: &[&str]) -> Scenario {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    Scenario::from_str_with_name(BASE, "base.toml", &set).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn plain_strings_and_toml_values() {
    let s = with(&[
        "load.mode=force",
        "fluid.wind_mps=[4,0,0]",
        "load.weight_n=20",
    ]);
    assert_eq!(s.load.mode, LoadMode::Force);
    assert_eq!(s.fluid.wind_mps, [4.0, 0.0, 0.0]);
    assert_eq!(s.load.weight_n, 20.0);
    let s = with(&["load.mode=\"payload\"", "load.sites = corners_and_midspan"]);
    assert_eq!(s.load.mode, LoadMode::Payload);
    assert_eq!(s.load.sites, Sites::Named(SiteSet::CornersAndMidspan));
    let s = with(&["load.sites=[[1, 0.5], [-1, -0.5]]"]);
    assert_eq!(s.load.sites, Sites::Points(vec![[1.0, 0.5], [-1.0, -0.5]]));
}

#[test]
fn string_keys_take_the_raw_text() {
    let s = with(&["name=2024"]);
    assert_eq!(s.name, "2024");
    let s = with(&["name=run.v2"]);
    assert_eq!(s.name, "run.v2");
}

#[test]
fn later_overrides_win_and_sections_are_created() {
    let s = with(&["load.weight_n=20", "load.weight_n=2000"]);
    assert_eq!(s.load.weight_n, 2000.0);
    let s = with(&["time.dt_s=5e-4", "output.frame_interval_s=0.1"]);
    assert_eq!((s.time.dt_s, s.output.frame_interval_s), (5e-4, 0.1));
}

#[test]
fn a_value_with_an_embedded_newline_stays_one_string() {
    // Not a TOML injection of a second key: taken as a plain string, then refused as a number.
    let e = Scenario::from_str_with_name(BASE, "b.toml", &["load.weight_n=1\nname = \"x\"".into()])
        .unwrap_err();
    assert!(e.to_string().contains("must be a number"), "{e}");
}

#[test]
fn overrides_go_through_the_same_validation() {
    let e = Scenario::from_str_with_name(BASE, "b.toml", &["time.dt_s=nan".into()]).unwrap_err();
    assert!(e.to_string().contains("finite"), "{e}");
    let e = Scenario::from_str_with_name(BASE, "b.toml", &["load.sites=ends".into()]).unwrap_err();
    assert!(e.to_string().contains("rectangular shell"), "{e}");
}
