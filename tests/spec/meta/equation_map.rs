//! docs/equations.md is checked, not trusted: every row of the equation map
//! has a unique seed-prefixed id (book-4.23, tls-12, thesis-3.5, mls-14), and
//! every row marked done names code that exists in src/ (`module::item`) and
//! a test that exists in tests/ (`tests/file.rs::test_name`), and the code
//! it names runs: each item outside a `(reference: …)` has a caller in src/.

use std::collections::HashSet;
use std::fs;
use std::path::{Path, PathBuf};

const MAP: &str = "docs/equations.md";
const SEEDS: [&str; 4] = ["book-", "tls-", "thesis-", "mls-"];

/// One row: id, what, implemented in, checked by, status.
struct Row {
    line: usize,
    cells: Vec<String>,
}

/// The rows of every table in the map; `\|` inside a cell is a literal bar.
fn rows() -> Vec<Row> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = fs::read_to_string(root.join(MAP)).expect("docs/equations.md exists");
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate() {
        if !line.starts_with("| ") || line.starts_with("| id ") {
            continue;
        }
        let masked = line.replace("\\|", "\u{1}");
        let cells: Vec<String> = masked
            .trim()
            .trim_matches('|')
            .split('|')
            .map(|c| c.trim().replace('\u{1}', "|"))
            .collect();
        out.push(Row { line: k + 1, cells });
    }
    out
}

/// The Rust sources of a module path `a::b::c`: src/a/b/c.rs, or every file
/// of src/a/b/c/ when it is a directory module. None if it is no module.
fn module_files(segments: &[&str]) -> Option<Vec<PathBuf>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let dir = segments.iter().fold(src, |p, s| p.join(s));
    let file = dir.with_extension("rs");
    if file.is_file() {
        return Some(vec![file]);
    }
    if dir.join("mod.rs").is_file() {
        let mut files: Vec<PathBuf> = fs::read_dir(&dir)
            .ok()?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "rs"))
            .collect();
        files.sort();
        return Some(files);
    }
    None
}

/// Whether `name` is declared in `text`: an item (fn, struct, enum, trait,
/// type, const, static, mod, macro), a struct field or an enum variant.
fn declares(text: &str, name: &str) -> bool {
    let word = |s: &str, i: usize| {
        s[i + name.len()..]
            .chars()
            .next()
            .is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
    };
    for kw in [
        "fn ",
        "struct ",
        "enum ",
        "trait ",
        "type ",
        "const ",
        "static ",
        "mod ",
        "macro_rules! ",
    ] {
        let pat = format!("{kw}{name}");
        if text
            .match_indices(&pat)
            .any(|(i, _)| word(text, i + kw.len()))
        {
            return true;
        }
    }
    // A field (`pub name:`) or an enum variant: the name at the start of a
    // line, followed by `:`, `,`, `(`, ` {` or the end of the line.
    text.lines().any(|l| {
        let t = l.trim_start();
        let t = t.strip_prefix("pub ").unwrap_or(t);
        t.strip_prefix(name)
            .is_some_and(|rest| rest.is_empty() || rest.starts_with([':', ',', '(', ' ', '{']))
    })
}

/// Checks one `module::…::item::…` path: the longest prefix that is a module
/// of the crate, then every further segment declared in its files.
fn check_code_path(path: &str) -> Result<(), String> {
    let segments: Vec<&str> = path.split("::").collect();
    let (files, rest) = (1..=segments.len())
        .rev()
        .find_map(|k| module_files(&segments[..k]).map(|f| (f, &segments[k..])))
        .ok_or_else(|| format!("`{path}`: no module `{}` in src/", segments[0]))?;
    let text: String = files
        .iter()
        .map(|f| fs::read_to_string(f).unwrap_or_default())
        .collect();
    for name in rest {
        if !declares(&text, name) {
            return Err(format!("`{path}`: `{name}` is not declared in {files:?}"));
        }
    }
    Ok(())
}

