//! LAMMPS-style dump files as `hompm check --input` (Karamelo's output,
//! issue #36): read strictly, one block (the last, or `--dump-step`),
//! 1-based ids made hompm's 0-based ones, and a displacement derived as
//! u = x − x0 with the rounding floor the verdict names
//! (`oracle::input_dump`, docs/conventions.md "Conventions of other codes").

use serde_json::Value;
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("dump-input");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const BAR: [&str; 5] = ["vibrating-bar", "--cells", "16", "--steps", "1999"];

/// hompm's own run as a Karamelo-style dump block: id (from 1), type, x0,
/// x, vx, s11 with 17 digits, and no displacement.
fn dump_block(extra: &[&str], timestep: u64) -> String {
    let mut args = vec!["run"];
    args.extend_from_slice(&BAR);
    args.extend_from_slice(extra);
    args.push("--json");
    let doc: Value = serde_json::from_str(&hompm::cli::run(&args).unwrap().stdout).unwrap();
    let p = &doc["particles"];
    let n = p["x"].as_array().unwrap().len();
    let mut out = format!(
        "ITEM: TIMESTEP\n{timestep}\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS sm sm sm\n0 25\n0 0\n0 0\nITEM: ATOMS id type x0 x vx s11\n"
    );
    for k in 0..n {
        let f = |c: &str| format!("{:.17e}", p[c][k].as_f64().unwrap());
        out.push_str(&format!(
            "{} 1 {} {} {} {}\n",
            k + 1,
            f("x0"),
            f("x"),
            f("v"),
            f("stress")
        ));
    }
    out
}

fn check(text: &str, name: &str, extra: &[&str]) -> hompm::Result<hompm::cli::Output> {
    let file = scratch(name);
    std::fs::write(&file, text).unwrap();
    let f = file.to_str().unwrap().to_string();
    let mut args = vec!["check"];
    args.extend_from_slice(&BAR);
    args.extend_from_slice(&["--columns", "v=vx,stress=s11", "--input", &f]);
    args.extend_from_slice(extra);
    hompm::cli::run(&args)
}

#[test]
fn a_dump_of_hompms_run_agrees_matched_by_its_one_based_ids_with_u_derived_from_x() {
    let out = check(&dump_block(&[], 0), "own.dump", &[]).unwrap();
    assert!(out.stdout.starts_with("agrees"), "{}", out.stdout);
    assert!(out.stdout.contains("in u, v, stress"), "{}", out.stdout);
    assert!(
        out.stdout.contains("derived from your columns: u = x − x0"),
        "{}",
        out.stdout
    );
    assert!(out.stdout.contains("matched by id"), "{}", out.stdout);
}

#[test]
fn the_derived_displacement_still_sees_the_positions_convention_of_another_code() {
    // Karamelo's rule (MLS Eq. 30) against the book's Eq. 4.11: u differs
    // by 2.1e-12, above the floor 4√n·ε·max|x| = 9.9e-13; with the
    // matching convention it agrees.
    let grid = dump_block(&["--positions", "grid"], 0);
    let out = check(&grid, "grid.dump", &[]).unwrap();
    assert!(out.stdout.starts_with("differs"), "{}", out.stdout);
    assert!(out.stdout.contains("in u (u)"), "{}", out.stdout);
    let out = check(&grid, "grid-matched.dump", &["--positions", "grid"]).unwrap();
    assert!(out.stdout.starts_with("agrees"), "{}", out.stdout);
    assert!(
        out.stdout.contains("differences below 9.9e-13 absolute"),
        "{}",
        out.stdout
    );
}

