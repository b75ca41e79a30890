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

/// A source line without its comment and the contents of its string
/// literals (`"…"` becomes `""`), so that a name in a message is no caller.
fn code_of(line: &str) -> String {
    let mut out = String::new();
    let mut chars = line.chars().peekable();
    let mut in_string = false;
    while let Some(c) = chars.next() {
        if in_string {
            match c {
                '\\' => {
                    chars.next();
                }
                '"' => {
                    in_string = false;
                    out.push('"');
                }
                _ => {}
            }
            continue;
        }
        match c {
            '"' => {
                in_string = true;
                out.push('"');
            }
            '/' if chars.peek() == Some(&'/') => break,
            _ => out.push(c),
        }
    }
    out
}

/// Whether `name` occurs in `line` as a whole word followed by `next`.
fn uses_word(line: &str, name: &str, next: &[&str]) -> bool {
    let is_word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
    line.match_indices(name).any(|(i, _)| {
        let after = &line[i + name.len()..];
        !is_word(line[..i].chars().next_back())
            && !is_word(after.chars().next())
            && (next.is_empty() || next.iter().any(|n| after.starts_with(n)))
    })
}

/// The self type of an `impl` line: the type after `for`, or the first
/// type after `impl` and its generics (`impl<D: Dim> Fit<D>` gives `Fit`).
fn impl_self_type(line: &str) -> Option<String> {
    let t = line.trim_start().strip_prefix("impl")?;
    if !t.starts_with([' ', '<']) {
        return None;
    }
    let mut depth = 0usize;
    let mut after_generics = String::new();
    for c in t.chars() {
        match c {
            '<' => depth += 1,
            '>' => depth = depth.saturating_sub(1),
            _ if depth == 0 => after_generics.push(c),
            _ => {}
        }
    }
    let head = after_generics.split('{').next().unwrap_or("");
    let head = head.split(" where").next().unwrap_or(head);
    let ty = head.rsplit(" for ").next().unwrap_or(head);
    let name: String = ty
        .trim()
        .trim_start_matches("dyn ")
        .rsplit("::")
        .next()
        .unwrap_or("")
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect();
    (!name.is_empty()).then_some(name)
}

/// For every code line of `lines`, the self type of the `impl` block it
/// is in (or the trait it declares), if any.
fn enclosing_types(lines: &[String]) -> Vec<Option<String>> {
    let mut out = Vec::new();
    let mut current: Option<String> = None;
    let mut depth = 0i64;
    for line in lines {
        let t = line.trim_start();
        if current.is_none() {
            current = impl_self_type(t).or_else(|| {
                let t = t.strip_prefix("pub ").unwrap_or(t);
                t.strip_prefix("trait ").map(|r| {
                    r.chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect()
                })
            });
            depth = 0;
        }
        out.push(current.clone());
        if current.is_some() {
            depth += line.matches('{').count() as i64 - line.matches('}').count() as i64;
            if depth <= 0 && line.contains('}') {
                current = None;
            }
        }
    }
    out
}

/// Whether a `use` of `module::{…}` or `module::name` in `code` imports
/// `name` (groups may span lines).
fn imports(code: &str, module: &str, name: &str) -> bool {
    let qualified = format!("{module}::{name}");
    if uses_word(code, &qualified, &[]) {
        return true;
    }
    code.match_indices(&format!("{module}::{{")).any(|(i, m)| {
        let inner = code[i + m.len()..].split('}').next().unwrap_or("");
        inner
            .split(|c: char| c == ',' || c.is_whitespace())
            .any(|w| w == name)
    })
}

/// What else stands for a type at a call: the traits it implements
/// (`impl Basis1d for LagrangeBasis`, so `basis: &dyn Basis1d` reaches it)
/// and the functions that return it (`fn parameters(…) -> Result<BarParameters>`).
struct Known {
    traits: Vec<String>,
    constructors: Vec<String>,
}

