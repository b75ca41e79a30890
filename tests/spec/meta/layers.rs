//! The layout follows the data (DESIGN.md's module map, issue #14): splines
//! → mass matrices and solvers → reconstruction → MPM step → scenes →
//! studies → tables → report → CLI. A lower layer never imports a higher
//! one. This test reads every file under src/ and fails on a `crate::x`
//! path that points up (or sideways, between two modules of one layer).

use crate::common;

/// The top-level modules of src/, lowest layer first; modules on one line
/// share a layer and may not refer to each other.
const LAYERS: &[&[&str]] = &[
    &["error", "rng"],
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
    let code: String = text
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
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