/// The crate paths named in an "implemented in" cell: words of the form
/// `a::b…` whose first segment is a module of the crate.
fn code_paths(cell: &str) -> Vec<String> {
    cell.split(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
        .filter(|w| w.contains("::"))
        .map(|w| w.trim_matches(':').to_string())
        .filter(|w| module_files(&[w.split("::").next().unwrap_or("")]).is_some())
        .collect()
}

#[test]
fn every_row_has_a_unique_seed_prefixed_id() {
    let mut seen = HashSet::new();
    let rows = rows();
    assert!(rows.len() > 150, "only {} rows parsed", rows.len());
    for r in &rows {
        assert_eq!(
            r.cells.len(),
            5,
            "line {}: {} cells, not 5",
            r.line,
            r.cells.len()
        );
        let id = &r.cells[0];
        assert!(
            SEEDS.iter().any(|s| id.starts_with(s)),
            "line {}: id `{id}` has no seed prefix",
            r.line
        );
        assert!(
            seen.insert(id.clone()),
            "line {}: id `{id}` repeats",
            r.line
        );
    }
}

#[test]
fn every_done_row_names_code_that_exists() {
    let mut errors = Vec::new();
    for r in rows().iter().filter(|r| r.cells[4] == "done") {
        let paths = code_paths(&r.cells[2]);
        if paths.is_empty() {
            errors.push(format!(
                "line {}: no `module::item` in `{}`",
                r.line, r.cells[2]
            ));
        }
        for p in paths {
            if let Err(e) = check_code_path(&p) {
                errors.push(format!("line {}: {e}", r.line));
            }
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

/// The "implemented in" cell without its `(reference: …)` parts: an item
/// named there is the equation written literally for the tests to compare
/// with, and need not run in the crate.
fn called_part(cell: &str) -> String {
    let mut out = String::new();
    let mut rest = cell;
    while let Some(i) = rest.find("reference:") {
        out.push_str(&rest[..i]);
        let after = &rest[i..];
        // Up to the parenthesis that closes the one the reference opens in.
        let mut depth = 0usize;
        let mut end = after.len();
        for (k, c) in after.char_indices() {
            match c {
                '(' => depth += 1,
                ')' if depth == 0 => {
                    end = k;
                    break;
                }
                ')' => depth -= 1,
                _ => {}
            }
        }
        rest = &after[end..];
    }
    out.push_str(rest);
    out
}

/// Whether `line` declares the item `name` (`fn name`, `struct name`, …);
/// unlike [`declares`], a line that starts with `name(` is a call here.
fn declares_item(line: &str, name: &str) -> bool {
    [
        "fn ", "struct ", "enum ", "trait ", "type ", "const ", "static ", "mod ",
    ]
    .iter()
    .any(|kw| {
        let pat = format!("{kw}{name}");
        line.match_indices(&pat).any(|(i, _)| {
            line[i + pat.len()..]
                .chars()
                .next()
                .is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
        })
    })
}

/// Whether `name` is used in the crate's code outside its own declaration
/// (comments and doc comments do not count).
fn has_caller(name: &str, sources: &[(std::path::PathBuf, String)]) -> bool {
    let is_word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
    sources.iter().any(|(_, text)| {
        text.lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .filter(|l| !declares_item(l, name))
            .any(|l| {
                l.match_indices(name).any(|(i, _)| {
                    !is_word(l[..i].chars().next_back())
                        && !is_word(l[i + name.len()..].chars().next())
                })
            })
    })
}

/// Issue #26: the map names the code that runs. Every item a done row
/// names outside `(reference: …)` is called somewhere in src/ besides its
/// declaration, and every done row names at least one such item.
#[test]
fn every_done_row_names_code_the_crate_calls() {
    let sources = crate::common::source_files();
    let mut errors = Vec::new();
    for r in rows().iter().filter(|r| r.cells[4] == "done") {
        let paths = code_paths(&called_part(&r.cells[2]));
        if paths.is_empty() {
            errors.push(format!(
                "line {}: names only references, no code the crate runs",
                r.line
            ));
        }
        for p in paths {
            let name = p.rsplit("::").next().unwrap_or(&p);
            if !has_caller(name, &sources) {
                errors.push(format!(
                    "line {}: `{p}` has no caller in src/ (name what runs, or mark it `(reference: …)`)",
                    r.line
                ));
            }
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn every_done_row_names_a_test_that_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut errors = Vec::new();
    for r in rows().iter().filter(|r| r.cells[4] == "done") {
        for named in r.cells[3].split(", ") {
            let Some((file, test)) = named.split_once("::") else {
                errors.push(format!(
                    "line {}: `{named}` names no test (file::test)",
                    r.line
                ));
                continue;
            };
            let text = fs::read_to_string(root.join(file)).unwrap_or_default();
            if !file.starts_with("tests/") || !declares(&text, test) {
                errors.push(format!("line {}: no test `{test}` in {file}", r.line));
            }
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

/// The `///` lines right above `fn name` in `text` (attributes skipped).
fn doc_above(text: &str, name: &str) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let at = lines.iter().position(|l| {
        l.trim_start().strip_prefix("fn ").is_some_and(|r| {
            r.starts_with(name)
                && !r[name.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
        })
    })?;
    let doc: Vec<&str> = lines[..at]
        .iter()
        .rev()
        .map(|l| l.trim_start())
        .take_while(|l| l.starts_with("///") || l.starts_with("#["))
        .filter(|l| l.starts_with("///"))
        .collect();
    Some(doc.into_iter().rev().collect::<Vec<_>>().join("\n"))
}

/// Issue #26: a test that several rows name for different equations says
/// why in its doc comment, in a line "Map rows: id, id — why." that lists
/// every one of those rows.
#[test]
fn a_test_named_by_several_rows_says_why() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut by_test: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    for r in rows().iter().filter(|r| r.cells[4] == "done") {
        for named in r.cells[3].split(", ") {
            let ids = by_test.entry(named.to_string()).or_default();
            if !ids.contains(&r.cells[0]) {
                ids.push(r.cells[0].clone());
            }
        }
    }
    let mut errors = Vec::new();
    for (named, ids) in by_test.iter().filter(|(_, ids)| ids.len() > 1) {
        let Some((file, test)) = named.split_once("::") else {
            continue;
        };
        let text = fs::read_to_string(root.join(file)).unwrap_or_default();
        let doc = doc_above(&text, test).unwrap_or_default();
        let Some(line) = doc.lines().find(|l| l.contains("Map rows:")) else {
            errors.push(format!(
                "{named}: named by {} rows and no \"Map rows: … — why\" line",
                ids.len()
            ));
            continue;
        };
        let (listed, why) = line.split_once(" — ").unwrap_or((line, ""));
        let listed: Vec<&str> = listed
            .split_once("Map rows:")
            .map_or("", |(_, l)| l)
            .split(", ")
            .map(str::trim)
            .collect();
        let missing: Vec<&String> = ids
            .iter()
            .filter(|id| !listed.contains(&id.as_str()))
            .collect();
        if !missing.is_empty() || why.trim().len() < 10 {
            errors.push(format!(
                "{named}: its \"Map rows\" line misses {missing:?} or a reason"
            ));
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn the_summary_line_counts_the_rows() {
    let rows = rows();
    let count = |status: &str| {
        rows.iter()
            .filter(|r| r.cells[4].starts_with(status))
            .count()
    };
    let expected = format!(
        "Summary: {} rows — {} done, {} pending, {} not applicable.",
        rows.len(),
        count("done"),
        count("pending"),
        count("not applicable")
    );
    let text = fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(MAP)).unwrap();
    assert!(
        text.lines().any(|l| l == expected),
        "docs/equations.md should say: {expected}"
    );
}
