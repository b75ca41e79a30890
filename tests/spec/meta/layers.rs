//! The layout follows the data (DESIGN.md's module map, issue #14): splines
//! → mass matrices and solvers → reconstruction → MPM step → scenes →
//! studies → tables → report → CLI. A lower layer never imports a higher
//! one. This test reads every file under src/ and fails on a `crate::x`
//! path that points up (or sideways, between two modules of one layer).

use crate::common;

/// The top-level modules of src/, lowest layer first; modules on one line
/// share a layer and may not refer to each other.
const LAYERS: &[&[&str]] = &[
    &["error", "rng", "dispatch", "placement"],
    &["basis", "quadrature"],
    &["spline", "lagrange"],
    &["sparse"],
    &["mass"],
    &["solve"],
    &["reconstruct"],
    &["mpm"],
    &["mpm2d", "fem"],
    &["scenes"],
    &["studies"],
    &["tables"],
    &["report"],
    &["oracle"],
    &["cli"],
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

/// The top-level modules a source text refers to: `crate::x` paths and the
/// `x::` heads inside `use crate::{…}` groups (comments skipped).
fn referenced_modules(text: &str) -> Vec<String> {
    let code = without_comments(text);
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out: Vec<String> = code
        .split("crate::")
        .skip(1)
        .map(ident)
        .filter(|s| !s.is_empty())
        .collect();
    for group in code.split("use crate::{").skip(1) {
        let inner = group.split('}').next().unwrap_or("");
        for item in inner.split(',') {
            let item = item.trim();
            if item.contains("::") {
                out.push(ident(item));
            }
        }
    }
    out
}

/// `text` with every `//` comment cut off its line.
fn without_comments(text: &str) -> String {
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn no_module_imports_a_higher_layer() {
    let mut upward = Vec::new();
    let mut unknown = Vec::new();
    for (rel, text) in &common::source_files() {
        let top = rel.iter().next().unwrap().to_string_lossy();
        let module = top.trim_end_matches(".rs");
        if module == "lib" || module == "bin" {
            continue;
        }
        let Some(own) = layer_of(module) else {
            unknown.push(module.to_string());
            continue;
        };
        for target in referenced_modules(text) {
            if target == module || target == "Error" || target == "Result" {
                continue;
            }
            match layer_of(&target) {
                Some(l) if l < own => {}
                Some(_) => upward.push(format!("{}: crate::{target}", rel.display())),
                None => unknown.push(target),
            }
        }
    }
    unknown.sort();
    unknown.dedup();
    assert!(
        unknown.is_empty(),
        "modules missing from LAYERS: {unknown:?}"
    );
    assert!(
        upward.is_empty(),
        "references to a higher or equal layer: {upward:#?}"
    );
}

/// The checker itself: an upward path and a grouped import are both seen.
#[test]
fn the_reference_scanner_sees_paths_and_grouped_imports() {
    let text = "use crate::{mass::lumped, error::Result};\n\
                // crate::cli in a comment\n\
                let x = crate::tables::run(spec);";
    let mut found = referenced_modules(text);
    found.sort();
    found.dedup();
    assert_eq!(found, ["error", "mass", "tables"]);
}

/// The sibling files a file of a folder refers to (issue #37): `super::b`
/// and `crate::folder::b` paths to a sibling module `b`, and `super::Name`
/// or `crate::folder::Name` for an item that exactly one sibling declares
/// (mod.rs re-exports it). mod.rs itself is the folder's facade and is not
/// a node: a sibling that names an item of mod.rs refers to no sibling.
fn sibling_references(
    folder: &str,
    own: &str,
    text: &str,
    declared_in: &std::collections::BTreeMap<String, Vec<String>>,
    siblings: &[String],
) -> std::collections::BTreeSet<String> {
    let code = without_comments(text);
    let ident = |s: &str| -> String {
        s.trim_start()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut names: Vec<String> = Vec::new();
    let crate_path = format!("crate::{folder}::");
    for head in ["super::", crate_path.as_str()] {
        for after in code.split(head).skip(1) {
            if let Some(group) = after.strip_prefix('{') {
                let inner = group.split('}').next().unwrap_or("");
                names.extend(inner.split(',').map(ident));
            } else {
                names.push(ident(after));
            }
        }
    }
    let mut out = std::collections::BTreeSet::new();
    for name in names.into_iter().filter(|n| !n.is_empty()) {
        if siblings.contains(&name) {
            out.insert(name);
        } else if let Some(files) = declared_in.get(&name) {
            if let [only] = files.as_slice() {
                out.insert(only.clone());
            }
        }
    }
    out.remove(own);
    out
}

/// The names a file declares as items (`fn`, `struct`, `enum`, `trait`,
/// `type`, `const`, `static`), for resolving `super::Name`.
fn declared_items(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let t = line.trim_start();
        let t = t
            .strip_prefix("pub(crate) ")
            .or_else(|| t.strip_prefix("pub(super) "))
            .or_else(|| t.strip_prefix("pub "))
            .unwrap_or(t);
        for kw in [
            "fn ", "struct ", "enum ", "trait ", "type ", "const ", "static ",
        ] {
            if let Some(rest) = t.strip_prefix(kw) {
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    out.push(name);
                }
            }
        }
    }
    out
}

/// A cycle in a directed graph of file stems, as a list of stems, if any.
fn find_cycle(
    edges: &std::collections::BTreeMap<String, std::collections::BTreeSet<String>>,
) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        edges: &std::collections::BTreeMap<String, std::collections::BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut std::collections::BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|p| p == node) {
            let mut cycle = path[at..].to_vec();
            cycle.push(node.to_string());
            return Some(cycle);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in edges.get(node).into_iter().flatten() {
            if let Some(c) = visit(next, edges, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = std::collections::BTreeSet::new();
    edges
        .keys()
        .find_map(|n| visit(n, edges, &mut Vec::new(), &mut done))
}

/// The files of each folder of src/, with their references to siblings.
fn folder_graphs() -> std::collections::BTreeMap<
    String,
    std::collections::BTreeMap<String, std::collections::BTreeSet<String>>,
> {
    use std::collections::BTreeMap;
    let files = common::source_files();
    let mut by_folder: BTreeMap<String, Vec<(String, &String)>> = BTreeMap::new();
    for (rel, text) in &files {
        let parts: Vec<String> = rel
            .iter()
            .map(|p| p.to_string_lossy().into_owned())
            .collect();
        if let [folder, file] = parts.as_slice() {
            let stem = file.trim_end_matches(".rs").to_string();
            if stem != "mod" {
                by_folder
                    .entry(folder.clone())
                    .or_default()
                    .push((stem, text));
            }
        }
    }
    let mut graphs = BTreeMap::new();
    for (folder, members) in by_folder {
        let siblings: Vec<String> = members.iter().map(|(s, _)| s.clone()).collect();
        let mut declared_in: BTreeMap<String, Vec<String>> = BTreeMap::new();
        for (stem, text) in &members {
            for name in declared_items(text) {
                let files = declared_in.entry(name).or_default();
                if !files.contains(stem) {
                    files.push(stem.clone());
                }
            }
        }
        let edges = members
            .iter()
            .map(|(stem, text)| {
                (
                    stem.clone(),
                    sibling_references(&folder, stem, text, &declared_in, &siblings),
                )
            })
            .collect();
        graphs.insert(folder, edges);
    }
    graphs
}

/// Issue #37: inside a folder the files form layers too; two files that
/// refer to each other (directly or round a longer cycle) are one idea
/// split in two, or a shared item living in the wrong file.
#[test]
fn no_two_files_of_a_folder_refer_to_each_other() {
    let cycles: Vec<String> = folder_graphs()
        .into_iter()
        .filter_map(|(folder, edges)| {
            find_cycle(&edges).map(|c| format!("src/{folder}: {}", c.join(" -> ")))
        })
        .collect();
    assert!(cycles.is_empty(), "cycles inside folders: {cycles:#?}");
}

/// The folder scanner itself: a `super::` path to a sibling, a grouped
/// import and an item that one sibling declares are each an edge, and a
/// two-file loop is found.
#[test]
fn the_folder_scanner_sees_siblings_items_and_loops() {
    let siblings = ["step".to_string(), "phases".to_string(), "grid".to_string()];
    let mut declared = std::collections::BTreeMap::new();
    declared.insert("Workspace".to_string(), vec!["step".to_string()]);
    declared.insert(
        "Shared".to_string(),
        vec!["step".to_string(), "grid".to_string()],
    );
    let text = "use super::{grid::Grid, Workspace};\n// super::phases in a comment\nlet s = super::Shared::new();";
    let refs = sibling_references("mpm2d", "phases", text, &declared, &siblings);
    assert_eq!(refs.into_iter().collect::<Vec<_>>(), ["grid", "step"]);
    let mut edges = std::collections::BTreeMap::new();
    edges.insert("a".to_string(), ["b".to_string()].into_iter().collect());
    edges.insert("b".to_string(), ["a".to_string()].into_iter().collect());
    assert_eq!(find_cycle(&edges).unwrap(), ["a", "b", "a"]);
    edges.insert("b".to_string(), Default::default());
    assert!(find_cycle(&edges).is_none());
}
