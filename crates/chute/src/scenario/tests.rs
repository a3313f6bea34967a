//! The declaration mechanism on the shapes of keys the format does not have yet: an array
//! of tables (`[[control]]`) whose errors name the entry, a key only valid with another
//! key's value, an optional section. The sections here exist only in this test.

use super::error::{Origin, ScenarioError};
use super::keys::{choice, key, section, when, Bound, Section};
use super::source::{self, Provenance};
use super::validate::Checker;
use super::{docs, overrides, rules, schema};

choice! {
    /// Membrane model.
    pub enum Membrane {
        /// Edge springs.
        Springs = "springs",
        /// Orthotropic fabric.
        Fabric = "fabric",
    }
}

section! {
    /// `[shell]`.
    pub struct Shell {
        /// membrane model
        membrane: Membrane = Membrane::Springs => key(),
        /// warp modulus
        #[serde(skip_serializing_if = "Option::is_none")]
        warp_modulus_pa: Option<f64> = None => key()
            .unit("Pa")
            .positive("a stiffness")
            .only_with(when("shell.membrane", "fabric"), ""),
    }
}

section! {
    /// One `[[control]]` entry.
    pub struct Pull {
        /// pulled lines
        lines: Vec<usize> = Vec::new() => key().required("say which lines to pull"),
        /// start of the pull
        start_s: f64 = 0.0 => key().unit("s").non_negative("a time"),
        /// shortening
        shorten_m: f64 = 0.0 => key().unit("m").range(Bound::Open, Bound::Incl(1.0), "a pull"),
    }
}

section! {
    /// `[guidance]`.
    pub struct Guidance {
        /// target
        target_m: Vec<f64> = Vec::new() => key().unit("m").required("say where to fly"),
    }
}

const SECTIONS: &[Section] = &[
    Section::table::<Shell>("shell"),
    Section::array::<Pull>("control"),
    Section::optional::<Guidance>("guidance").only_with(when("shell.membrane", "fabric"), ""),
];

const TEXT: &str = "[shell]\nmembrane = \"springs\"\n\
                    [[control]]\nlines = [0, 1]\nstart_s = 1.0\n\
                    [[control]]\nlines = [2]\nshorten_m = 0.5\n";

