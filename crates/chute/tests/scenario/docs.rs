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

/// Every value the docs state for a named constant or solver default, as the scanner reads
/// them: `` `name = V` ``, or `` `name` `` (or `` `Type::name` ``) followed by at most a symbol
/// (`η`) and `=`, `(` or `,` before the number V. Returns (page, value text) pairs.
fn statements(name: &str) -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs");
    let mut out = Vec::new();
    for entry in std::fs::read_dir(&dir).expect("docs/") {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "md") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap().replace('\n', " ");
        let page = path.file_name().unwrap().to_string_lossy().to_string();
        // Backticked segments: odd pieces of a split on '`'.
        let pieces: Vec<&str> = text.split('`').collect();
        for (i, seg) in pieces.iter().enumerate().filter(|(i, _)| i % 2 == 1) {
            let (head, inside) = seg.split_once('=').unwrap_or((seg, ""));
            let head = head.trim();
            if head != name && !head.ends_with(&format!("::{name}")) {
                continue;
            }
            let after = if inside.is_empty() {
                // `name` then a symbol and a separator, outside the backticks.
                let rest = pieces.get(i + 1).copied().unwrap_or("").trim_start();
                let rest = rest
                    .split_once(' ')
                    .filter(|(sym, _)| {
                        sym.chars().count() == 1 && !sym.starts_with(['(', ',', '='])
                    })
                    .map_or(rest, |(_, r)| r.trim_start());
                match rest.chars().next() {
                    Some('=' | '(' | ',') => rest[1..].trim_start().to_string(),
                    _ => continue,
                }
            } else {
                inside.trim().to_string()
            };
            let number: String = after
                .chars()
                .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | '-' | '+'))
                .collect();
            if !number.is_empty() {
                out.push((page.clone(), number));
            }
        }
    }
    out
}

/// The solver defaults and limits the docs name carry the code's values: a page that states
/// one differently (or a default changed without its page) fails here. Each is stated at
/// least once, so the scanner is known to find them.
#[test]
fn documented_defaults_and_limits_match_the_code() {
    let r = engine::NewtonOptions::recommended();
    let constants: [(&str, f64); 9] = [
        ("reuse_contraction", r.reuse_contraction),
        ("held_iterations", r.held_iterations as f64),
        ("anderson_depth", r.anderson_depth as f64),
        ("divergence_limit", r.divergence_limit),
        ("accuracy_fraction", r.accuracy_fraction),
        ("accuracy_floor", r.accuracy_floor),
        (
            "GROW_AFTER",
            f64::from(engine::stepper::step_size::GROW_AFTER),
        ),
        ("HOLD_BAND", engine::stepper::step_size::HOLD_BAND),
        ("MAX_COORDINATE_M", chute::mesh::MAX_COORDINATE_M),
    ];
    for (name, value) in constants {
        let stated = statements(name);
        assert!(!stated.is_empty(), "no page states `{name}` (= {value})");
        for (page, text) in stated {
            let v: f64 = text
                .parse()
                .unwrap_or_else(|_| panic!("docs/{page}: `{name}` stated as `{text}`"));
            assert_eq!(
                v, value,
                "docs/{page} states `{name}` = {text}, the code {value}"
            );
        }
    }
}

/// The Python bindings reach chute through its front door only (`chute::api`), so that the
/// internals can change without them (docs/architecture.md §Application).
#[test]
fn the_python_bindings_use_only_the_front_door() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../python/src");
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).expect("python/src") {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        files += 1;
        for (i, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for (at, _) in code.match_indices("chute::") {
                assert!(
                    code[at..].starts_with("chute::api"),
                    "{}:{}: `{}` reaches past chute::api",
                    path.display(),
                    i + 1,
                    line.trim()
                );
            }
        }
    }
    assert!(files >= 3, "no binding sources found in {}", dir.display());
}
