//! docs/scenarios.md holds exactly the key tables the declarations generate.

use std::path::Path;

/// The page's key tables are what `chute::scenario::docs::update` generates from the key
/// declarations; `CHUTE_BLESS=1` rewrites them.
#[test]
fn scenarios_md_key_tables_match_the_declarations() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scenarios.md");
    let text = std::fs::read_to_string(&path).expect("docs/scenarios.md");
    let want =
        chute::scenario::docs::update(&text).unwrap_or_else(|e| panic!("docs/scenarios.md: {e}"));
    if std::env::var_os("CHUTE_BLESS").is_some() {
        std::fs::write(&path, &want).expect("write docs/scenarios.md");
        return;
    }
    let diff = text.lines().zip(want.lines()).position(|(a, b)| a != b);
    assert!(
        text == want,
        "docs/scenarios.md differs from the key declarations (crates/chute/src/scenario/sections.rs) \
         at line {}; regenerate with `CHUTE_BLESS=1 cargo test -p chute --test scenario docs`",
        diff.map_or(text.lines().count().min(want.lines().count()) + 1, |i| i + 1)
    );
}
