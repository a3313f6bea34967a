//! No scenario text or override, however mangled, makes the parser panic: mutated versions
//! of the bundled scenarios and random `--set` arguments must give `Ok` or a `ScenarioError`.

use chute::scenario::{schema, Scenario};
use proptest::prelude::*;

use crate::common::mutate;

const SEEDS: &[&str] = &[
    include_str!("../../../../scenarios/report-rod-200n.toml"),
    include_str!("../../../../scenarios/report-shell-6-sites.toml"),
    include_str!("../../../../scenarios/round-parachute.toml"),
    include_str!("../../../../scenarios/dismech-hex-n6.toml"),
];

const TOKENS: &[&str] = &[
    "1e-300",
    "-5",
    "2",
    "100000000",
    "0.5",
    "3.0",
    "[0, 0, 0]",
    "[]",
    "[1, 2, 3]",
    "\"ends\"",
    "\"center\"",
    "=",
    "[",
    "]",
    "\"",
    "'",
    "nan",
    "inf",
    "-1e309",
    "1e308",
    "0",
    "-0.0",
    "[[1,2]]",
    "[[1e9, -1e9]]",
    "[canopy]",
    "[load]",
    "[[case]]",
    "\n",
    "{",
    "}",
    "0x10",
    "1979-05-27",
    "true",
    "\"mesh\"",
    "\"rim\"",
    "nodes = 2",
    "nodes = 99999999999",
    "span_m = 1e-300",
    "dt_s = 1e-300",
    "\\u0000",
    "é",
    ".",
    "#",
    "sites = []",
    "sites = [[]]",
    "kind = \"rod\"",
    "shape = \"hexagon\"",
    "mode = \"node_mass_scale\"",
];

fn mutate(text: &str, ops: &[(u8, usize, String)]) -> String {
    let mut t = text.to_string();
    for (op, pos, payload) in ops {
        let lines: Vec<String> = t.lines().map(str::to_string).collect();
        let n = lines.len().max(1);
        t = match op % 8 {
            0 => mutate::insert(&t, *pos, payload),
            1 => mutate::delete(&t, *pos, payload.len()),
            2 => {
                let mut l = lines.clone();
                if !l.is_empty() {
                    l[pos % n] = payload.clone();
                }
                l.join("\n")
            }
            3 if !lines.is_empty() => mutate::duplicate_line(lines, *pos),
            4 if lines.len() > 1 => mutate::swap_lines(lines, *pos),
            3 | 4 => lines.join("\n"),
            // Keep a `key = value` line's key and give it a wild value: valid TOML that
            // reaches the schema and physical checks.
            5 | 6 => {
                let mut l = lines.clone();
                let with_eq: Vec<usize> = (0..l.len()).filter(|&i| l[i].contains('=')).collect();
                if !with_eq.is_empty() {
                    let k = with_eq[pos % with_eq.len()];
                    let key = l[k].split('=').next().unwrap_or("").to_string();
                    let tok = if *op % 8 == 5 {
                        TOKENS[(pos / 7919) % TOKENS.len()].to_string()
                    } else {
                        payload.clone()
                    };
                    l[k] = format!("{key}= {tok}");
                }
                l.join("\n")
            }
            _ => mutate::insert(&t, *pos, TOKENS[pos % TOKENS.len()]),
        };
    }
    t
}

fn override_strategy() -> impl Strategy<Value = String> {
    let keys = schema::all_keys();
    prop_oneof![
        1 => "[a-z_.=]{0,24}[\\PC]{0,10}",
        4 => (0..keys.len(), prop::sample::select(TOKENS.to_vec()), prop_oneof![Just(String::new()), "[\\PC]{0,6}".boxed()])
            .prop_map(move |(k, tok, extra)| format!("{}={tok}{extra}", keys[k])),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenarios_never_panic(
        seed in 0..SEEDS.len(),
        ops in prop::collection::vec((any::<u8>(), any::<usize>(), "[\\PC\n]{0,12}"), 1..4),
        sets in prop_oneof![2 => Just(Vec::new()), 1 => prop::collection::vec(override_strategy(), 1..3)],
    ) {
        let text = mutate(SEEDS[seed], &ops);
        let result = Scenario::from_str_with_name(&text, "fuzz/case.toml", &sets);
        if let Err(e) = result {
            // Every error renders to a non-empty single message.
            prop_assert!(!e.to_string().is_empty());
        }
    }
}

/// The mutator must reach past the TOML parser often, or the property above would only
/// exercise syntax errors: count how mutated texts fare, deterministically.
#[test]
fn mutations_reach_the_schema_and_physical_checks() {
    use chute::scenario::ScenarioError;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    let mut rng = StdRng::seed_from_u64(7);
    let (mut syntax, mut later, mut ok) = (0, 0, 0);
    for _ in 0..2000 {
        let seed = SEEDS[rng.random_range(0..SEEDS.len())];
        let ops: Vec<(u8, usize, String)> = (0..rng.random_range(1..4))
            .map(|_| {
                (
                    rng.random::<u8>(),
                    rng.random::<u32>() as usize,
                    "x".repeat(rng.random_range(0..3)),
                )
            })
            .collect();
        match Scenario::from_str_with_name(&mutate(seed, &ops), "fuzz/case.toml", &[]) {
            Ok(_) => ok += 1,
            Err(ScenarioError::Syntax { .. }) => syntax += 1,
            Err(_) => later += 1,
        }
    }
    eprintln!("syntax errors {syntax}, later errors {later}, accepted {ok}");
    assert!(
        later >= 300 && ok >= 100,
        "syntax {syntax}, later {later}, ok {ok}"
    );
}