impl Known {
    fn of(owner: &str, files: &[(&std::path::PathBuf, Vec<String>)]) -> Self {
        let mut traits = Vec::new();
        let mut constructors = Vec::new();
        for line in files.iter().flat_map(|(_, lines)| lines.iter()) {
            let t = line.trim_start();
            if let Some((head, ty)) = t.strip_prefix("impl ").and_then(|r| r.split_once(" for ")) {
                if impl_self_type(&format!("impl X for {ty}")).as_deref() == Some(owner) {
                    traits.extend(impl_self_type(&format!("impl {head} {{")));
                }
            }
            if let Some((sig, ret)) = t.split_once(") -> ") {
                let returns_owner = ["", "Result<", "Option<", "crate::Result<"]
                    .iter()
                    .any(|w| {
                        ret.trim_end_matches(" {").trim()
                            == format!("{w}{owner}{}", if w.is_empty() { "" } else { ">" })
                    });
                if returns_owner {
                    if let Some(f) = sig.split("fn ").nth(1) {
                        let f: String = f
                            .chars()
                            .take_while(|c| c.is_alphanumeric() || *c == '_')
                            .collect();
                        constructors.push(f);
                    }
                }
            }
        }
        Self {
            traits,
            constructors,
        }
    }
}

/// The identifier that `text` ends with (empty if it ends otherwise).
fn identifier_ending(text: &str) -> String {
    let start = text
        .char_indices()
        .rev()
        .take_while(|(_, c)| c.is_alphanumeric() || *c == '_')
        .last()
        .map_or(text.len(), |(k, _)| k);
    text[start..].to_string()
}

/// The receivers of the method calls `r.name(` / field uses `r.name` on
/// `line`: the identifier right before the dot, with a leading `.` when it
/// is itself a field (`self.grid.name(` gives `.grid`; `self.name(` gives
/// `self`).
fn receivers(line: &str, name: &str) -> Vec<String> {
    let dotted = format!(".{name}");
    line.match_indices(&dotted)
        .filter(|(i, _)| uses_word(&line[i + 1..], name, &[]))
        .filter_map(|(i, _)| {
            let head = line[..i].trim_end_matches('?');
            if head.ends_with(')') {
                // A call's result: `f(…)?.name` gives `f)`.
                let mut depth = 0i64;
                let open = head.char_indices().rev().find_map(|(k, c)| {
                    depth += match c {
                        ')' => 1,
                        '(' => -1,
                        _ => 0,
                    };
                    (depth == 0).then_some(k)
                })?;
                let f = identifier_ending(&head[..open]);
                return (!f.is_empty()).then(|| format!("{f})"));
            }
            let before = identifier_ending(&line[..i]);
            let field = line[..i - before.len()].ends_with('.');
            (!before.is_empty()).then(|| if field { format!(".{before}") } else { before })
        })
        .collect()
}

