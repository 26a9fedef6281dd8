//! The user guide's (`docs/user-guide.md`) table of the default keymap names every key and
//! every action of `keymaps/default.json`, and its glossary explains the words the console uses.

use std::collections::BTreeSet;

/// The rows of the table under the user guide's "The default keymap" heading: (keys, action,
/// description), each cell as written.
fn default_keymap_rows(readme: &str) -> Vec<(String, String, String)> {
    let start = readme
        .find("#### The default keymap")
        .expect("docs/user-guide.md has a \"The default keymap\" section");
    readme[start..]
        .lines()
        .skip_while(|line| !line.starts_with('|'))
        .take_while(|line| line.starts_with('|'))
        .skip(2) // the header and its rule
        .map(|line| {
            let cells: Vec<&str> = line.trim_matches('|').split(" | ").collect();
            assert_eq!(
                cells.len(),
                3,
                "not a key | action | description row: {line}"
            );
            (
                cells[0].trim().to_string(),
                cells[1].trim().to_string(),
                cells[2].trim().to_string(),
            )
        })
        .collect()
}

/// The `code` spans of a cell.
fn code_spans(cell: &str) -> BTreeSet<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

#[test]
fn the_readme_names_every_default_key_and_action() {
    let root = env!("CARGO_MANIFEST_DIR");
    let readme =
        std::fs::read_to_string(format!("{root}/docs/user-guide.md")).expect("docs/user-guide.md");
    let keymap: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(format!("{root}/keymaps/default.json")).expect("default.json"),
    )
    .expect("default.json is JSON");
    let bindings = keymap["bindings"].as_object().expect("bindings");
    let rows = default_keymap_rows(&readme);
    assert!(!rows.is_empty(), "the default keymap table has no rows");
    let mut missing = Vec::new();
    for (key, action) in bindings {
        let action = action.as_str().expect("an action name");
        let listed = rows.iter().any(|(keys, actions, description)| {
            code_spans(keys).contains(key)
                && code_spans(actions).contains(action)
                && !description.is_empty()
        });
        if !listed {
            missing.push(format!("| `{key}` | `{action}` | ... |"));
        }
    }
    assert!(
        missing.is_empty(),
        "docs/user-guide.md's default keymap table lacks these bindings of keymaps/default.json:\n{}",
        missing.join("\n")
    );
    // And lists nothing the keymap does not bind.
    for (keys, actions, _) in &rows {
        for action in code_spans(actions) {
            for key in code_spans(keys) {
                assert_eq!(
                    bindings.get(&key).and_then(|a| a.as_str()),
                    Some(action.as_str()),
                    "docs/user-guide.md binds `{key}` to `{action}`; keymaps/default.json does not"
                );
            }
        }
    }
}

#[test]
fn every_action_of_the_console_is_in_the_readme() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/user-guide.md"))
            .expect("docs/user-guide.md");
    let rows = default_keymap_rows(&readme);
    for action in armjog::console::action::Action::ALL {
        let name = action.name();
        assert!(
            rows.iter()
                .any(|(_, actions, _)| code_spans(actions).contains(&name)),
            "docs/user-guide.md's default keymap table lacks `{name}`"
        );
    }
}

#[test]
fn one_glossary_explains_anchor_parent_and_the_polar_words() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/user-guide.md"))
            .expect("docs/user-guide.md");
    assert_eq!(readme.matches("\n## Glossary\n").count(), 1, "one glossary");
    let start = readme.find("\n## Glossary\n").expect("glossary");
    let glossary = readme[start + 1..]
        .split("\n## ")
        .next()
        .expect("glossary text");
    for word in [
        "anchor",
        "parent",
        "altitude",
        "elevation",
        "delta",
        "azimuth",
    ] {
        assert!(
            glossary.contains(&format!("- **{word}**:")),
            "the glossary does not explain {word}"
        );
    }
}
