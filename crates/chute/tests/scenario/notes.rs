//! The rules that key declarations state in prose (`.note(…)`, the docs' "allowed" column) are
//! enforced: each one has a case here that breaks it and the error (or warning) that follows,
//! naming the key. A note without a case fails [`every_note_has_a_case`], so the docs cannot
//! state a rule that no test holds the code to.

use std::path::Path;

use chute::scenario::sections::SECTIONS;
use chute::scenario::Scenario;

/// What breaking a note's rule must produce.
enum Expect {
    /// The loader refuses the scenario; the message holds the key and this text.
    Refused(&'static str),
    /// The scenario loads, the builder refuses it; the message holds the key and this text.
    Unbuildable(&'static str),
    /// The scenario loads with a warning (loader notes or plausibility) holding this text.
    Warned(&'static str),
    /// The note describes a value's meaning, not a rule (why it needs no case).
    Meaning(&'static str),
}

use Expect::*;

/// One broken rule: the note's key (`section.key`), a bundled scenario, text appended to it
/// and `--set` overrides.
struct Case {
    key: &'static str,
    base: &'static str,
    extra: &'static str,
    set: &'static [&'static str],
    expect: Expect,
}

const fn case(
    key: &'static str,
    base: &'static str,
    set: &'static [&'static str],
    expect: Expect,
) -> Case {
    Case {
        key,
        base,
        extra: "",
        set,
        expect,
    }
}

/// A coarse payload canopy with lines (`control-steer` at 0.3 m triangles).
const PAYLOAD: &str = "control-steer";
const GUIDED: &str = "control-guidance";
const SHELL: &str = "report-shell-4-sites";
const ROD: &str = "report-rod-200n";
const FABRIC: &str = "round-fabric";
const ROUND: &str = "round-solid";

/// A packed round canopy with contact.
const OPENING: &str = "opening";
/// A canopy falling from altitude through a wind that grows with height.
const WINDY: &str = "drop-wind";
/// A payload canopy with ground, an altimeter and a pull it starts.
const LANDING: &str = "control-soft-landing";

const CASES: &[Case] = &[
    case(
        "name",
        SHELL,
        &["name=.hidden"],
        Refused("not starting with"),
    ),
    case(
        "canopy.shape",
        ROD,
        &["canopy.shape=circle"],
        Refused("rectangle"),
    ),
    case(
        "canopy.thickness_m",
        SHELL,
        &["canopy.thickness_m=0.5"],
        Refused("1/10"),
    ),
    case(
        "canopy.edge_length_m",
        SHELL,
        &["canopy.edge_length_m=5"],
        Refused("two edges"),
    ),
    case(
        "canopy.mesh_file",
        SHELL,
        &[
            "canopy.shape=mesh",
            "canopy.mesh_file=no-such-mesh.obj",
            "load.sites=center",
        ],
        Refused("no-such-mesh.obj"),
    ),
    case(
        "canopy.released_with_wind",
        WINDY,
        &["canopy.initial_velocity_mps=[1.0, 0.0, 0.0]"],
        Refused("set one"),
    ),
    case(
        "canopy.vent_radius_m",
        ROUND,
        &["canopy.vent_radius_m=1.4"],
        Refused("edge_length_m"),
    ),
    case(
        "contact.distance_m",
        OPENING,
        &["contact.distance_m=0.2"],
        Refused("edge_length_m / 2"),
    ),
    case(
        "opening.mesh_file",
        OPENING,
        &[
            "opening.pack=mesh",
            "opening.mesh_file=../crates/chute/data/meshes/hexparachute_n6_python.txt",
        ],
        Unbuildable("not the canopy mesh"),
    ),
    case(
        "opening.packed_radius_m",
        OPENING,
        &["opening.packed_radius_m=0.9"],
        Refused("radius_m / 2"),
    ),
    case(
        "opening.attitude_deg",
        OPENING,
        &["opening.attitude_deg=20", "fluid.inflation_speed=\"panel\""],
        Refused("inflation_speed = \"canopy\""),
    ),
    case(
        "canopy.imperfection_m",
        SHELL,
        &["canopy.imperfection_m=0.5"],
        Refused("5 %"),
    ),
    case(
        "material.fabric_poisson_ratio",
        FABRIC,
        &["material.fabric_poisson_ratio=3"],
        Refused("positive definite"),
    ),
    case(
        "material.wrinkle_strain",
        FABRIC,
        &[
            "material.no_compression=true",
            "material.wrinkle_strain=0.01",
        ],
        Refused("above 0.1"),
    ),
    case(
        "material.permeability_m2",
        FABRIC,
        &[
            "material.permeability_m2=1e-12",
            "material.air_permeability_cfm=5",
        ],
        Refused("air_permeability_cfm"),
    ),
    case(
        "material.air_permeability_cfm",
        FABRIC,
        &[
            "material.air_permeability_cfm=5",
            "fluid.drag=linear",
            "fluid.linear_drag_coefficient_n_s_m=10",
        ],
        Refused("linear"),
    ),
    case(
        "material.forchheimer_coefficient",
        FABRIC,
        &["material.forchheimer_coefficient=0.1"],
        Refused("permeability"),
    ),
    case(
        "load.mode",
        SHELL,
        &["load.mode=node_mass_scale"],
        Refused("mesh"),
    ),
    case(
        "load.sites",
        SHELL,
        &["load.sites=[[100.0, 0.0]]"],
        Refused("outside the canopy"),
    ),
    case(
        "load.node",
        "dismech-hex-n6",
        &["load.mode=node_mass_scale", "load.node=100000"],
        Unbuildable("node"),
    ),
    case(
        "lines.drag_coefficient",
        PAYLOAD,
        &[],
        Meaning("0 is a value, not a refusal"),
    ),
    case(
        "fluid.incidence_alpha_deg",
        ROUND,
        &[
            "fluid.incidence_alpha_deg=[-90, 0, 45]",
            "fluid.incidence_cn=[0, 0, 0]",
        ],
        Refused("90"),
    ),
    case(
        "fluid.incidence_cn",
        ROUND,
        &[
            "fluid.incidence_alpha_deg=[-90, 0, 90]",
            "fluid.incidence_cn=[0.1, 0, 0.1]",
        ],
        Refused("odd"),
    ),
    case(
        "atmosphere.model",
        "drop-1000m",
        &["fluid.density_kg_m3=1.0"],
        Warned("density_kg_m3"),
    ),
    case(
        "atmosphere.ground_altitude_m",
        PAYLOAD,
        &["atmosphere.ground_altitude_m=10"],
        Refused("below"),
    ),
    case(
        "time.dt_s",
        SHELL,
        &["time.dt_s=20", "time.duration_s=10"],
        Refused("duration_s"),
    ),
    case(
        "time.dt_min_s",
        SHELL,
        &["time.adaptive=true", "time.dt_min_s=1"],
        Refused("dt_s"),
    ),
    case(
        "time.dt_max_s",
        SHELL,
        &["time.adaptive=true", "time.dt_max_s=1e-5"],
        Refused("dt_s"),
    ),
    case(
        "output.frame_interval_s",
        SHELL,
        &["output.frame_interval_s=1e-5"],
        Refused("dt_s"),
    ),
    case(
        "output.snapshots_s",
        SHELL,
        &["output.snapshots_s=[1.0001, 1.0002]"],
        Warned("millisecond"),
    ),
    case(
        "control.lines",
        PAYLOAD,
        &["control[0].lines=[99]"],
        Refused("lines"),
    ),
    case(
        "control.shorten_m",
        PAYLOAD,
        &["control[0].shorten_m=2.9"],
        Refused("10 %"),
    ),
    case(
        "control.sensor",
        LANDING,
        &["control[0].sensor=radar"],
        Refused("radar"),
    ),
    case(
        "control.below_m",
        PAYLOAD,
        &["control[0].below_m=1"],
        Refused("sensor"),
    ),
    Case {
        key: "sensor.name",
        base: LANDING,
        extra: "\n[[sensor]]\nname = \"altimeter\"\n",
        set: &[],
        expect: Refused("altimeter"),
    },
    case(
        "sensor.rate_hz",
        LANDING,
        &["sensor[0].rate_hz=1e9", "time.duration_s=1"],
        Refused("at most"),
    ),
    case(
        "sensor.seed",
        LANDING,
        &["sensor[0].seed=-1"],
        Refused("seed"),
    ),
    case(
        "fluid.added_mass",
        WINDY,
        &["fluid.added_mass=true"],
        Refused("[wind]"),
    ),
    Case {
        key: "wind.roughness_m",
        base: "drop-1000m",
        extra: "\n[wind]\nprofile = \"log\"\nroughness_m = 20.0\n",
        set: &[],
        expect: Refused("below"),
    },
    Case {
        key: "wind.file",
        base: "drop-1000m",
        extra: "\n[wind]\nprofile = \"table\"\nfile = \"no-such-winds.csv\"\n",
        set: &[],
        expect: Refused("no-such-winds.csv"),
    },
    case(
        "guidance.target_m",
        GUIDED,
        &["guidance.target_m=[1.0]"],
        Refused("two"),
    ),
    case(
        "guidance.max_pull_m",
        GUIDED,
        &["guidance.max_pull_m=100"],
        Refused("10 %"),
    ),
    case(
        "guidance.pull_side",
        GUIDED,
        &["canopy.shape=hexagon", "load.sites=corners"],
        Refused("shape"),
    ),
    case(
        "guidance.ramp_s",
        GUIDED,
        &["guidance.ramp_s=2", "guidance.update_s=1"],
        Refused("update_s"),
    ),
];

fn scenario_text(base: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenarios/{base}.toml"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The key as messages write it: `control[0].lines` for an entry of an array section.
fn named(msg: &str, key: &str) -> bool {
    let (section, name) = key.split_once('.').unwrap_or(("", key));
    msg.contains(key) || (msg.contains(section) && msg.contains(name))
}

/// Break `c`'s rule; `Err` says how the outcome differs from the expected one.
fn check(c: &Case) -> Result<(), String> {
    let text = scenario_text(c.base) + c.extra;
    let set: Vec<String> = c.set.iter().map(|s| s.to_string()).collect();
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenarios/{}.toml", c.base));
    let loaded = Scenario::from_str_with_name(&text, &file.to_string_lossy(), &set);
    let ctx = format!("{} ({} {:?})", c.key, c.base, c.set);
    // The rule is broken by the case's change, not by the scenario it starts from.
    Scenario::from_str_with_name(&scenario_text(c.base), &file.to_string_lossy(), &[])
        .map_err(|e| format!("{ctx}: the base does not load: {e}"))?;
    let says = |msg: &str, what: &str| match named(msg, c.key) && msg.contains(what) {
        true => Ok(()),
        false => Err(format!("{ctx}: wanted the key and {what:?} in: {msg}")),
    };
    match c.expect {
        Refused(what) => match loaded {
            Ok(_) => Err(format!("{ctx}: accepted")),
            Err(e) => says(&e.to_string(), what),
        },
        Unbuildable(what) => match chute::build::build(&loaded.map_err(|e| format!("{ctx}: {e}"))?)
        {
            Ok(_) => Err(format!("{ctx}: built")),
            Err(e) => says(&e.to_string(), what),
        },
        Warned(what) => {
            let s = loaded.map_err(|e| format!("{ctx}: {e}"))?;
            let mut warnings = s.notes.0.clone();
            warnings.extend(chute::api::plausibility_warnings(&s));
            warnings
                .iter()
                .find(|w| says(w, what).is_ok())
                .map(|_| ())
                .ok_or(format!(
                    "{ctx}: no warning with the key and {what:?} in {warnings:?}"
                ))
        }
        Meaning(why) => match why.is_empty() {
            true => Err(format!("{ctx}: say why the note needs no case")),
            false => Ok(()),
        },
    }
}

#[test]
fn every_noted_rule_is_enforced() {
    let failed: Vec<String> = CASES.iter().filter_map(|c| check(c).err()).collect();
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn every_note_has_a_case() {
    for section in SECTIONS {
        for k in section.keys.iter().filter(|k| !k.meta.note.is_empty()) {
            let key = match section.name {
                "" => k.name.to_string(),
                s => format!("{s}.{}", k.name),
            };
            assert!(
                CASES.iter().any(|c| c.key == key),
                "{key}'s note ({:?}) states a rule that no case in tests/scenario/notes.rs breaks",
                k.meta.note
            );
        }
    }
}