/// Whether the lines up to a call bind `receiver` to `owner`: a parameter
/// or field `receiver: Owner` (also `&Owner`, `&mut Owner`, `Vec<Owner>`
/// is not), or `let [mut] receiver = Owner::…` / `Owner {`; `self` inside
/// `impl … Owner`.
fn typed_as(lines: &[String], receiver: &str, owner: &str, known: &Known) -> bool {
    if receiver == "self" {
        return enclosing_types(lines).last().cloned().flatten().as_deref() == Some(owner);
    }
    let by_trait_or_constructor = lines.iter().rev().take(200).any(|l| {
        known.traits.iter().any(|t| {
            [
                format!("{receiver}: &dyn {t}"),
                format!("{receiver}: &impl {t}"),
                format!("{receiver}: &mut dyn {t}"),
            ]
            .iter()
            .any(|b| uses_word(l, b, &[]))
        }) || known.constructors.iter().any(|f| {
            [
                format!("let {receiver} = "),
                format!("let mut {receiver} = "),
            ]
            .iter()
            .any(|b| {
                l.split_once(b.as_str()).is_some_and(|(before, after)| {
                    !before.ends_with(|c: char| c.is_alphanumeric() || c == '_')
                        && uses_word(after.split('(').next().unwrap_or(""), f, &[])
                        && after.contains('(')
                })
            })
        })
    });
    if by_trait_or_constructor {
        return true;
    }
    let bindings = [
        format!("{receiver}: {owner}"),
        format!("{receiver}: &{owner}"),
        format!("{receiver}: &mut {owner}"),
        format!("let {receiver} = {owner}::"),
        format!("let mut {receiver} = {owner}::"),
        format!("let {receiver} = {owner} {{"),
        format!("let {receiver}: {owner}"),
        format!("let mut {receiver}: {owner}"),
    ];
    lines.iter().rev().take(200).any(|l| {
        bindings.iter().any(|b| {
            l.match_indices(b.as_str()).any(|(i, _)| {
                let after = &l[i + b.len()..];
                !l[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_')
                    && (b.ends_with("::")
                        || b.ends_with('{')
                        || !after.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
            })
        })
    })
}

/// Whether the item a map row names is used by the crate's code outside
/// its own declaration (comments and string literals do not count).
///
/// - A type or constant (`Owner`, `SINGULAR_CONDITION`): any use of the word.
/// - A method `Owner::name`: `Owner::name`, `Self::name` or `self.name(`
///   inside `impl … Owner`, or a call `.name(` / field `.name` in a file that
///   mentions `Owner` and no other type with a method or field of that name
///   (a `.evaluate(` beside both `TaylorBasis` and `CellFit` says nothing).
/// - A free function `module::name`: a call `name(` (not `.name(`) in the
///   module's own file or in a file that imports it, or `module::name(`.
fn has_caller(path: &str, sources: &[(std::path::PathBuf, String)]) -> bool {
    let segments: Vec<&str> = path.split("::").collect();
    let name = segments[segments.len() - 1];
    let Some(owner) = segments.len().checked_sub(2).map(|k| segments[k]) else {
        return false;
    };
    let files: Vec<(&std::path::PathBuf, Vec<String>)> = sources
        .iter()
        .map(|(p, t)| (p, t.lines().map(code_of).collect()))
        .collect();
    let not_declaration = |l: &&String| !declares_item(l, name);
    if name.starts_with(|c: char| c.is_uppercase()) {
        return files.iter().any(|(_, lines)| {
            lines
                .iter()
                .filter(not_declaration)
                .any(|l| uses_word(l, name, &[]))
        });
    }
    if !owner.starts_with(|c: char| c.is_uppercase()) {
        return files.iter().any(|(file, lines)| {
            let stem = file.file_stem().and_then(|s| s.to_str()).unwrap_or("");
            let parent = file
                .parent()
                .and_then(|p| p.file_name())
                .and_then(|p| p.to_str())
                .unwrap_or("");
            let own_file = stem == owner || (stem == "mod" && parent == owner);
            let code = lines.join("\n");
            let called = |l: &&String| {
                l.match_indices(name)
                    .any(|(i, _)| !l[..i].ends_with('.') && uses_word(&l[i..], name, &["(", "::<"]))
            };
            uses_word(&code, &format!("{owner}::{name}"), &["(", "::<", ")", ","])
                || ((own_file
                    || imports(&code, owner, name)
                    || (parent == owner && imports(&code, "super", name)))
                    && lines.iter().filter(not_declaration).any(|l| called(&l)))
        });
    }
    // Types with a method or a field of this name.
    let mut owners = std::collections::BTreeSet::new();
    for (_, lines) in &files {
        for (line, ty) in lines.iter().zip(enclosing_types(lines)) {
            let t = line.trim_start();
            let t = t.strip_prefix("pub ").unwrap_or(t);
            let field = t.starts_with(name) && t[name.len()..].starts_with(':');
            if let Some(ty) = ty.filter(|_| declares_item(line, name)) {
                owners.insert(ty);
            } else if field {
                owners.insert(String::new());
            }
        }
    }
    let known = Known::of(owner, &files);
    // Fields declared with the owner's type anywhere (`pub grid: Grid,`).
    let fields_of_type: std::collections::BTreeSet<String> = files
        .iter()
        .flat_map(|(_, lines)| lines.iter())
        .filter_map(|l| {
            let t = l.trim_start();
            let t = t.strip_prefix("pub ").unwrap_or(t);
            let (field, ty) = t.split_once(": ")?;
            let ty = ty.trim_end_matches(',').trim();
            (field.chars().all(|c| c.is_alphanumeric() || c == '_') && ty == owner)
                .then(|| field.to_string())
        })
        .collect();
    files.iter().any(|(_, lines)| {
        let types = enclosing_types(lines);
        let inside_owner = lines.iter().zip(&types).any(|(l, ty)| {
            ty.as_deref() == Some(owner)
                && !declares_item(l, name)
                && (uses_word(l, &format!("Self::{name}"), &[])
                    || l.contains(&format!("self.{name}")))
        });
        if inside_owner {
            return true;
        }
        if lines
            .iter()
            .filter(not_declaration)
            .any(|l| uses_word(l, &format!("{owner}::{name}"), &[]))
        {
            return true;
        }
        let mentions = |ty: &str| lines.iter().any(|l| uses_word(l, ty, &[]));
        let rivals = owners
            .iter()
            .any(|t| t.as_str() != owner && !t.is_empty() && mentions(t));
        lines.iter().enumerate().any(|(k, l)| {
            if declares_item(l, name) {
                return false;
            }
            let mut found = receivers(l, name);
            if found.is_empty() && l.trim_start().starts_with(&format!(".{name}")) && k > 0 {
                // A chained call: the receiver ends the line before.
                found = receivers(&format!("{}.{name}", lines[k - 1].trim_end()), name);
            }
            found.iter().any(|r| {
                let bound = match r.strip_prefix('.') {
                    Some(field) => fields_of_type.contains(field),
                    None if r.ends_with(')') => known
                        .constructors
                        .iter()
                        .any(|f| r.trim_end_matches(')') == f),
                    None => typed_as(&lines[..=k], r, owner, &known),
                };
                bound || (!rivals && mentions(owner) && r != "self")
            })
        })
    })
}

/// The caller rule itself: a name in a comment or a string is no caller,
/// a shared method name needs a call that says whose it is, and a unique
/// function's call counts.
#[test]
fn the_caller_rule_needs_a_call_that_names_its_owner() {
    let file = |t: &str| vec![(std::path::PathBuf::from("m.rs"), t.to_string())];
    let shared = "impl Basis {\n    pub fn evaluate(&self) {}\n}\nimpl Fit {\n    pub fn evaluate(&self) {}\n}\n";
    assert!(!has_caller(
        "m::Basis::evaluate",
        &file(&format!("{shared}fn g(f: Fit) {{ f.evaluate(); }}"))
    ));
    assert!(has_caller(
        "m::Basis::evaluate",
        &file(&format!("{shared}fn g(b: &Basis) {{ b.evaluate(); }}"))
    ));
    assert!(has_caller(
        "m::Basis::evaluate",
        &file(&format!("{shared}fn g() {{ Basis::evaluate(&b); }}"))
    ));
    assert!(!has_caller(
        "m::unique",
        &file("fn unique() {}\n// unique()\nlet s = \"unique()\";")
    ));
    assert!(has_caller(
        "m::unique",
        &file("fn unique() {}\nfn g() { unique(); }")
    ));
    assert!(has_caller(
        "m::unique",
        &file("fn unique() {}\nfn g() { xs.map(m::unique); }")
    ));
    assert!(!has_caller("m::Owner", &file("struct Owner;\n// Owner")));
    let modules = "fn fit() {}\nfn fit_rows() {}\nimpl T { fn fit(&self) {} }\n";
    let elsewhere = |t: &str| vec![(std::path::PathBuf::from("other.rs"), t.to_string())];
    assert!(!has_caller(
        "m::fit",
        &elsewhere(&format!(
            "{modules}use m::fit_rows;\nfn g(t: T) {{ t.fit(); }}"
        ))
    ));
}

/// Issue #26: the map names the code that runs. Every item a done row
/// names outside `(reference: …)` is called somewhere in src/ besides its
/// declaration, and every done row names at least one such item. Issue
/// #37: a row names an item, not a module, and a shared method name is
/// satisfied only by a call that names its owner ([`has_caller`]).
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
            let segments: Vec<&str> = p.split("::").collect();
            if module_files(&segments).is_some() {
                errors.push(format!(
                    "line {}: `{p}` is a module; name the item that implements the equation",
                    r.line
                ));
            } else if !has_caller(&p, &sources) {
                errors.push(format!(
                    "line {}: `{p}` has no caller in src/ that names it (name what runs, or mark it `(reference: …)`)",
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
