//! Every module doc names the public items its module holds (issue #14):
//! a reader who opens a file learns from its first lines what is in it.

use crate::common;

/// The name declared by a top-level `pub fn|struct|enum|const|trait|type|static|mod` line.
fn public_item(line: &str) -> Option<&str> {
    let rest = line.strip_prefix("pub ")?;
    let rest = [
        "fn ", "struct ", "enum ", "const ", "trait ", "type ", "static ", "mod ",
    ]
    .iter()
    .find_map(|k| rest.strip_prefix(k))?;
    let end = rest
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(rest.len());
    Some(&rest[..end])
}

fn mentions(doc: &str, name: &str) -> bool {
    doc.match_indices(name).any(|(i, _)| {
        let before = doc[..i].chars().next_back();
        let after = doc[i + name.len()..].chars().next();
        let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
        !word(before) && !word(after)
    })
}

#[test]
fn every_module_doc_names_its_public_items() {
    let files = common::source_files();
    let mut missing = Vec::new();
    for (file, text) in &files {
        let doc: String = text
            .lines()
            .filter(|l| l.starts_with("//!"))
            .collect::<Vec<_>>()
            .join("\n");
        for name in text.lines().filter_map(public_item) {
            if !mentions(&doc, name) {
                missing.push(format!("{}: {name}", file.display()));
            }
        }
    }
    assert!(files.len() > 40, "found only {} source files", files.len());
    assert!(missing.is_empty(), "module docs do not name: {missing:#?}");
}

/// The names listed after "Items:" in a module doc (`[`name`]` links, up to
/// the first empty doc line).
fn listed_items(text: &str) -> Vec<String> {
    let doc: Vec<&str> = text.lines().filter(|l| l.starts_with("//!")).collect();
    let Some(start) = doc.iter().position(|l| l.contains("Items:")) else {
        return vec![];
    };
    let list: String = doc[start..]
        .iter()
        .take_while(|l| l.trim_start_matches("//!").trim() != "" || l.contains("Items:"))
        .copied()
        .collect::<Vec<_>>()
        .join(" ");
    list.split("[`")
        .skip(1)
        .filter_map(|s| s.split("`]").next())
        .map(|s| {
            let s = s.trim_end_matches("()").trim_end_matches('!');
            s.split("::").next().unwrap_or(s).to_string()
        })
        .collect()
}

/// The reverse of the test above: a module doc lists no item the module
/// does not hold, so a moved function cannot leave its name behind.
#[test]
fn every_item_a_module_doc_lists_is_in_the_module() {
    let mut stale = Vec::new();
    for (file, text) in &common::source_files() {
        let declared: Vec<&str> = text.lines().filter_map(public_item).collect();
        let reexported = |name: &str| {
            text.lines()
                .filter(|l| l.starts_with("pub use "))
                .any(|l| mentions(l, name))
        };
        for name in listed_items(text) {
            if !declared.contains(&name.as_str()) && !reexported(&name) {
                stale.push(format!("{}: {name}", file.display()));
            }
        }
    }
    assert!(
        stale.is_empty(),
        "module docs list items the module does not hold: {stale:#?}"
    );
}