fn parse(text: &str) -> (toml::Table, Provenance) {
    source::parse(text, "c.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// The first declared-rule violation of `table` (already type-checked).
fn rules_of(table: &toml::Table, prov: &Provenance) -> Result<(), ScenarioError> {
    let mut c = Checker::new(prov);
    rules::declared(&mut c, SECTIONS, table);
    c.first()
}

#[test]
fn array_entries_are_checked_and_named_by_index() {
    let (t, prov) = parse(TEXT);
    schema::check_in(SECTIONS, &t, &prov).unwrap();
    schema::required_in(SECTIONS, &t).unwrap();
    rules_of(&t, &prov).unwrap();

    let (t, prov) = parse(&TEXT.replace("shorten_m", "shortn_m"));
    match schema::check_in(SECTIONS, &t, &prov).unwrap_err() {
        ScenarioError::UnknownKey {
            key,
            origin,
            suggestion,
        } => {
            assert_eq!(key, "control[1].shortn_m");
            assert!(matches!(origin, Origin::File { line: 8, .. }), "{origin:?}");
            assert_eq!(suggestion.as_deref(), Some("control[1].shorten_m"));
        }
        e => panic!("{e:?}"),
    }

    let (t, prov) = parse(&TEXT.replace("start_s = 1.0", "start_s = \"soon\""));
    let e = schema::check_in(SECTIONS, &t, &prov).unwrap_err();
    assert_eq!(e.key(), Some("control[0].start_s"), "{e}");
    assert!(e.to_string().contains("(c.toml:5) must be a number"), "{e}");

    let (t, _) = parse(&TEXT.replace("lines = [2]\n", ""));
    let e = schema::required_in(SECTIONS, &t).unwrap_err();
    assert_eq!(e.key(), Some("control[1].lines"), "{e}");

    let (t, prov) = parse(&TEXT.replace("shorten_m = 0.5", "shorten_m = 2"));
    let e = rules_of(&t, &prov).unwrap_err();
    assert_eq!(
        e.to_string(),
        "`control[1].shorten_m` (c.toml:8) = 2 is invalid: must be at most 1 (a pull)"
    );
}

#[test]
fn only_with_names_the_condition_and_optional_sections_obey_it() {
    let (t, prov) = parse("[shell]\nwarp_modulus_pa = 1e9\n");
    let e = rules_of(&t, &prov).unwrap_err();
    assert_eq!(
        e.to_string(),
        "`shell.warp_modulus_pa` (c.toml:2) = 1e9 is invalid: only used with \
         `shell.membrane = \"fabric\"`"
    );
    let (t, prov) = parse("[shell]\nmembrane = \"fabric\"\nwarp_modulus_pa = -1\n");
    let e = rules_of(&t, &prov).unwrap_err();
    assert!(
        e.to_string().contains("must be positive (a stiffness)"),
        "{e}"
    );

    // An optional section: absent is fine, written without its condition is refused, and
    // its required keys are only required when it is written.
    let (t, prov) = parse("[shell]\nmembrane = \"fabric\"\n");
    schema::required_in(SECTIONS, &t).unwrap();
    rules_of(&t, &prov).unwrap();
    let (t, prov) = parse("[guidance]\ntarget_m = [1, 2]\n");
    let e = rules_of(&t, &prov).unwrap_err();
    assert_eq!(e.key(), Some("guidance"), "{e}");
    assert!(
        e.to_string()
            .contains("only used with `shell.membrane = \"fabric\"`"),
        "{e}"
    );
    let (t, _) = parse("[guidance]\n");
    let e = schema::required_in(SECTIONS, &t).unwrap_err();
    assert_eq!(e.key(), Some("guidance.target_m"), "{e}");
}

#[test]
fn overrides_reach_array_entries() {
    let (mut t, mut prov) = parse(TEXT);
    let set = |s: &str| vec![s.to_string()];
    overrides::apply_in(SECTIONS, &mut t, &mut prov, &set("control[1].start_s=2.5")).unwrap();
    overrides::apply_in(SECTIONS, &mut t, &mut prov, &set("control[2].lines=[3]")).unwrap();
    let entries = t["control"].as_array().unwrap();
    assert_eq!(entries.len(), 3);
    assert_eq!(entries[1]["start_s"].as_float(), Some(2.5));
    assert_eq!(entries[2]["lines"].as_array().map(Vec::len), Some(1));
    let arg = "control[2].shorten_m=5";
    overrides::apply_in(SECTIONS, &mut t, &mut prov, &set(arg)).unwrap();
    let e = rules_of(&t, &prov).unwrap_err();
    assert!(
        e.to_string().contains(&format!("(from `--set {arg}`)")),
        "{e}"
    );

    let e = overrides::apply_in(SECTIONS, &mut t, &mut prov, &set("control[7].start_s=1"));
    assert!(matches!(e, Err(ScenarioError::BadOverride { .. })), "{e:?}");
    // A whole array at once; an error inside it is reported from that `--set`.
    let arg = "control=[{lines = [0], start_s = -1}]";
    overrides::apply_in(SECTIONS, &mut t, &mut prov, &set(arg)).unwrap();
    schema::check_in(SECTIONS, &t, &prov).unwrap();
    let e = rules_of(&t, &prov).unwrap_err();
    assert_eq!(e.key(), Some("control[0].start_s"), "{e}");
    assert!(
        e.to_string().contains(&format!("(from `--set {arg}`)")),
        "{e}"
    );
}

#[test]
fn docs_tables_cover_new_shapes() {
    let table = docs::table(SECTIONS, &SECTIONS[1]);
    assert!(
        table.contains("| `shorten_m` | shortening | m | 0 | ≤ 1 |"),
        "{table}"
    );
    assert!(
        table.contains("| `lines` | pulled lines | – | **required** | non-negative integers |"),
        "{table}"
    );
    assert_eq!(Membrane::NAMES, ["springs", "fabric"]);
    assert_eq!(Membrane::Fabric.name(), "fabric");
    let table = docs::table(SECTIONS, &SECTIONS[0]);
    assert!(
        table.contains("| > 0; only with `shell.membrane = \"fabric\"` |"),
        "{table}"
    );
}

/// A scenario named by a bare file name resolves its relative paths against the current
/// directory as an absolute path, so a run records its mesh where `chute resume` finds it
/// from any directory.
#[test]
fn a_bare_scenario_name_has_an_absolute_base_directory() {
    let cwd = std::env::current_dir().unwrap();
    for name in ["s.toml", "./s.toml"] {
        let dir = super::parse::base_dir(std::path::Path::new(name));
        assert!(dir.is_absolute(), "{name}: {dir:?}");
        assert_eq!(dir, cwd, "{name}");
    }
    let sub = super::parse::base_dir(std::path::Path::new("sub/../s.toml"));
    assert_eq!(sub, cwd, "a `..` is normalized away");
}