#[test]
fn the_last_block_is_read_unless_dump_step_names_another() {
    // Block 7 is a run of another convention; the last (1999) is hompm's.
    let two = dump_block(&["--transfer", "pic"], 7) + &dump_block(&[], 1999);
    assert!(check(&two, "two.dump", &[])
        .unwrap()
        .stdout
        .starts_with("agrees"));
    let out = check(&two, "two-7.dump", &["--dump-step", "7"]).unwrap();
    assert!(out.stdout.starts_with("differs"), "{}", out.stdout);
    let e = check(&two, "two-8.dump", &["--dump-step", "8"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("no timestep 8 (it has 7, 1999)"), "{e}");
}

#[test]
fn a_malformed_dump_is_one_line_naming_the_problem() {
    let good = dump_block(&[], 5);
    let cases: Vec<(String, &str)> = vec![
        (
            good.replace("NUMBER OF ATOMS\n64", "NUMBER OF ATOMS\n65"),
            "has 64 rows",
        ),
        (
            good.replace("NUMBER OF ATOMS\n64", "NUMBER OF ATOMS\n63"),
            "more rows than",
        ),
        (good.replacen(" 1 ", " one ", 1), "is not a number"),
        (good.clone() + &good, "timestep 5 appears twice"),
        (
            good.replace("ITEM: TIMESTEP\n5\n", ""),
            "before the block's TIMESTEP",
        ),
        (
            good.replace("ITEM: BOX BOUNDS sm sm sm", "ITEM: BOXES"),
            "unknown item",
        ),
        (
            good.replacen("\n1 1 ", "\n0 1 ", 1),
            "not a whole number from 1",
        ),
        (
            good.replace("x vx s11\n", "x vx\n"),
            "values but ATOMS names",
        ),
        (
            good.replace("TIMESTEP\n5", "TIMESTEP\nfive"),
            "not a whole number (TIMESTEP)",
        ),
        (good.clone() + "ITEM: TIMESTEP\n6\n", "no ATOMS section"),
    ];
    for (text, expected) in cases {
        let e = check(&text, "bad.dump", &[]).unwrap_err();
        assert!(matches!(e, hompm::Error::Input(_)), "{e}");
        let m = e.to_string();
        assert!(m.contains(expected), "expected '{expected}' in: {m}");
        assert!(!m.contains('\n'), "{m}");
    }
    let csv = "x0,u\n0.1,0.0\n";
    let e = check(csv, "dump-step.csv", &["--dump-step", "1"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("--dump-step applies to a LAMMPS dump"), "{e}");
    let e = check(&good, "forced.csv", &["--format", "csv"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("row") || e.contains("column"), "{e}");
}

#[test]
fn the_fuzz_finds_of_issue_36_are_refused_or_agree_as_they_should() {
    let good = dump_block(&[], 5);
    // Ids 2..=n+1 are not LAMMPS' 1..=n: refused (they were read twice as
    // 1-based).
    let shifted: String = good
        .lines()
        .map(|l| match l.split_once(' ') {
            Some((id, rest)) if id.parse::<usize>().is_ok() && rest.starts_with("1 ") => {
                format!("{} {rest}\n", id.parse::<usize>().unwrap() + 1)
            }
            _ => format!("{l}\n"),
        })
        .collect();
    let e = check(&shifted, "shifted.dump", &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("id 65 is not a particle"), "{e}");
    // A second NUMBER OF ATOMS in a block is refused.
    let twice = good.replacen("ITEM: BOX", "ITEM: NUMBER OF ATOMS\n64\nITEM: BOX", 1);
    let e = check(&twice, "twice.dump", &[]).unwrap_err().to_string();
    assert!(e.contains("a second NUMBER OF ATOMS"), "{e}");
    // Line numbers count blank lines among the rows.
    let mut lines: Vec<String> = good.lines().map(str::to_string).collect();
    lines.insert(12, String::new());
    lines.insert(12, String::new());
    lines[16] = lines[16].replacen(" 1 ", " one ", 1);
    let e = check(&(lines.join("\n") + "\n"), "blank.dump", &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("line 17:"), "{e}");
    // An unknown item with a Unicode line separator stays on one line.
    let sep = good.replacen("ITEM: BOX BOUNDS sm sm sm", "ITEM: BOX\u{2028}X", 1);
    let e = check(&sep, "sep.dump", &[]).unwrap_err().to_string();
    let line = hompm::cli::one_line(&e);
    assert!(
        line.contains("\\u{2028}") && line.lines().count() == 1,
        "{line}"
    );
}

#[test]
fn a_dump_reads_time_and_units_items_and_refuses_bad_box_bounds_and_short_blocks() {
    let good = dump_block(&[], 5);
    let with_items = good.replacen(
        "ITEM: NUMBER OF ATOMS",
        "ITEM: UNITS\nsi\nITEM: TIME\n0.01999\nITEM: NUMBER OF ATOMS",
        1,
    );
    assert!(check(&with_items, "items.dump", &[])
        .unwrap()
        .stdout
        .starts_with("agrees"));
    for (bounds, name) in [("0\n", "one"), ("0 x\n", "word")] {
        let bad = good.replacen("0 25\n", bounds, 1);
        let e = check(&bad, &format!("bounds-{name}.dump"), &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("is not a box bound"), "{e}");
    }
    // A block that claims one atom more than it has, followed by another
    // block: the next block's ITEM line is not read as a row.
    let short =
        good.replacen("NUMBER OF ATOMS\n64", "NUMBER OF ATOMS\n65", 1) + &dump_block(&[], 6);
    let e = check(&short, "short.dump", &[]).unwrap_err().to_string();
    assert!(
        e.contains("NUMBER OF ATOMS is 65 but timestep 5 has 64 rows"),
        "{e}"
    );
    // A value that is not finite names its line.
    let e = check(
        &good.replacen("\n1 1 ", "\n1 1 inf ", 1).replacen(
            "ATOMS id type x0",
            "ATOMS id type q x0",
            1,
        ),
        "inf.dump",
        &[],
    );
    let e = e.unwrap_err().to_string();
    assert!(e.contains("line 10: column 'q' is inf"), "{e}");
    // Line numbers are the file's, from 1.
    let e = check(
        &good.replacen("TIMESTEP\n5", "TIMESTEP\nfive", 1),
        "ts.dump",
        &[],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("line 2:"), "{e}");
}
