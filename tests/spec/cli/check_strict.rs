//! A verdict that can be trusted (issue #35): every finding of the issue,
//! made from hompm's own valid output, as a test. `hompm check` never
//! panics, never says "agrees" about something it did not compare, reads
//! every input strictly (one line, exit 2), scales its absolute tolerance
//! by each field's size, stays finite for huge finite inputs, and refuses
//! a convergence study it cannot judge.

use approx::assert_relative_eq;
use hompm::Error;
use serde_json::{json, Value};
use std::path::PathBuf;

/// The 1D setup of these tests: the thesis bar on 4 cells × 2 PPC, 5 steps.
pub(super) const SETUP_1D: &[&str] = &[
    "vibrating-bar",
    "--cells",
    "4",
    "--ppc",
    "2",
    "--dt",
    "1e-3",
    "--steps",
    "5",
];
/// The 2D setup ([`crate::common::SETUP_2D`]).
pub(super) const SETUP_2D: &[&str] = crate::common::SETUP_2D;

fn scratch(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("check-strict");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// `hompm <command> <setup> <extra>`'s stdout.
fn output(command: &str, setup: &[&str], extra: &[&str]) -> String {
    let mut args = vec![command];
    args.extend_from_slice(setup);
    args.extend_from_slice(extra);
    cli::run(&args).unwrap().stdout
}

fn doc(command: &str, setup: &[&str]) -> Value {
    serde_json::from_str(&output(command, setup, &["--json"])).unwrap()
}

/// `hompm check <setup> --input FILE <extra>` on `text`.
fn check(setup: &[&str], name: &str, text: &str, extra: &[&str]) -> cli::Result {
    let path = scratch(name);
    std::fs::write(&path, text).unwrap();
    let p = path.to_str().unwrap().to_string();
    let mut args: Vec<&str> = vec!["check"];
    args.extend_from_slice(setup);
    args.extend_from_slice(&["--input", &p]);
    args.extend_from_slice(extra);
    cli::Result(cli::run(&args))
}

mod cli {
    pub use hompm::cli::*;
    /// A check's outcome, with the assertions these tests make on it.
    pub struct Result(pub hompm::Result<hompm::cli::Output>);
}

impl cli::Result {
    /// Refused as unusable input: one line, exit 2, containing `needle`.
    #[track_caller]
    fn refused(self, needle: &str) {
        match self.0 {
            Err(e) => {
                let line = cli::one_line(&e.to_string());
                assert_eq!(cli::exit_code(&e), 2, "{line}");
                assert!(line.contains(needle), "'{needle}' not in: {line}");
                assert!(line.len() < 600, "a long line: {line}");
            }
            Ok(out) => panic!("accepted ({:?}): {}", out.failure, out.stdout),
        }
    }

    /// Says "differs" (exit 1) with the report printed.
    #[track_caller]
    fn differs(self) -> String {
        match self.0 {
            Ok(out) => match out.failure {
                Some(e @ Error::Differs(_)) => {
                    assert_eq!(cli::exit_code(&e), 1);
                    out.stdout
                }
                other => panic!("not 'differs': {other:?}\n{}", out.stdout),
            },
            Err(e) => panic!("refused: {e}"),
        }
    }

    /// Agrees (exit 0).
    #[track_caller]
    fn agrees(self) -> String {
        match self.0 {
            Ok(out) if out.failure.is_none() => out.stdout,
            Ok(out) => panic!("{:?}\n{}", out.failure, out.stdout),
            Err(e) => panic!("refused: {e}"),
        }
    }
}

fn text(v: &Value) -> String {
    serde_json::to_string(v).unwrap()
}

#[test]
fn a_last_traced_step_with_short_or_empty_displacements_is_refused_not_a_panic() {
    for (setup, key) in [(SETUP_1D, "book-4.12"), (SETUP_2D, "mls-30-u")] {
        let base = doc("trace", setup);
        for keep in [0usize, 1] {
            let mut t = base.clone();
            let steps = t["steps"].as_array_mut().unwrap();
            let last = steps.last_mut().unwrap();
            let v = last["equations"][key].as_array_mut().unwrap();
            let n = if keep == 0 { 0 } else { v.len() - 1 };
            v.truncate(n);
            check(setup, "short.json", &text(&t), &[])
                .refused(&format!("{key}: your trace has {n} values"));
        }
    }
}

#[test]
fn a_column_of_the_wrong_json_type_is_refused_not_dropped() {
    let base = doc("run", SETUP_1D);
    for bad in [json!(null), json!("x"), json!(1.0), json!({}), json!(true)] {
        let mut d = base.clone();
        d["particles"]["u"] = bad;
        check(SETUP_1D, "type.json", &text(&d), &[]).refused("'particles.u' is");
    }
    // An object of columns: `{"u": null}` beside the columns.
    let p = &base["particles"];
    let columns = json!({"x0": p["x0"], "v": p["v"], "u": null});
    check(SETUP_1D, "type.json", &text(&columns), &[]).refused("'u' is null");
    // A number where a column stands is refused by hompm's name.
    let columns = json!({"x0": p["x0"], "v": p["v"], "u": 1.0});
    check(SETUP_1D, "type.json", &text(&columns), &[]).refused("'u' is one number");
    // A row of rows with a string in it.
    let mut d = base.clone();
    d["particles"]["u"][2] = json!("0.1");
    check(SETUP_1D, "type.json", &text(&d), &[]).refused("row 3, column 'u'");
}

#[test]
fn a_third_component_on_a_2d_vector_entry_is_refused_not_ignored() {
    let base = doc("run", SETUP_2D);
    for entry in [json!([0.0, 0.0, 0.0]), json!([0.0]), json!(0.0)] {
        let mut d = base.clone();
        d["particles"]["u"][3] = entry;
        check(SETUP_2D, "third.json", &text(&d), &[]).refused("row 4, column 'u'");
    }
}

/// The fuzz campaign of issue #35 (scripts/fuzz_check.py): a column under
/// one of hompm's names in another shape was split or kept under a name
/// that is not hompm's, dropped as "not compared", and the check agreed on
/// the rest. Every entry of 1D `volume` or `u` as an [a, a] pair, a 2D `u`,
/// `v` or `F` of single numbers, 2D `stress` as pairs or `u` as 4-wide rows:
/// each is refused, naming the quantity and the shape hompm has.
#[test]
fn a_column_of_hompm_s_name_in_another_shape_is_refused_not_dropped() {
    let wrap = |v: &Value, width: usize| -> Value {
        json!(v
            .as_array()
            .unwrap()
            .iter()
            .map(|e| {
                let x = if e.is_array() {
                    e[0].clone()
                } else {
                    e.clone()
                };
                if width == 1 {
                    x
                } else {
                    json!(vec![x; width])
                }
            })
            .collect::<Vec<_>>())
    };
    let base = doc("run", SETUP_1D);
    for (column, needle) in [
        ("volume", "column 'volume_x' is a component of 'volume', which hompm's 1D run has as one number per particle"),
        ("u", "column 'u_x' is a component of 'u'"),
    ] {
        let mut d = base.clone();
        d["particles"][column] = wrap(&d["particles"][column], 2);
        check(SETUP_1D, "shape.json", &text(&d), &[]).refused(needle);
    }
    let base = doc("run", SETUP_2D);
    for (column, width, needle) in [
        (
            "u",
            1,
            "column 'u' has one number per particle, but hompm's 2D 'u' is an [x, y] pair",
        ),
        ("v", 1, "hompm's 2D 'v' is an [x, y] pair"),
        (
            "deformation_gradient",
            1,
            "hompm's 2D 'F' is an [xx, xy, yx, yy] row",
        ),
        ("stress", 2, "column 'stress_x' is a component of 'stress'"),
        ("u", 4, "column 'u_xx' is a component of 'u'"),
    ] {
        let mut d = base.clone();
        d["particles"][column] = wrap(&d["particles"][column], width);
        check(SETUP_2D, "shape2d.json", &text(&d), &[]).refused(needle);
    }
    // A single value under a 2D quantity's name (the second fuzz seed's
    // find: `"u": "x"` or `"u": 1.5` was kept as metadata).
    for value in [json!("x"), json!(1.5)] {
        let mut columns = base["particles"].clone();
        columns["u"] = value;
        check(SETUP_2D, "scalar2d.json", &text(&columns), &[])
            .refused("'u' is one number, not a column");
    }
    // The same in CSV: a 1D code's `u_x` is refused, and `--columns u=u_x`
    // reads it.
    let csv = particles_csv(SETUP_1D).replacen(",u,", ",u_x,", 1);
    check(SETUP_1D, "shape.csv", &csv, &[]).refused("column 'u_x' is a component of 'u'");
    check(SETUP_1D, "shape.csv", &csv, &["--columns", "u=u_x"]).agrees();
}

/// The other side of the shape rule: a column that is no quantity of the
/// run's dimension in any shape is ignored (with a warning), not refused.
/// 1D has no F, so a 1D file's F rows (F_xx …) are ignored; a 2D file's x
/// as single numbers is a position, not a field of the physics, and is
/// ignored while u, v, stress and F are compared.
#[test]
fn a_column_that_is_no_quantity_of_the_run_s_dimension_is_ignored_not_refused() {
    let mut d = doc("run", SETUP_1D);
    let n = d["particles"]["u"].as_array().unwrap().len();
    d["particles"]["F"] = json!(vec![json!([1.0, 0.0, 0.0, 1.0]); n]);
    let out = check(SETUP_1D, "f1d.json", &text(&d), &[]).agrees();
    assert!(out.contains("agrees"), "{out}");
    let mut d = doc("run", SETUP_2D);
    let xs: Vec<Value> = d["particles"]["x"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p[0].clone())
        .collect();
    d["particles"]["x"] = json!(xs);
    check(SETUP_2D, "x2d.json", &text(&d), &[]).agrees();
}

#[test]
fn a_json_key_given_twice_is_refused_in_particles_trace_headers_and_steps() {
    let run = output("run", SETUP_1D, &["--json"]);
    let dup = run.replacen(
        "\"particles\": {",
        "\"particles\": {\"u\": [0,0,0,0,0,0,0,0],",
        1,
    );
    check(SETUP_1D, "dup.json", &dup, &[]).refused("the key 'u' appears twice");
    let trace = output("trace", SETUP_1D, &["--json"]);
    let dup = trace.replacen("\"header\": {", "\"header\": {\"dt\": 1.0,", 1);
    check(SETUP_1D, "dup.json", &dup, &[]).refused("the key 'dt' appears twice");
    let dup = trace.replacen("\"equations\": {", "\"equations\": {\"book-4.5\": [1],", 1);
    check(SETUP_1D, "dup.json", &dup, &[]).refused("the key 'book-4.5' appears twice");
    let dup = trace.replacen("\"step\": 1,", "\"step\": 1, \"step\": 2,", 1);
    check(SETUP_1D, "dup.json", &dup, &[]).refused("the key 'step' appears twice");
    // CSV: a column or a comment key given twice.
    let csv = particles_csv(SETUP_1D);
    let twice = csv.replacen("x0,x,", "x0,x0,", 1);
    check(SETUP_1D, "dup.csv", &twice, &[]).refused("'x0' appears twice");
    let twice = format!("# cells: 4\n# cells: 8\n{csv}");
    check(SETUP_1D, "dup.csv", &twice, &[]).refused("'# cells:' appears twice");
}

/// hompm's final 1D particles as CSV with 17 digits, every column.
fn particles_csv(setup: &[&str]) -> String {
    let d = doc("run", setup);
    let p = &d["particles"];
    let names = ["x0", "x", "u", "v", "stress", "volume", "density"];
    let n = p["u"].as_array().unwrap().len();
    let mut out = names.join(",") + "\n";
    for k in 0..n {
        let row: Vec<String> = names
            .iter()
            .map(|c| format!("{:.17e}", p[c][k].as_f64().unwrap()))
            .collect();
        out.push_str(&(row.join(",") + "\n"));
    }
    out
}

#[test]
fn two_of_hompm_s_fields_mapped_to_one_column_are_refused() {
    let csv = particles_csv(SETUP_1D).replacen("x0,x,u,v,", "X0,x,U,v,", 1);
    check(SETUP_1D, "map.csv", &csv, &["--columns", "x0=X0,u=U,v=U"])
        .refused("maps your column 'U' to both 'u' and 'v'");
    check(SETUP_1D, "map.csv", &csv, &["--columns", "x0=X0,u=U,u=x"])
        .refused("maps both 'U' and 'x' to hompm's 'u'");
    check(SETUP_1D, "map.csv", &csv, &["--columns", "x0=X0,u=U"]).agrees();
}

#[test]
fn a_file_that_gives_none_of_u_v_stress_or_f_is_refused_naming_what_was_ignored() {
    let csv = particles_csv(SETUP_1D).replacen("x0,x,u,v,stress,", "x0,X,ux,vx,s11,", 1);
    check(SETUP_1D, "nophys.csv", &csv, &[])
        .refused("none of u, v, stress or F (u, v, stress); the file's other columns, X, ux, vx, s11, were ignored");
    // With hompm's x and x0 the displacement is derived as x − x0 and
    // compared, and the verdict says so.
    let derived = particles_csv(SETUP_1D).replacen("x0,x,u,v,stress,", "x0,x,ux,vx,s11,", 1);
    let out = check(SETUP_1D, "derived.csv", &derived, &[]).agrees();
    assert!(
        out.contains("derived from your columns: u = x − x0"),
        "{out}"
    );
    // Mapped, the same file agrees, and the verdict names what it compared.
    let out = check(
        SETUP_1D,
        "nophys.csv",
        &csv,
        &["--columns", "u=ux,v=vx,stress=s11,x=X"],
    )
    .agrees();
    assert!(
        out.contains("bit for bit in u, v, stress, x0, x, volume, density"),
        "{out}"
    );
    // One physical field is enough, and the verdict names only what it saw.
    let only_v = particles_csv(SETUP_1D).replacen("x0,x,u,v,stress,", "x0,X,ux,v,s11,", 1);
    let out = check(SETUP_1D, "onlyv.csv", &only_v, &[]).agrees();
    assert!(
        out.contains("bit for bit in v, x0, volume, density"),
        "{out}"
    );
    assert!(
        out.contains("not compared: your columns X, ux, s11"),
        "{out}"
    );
}

#[test]
fn an_x0_that_contradicts_the_id_is_refused_or_seen() {
    let base = doc("run", SETUP_1D);
    let p = &base["particles"];
    let n = p["u"].as_array().unwrap().len();
    let with_id = |x0: Vec<f64>| json!({"id": (0..n).collect::<Vec<_>>(), "x0": x0, "u": p["u"], "v": p["v"]});
    let x0: Vec<f64> = p["x0"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    check(SETUP_1D, "x0.json", &text(&with_id(vec![0.0; n])), &[])
        .refused("row 1: matched by id to hompm's particle 0");
    // One x0 moved by a tenth of the spacing: matched, and seen as a
    // difference in x0.
    let mut moved = x0.clone();
    moved[3] += 0.1 * 25.0 / 8.0;
    let out = check(SETUP_1D, "x0.json", &text(&with_id(moved.clone())), &[]).differs();
    assert!(out.contains("in x0 (x0) at particle 3"), "{out}");
    // Without id the same file is matched by x0 and still differs.
    let no_id = json!({"x0": moved, "u": p["u"], "v": p["v"]});
    check(SETUP_1D, "x0.json", &text(&no_id), &[]).differs();
    // Ids in another order than hompm's, x0 right: refused, and --match x0
    // takes it.
    let mut ids: Vec<usize> = (1..=n).collect();
    ids.reverse();
    let foreign = json!({"id": ids, "x0": x0, "u": p["u"], "v": p["v"]});
    check(SETUP_1D, "x0.json", &text(&foreign), &[]).refused("give --match x0");
    let out = check(SETUP_1D, "x0.json", &text(&foreign), &["--match", "x0"]).agrees();
    assert!(out.contains("matched by x0"), "{out}");
}

#[test]
fn a_2d_code_s_own_one_based_ids_are_refused_when_its_x0_disagree() {
    let base = doc("run", SETUP_2D);
    let p = &base["particles"];
    let n = p["u"].as_array().unwrap().len();
    // The code numbers its particles 1..n in reverse of hompm's order and
    // writes its rows in that order.
    let rev = |key: &str| -> Vec<Value> {
        let mut v = p[key].as_array().unwrap().clone();
        v.reverse();
        v
    };
    let d =
        json!({"id": (1..=n).collect::<Vec<_>>(), "x0": rev("x0"), "u": rev("u"), "v": rev("v")});
    check(SETUP_2D, "ids2d.json", &text(&d), &[]).refused("give --match x0");
    check(SETUP_2D, "ids2d.json", &text(&d), &["--match", "x0"]).agrees();
}

#[test]
fn trace_steps_outside_the_run_are_refused() {
    let base = doc("trace", SETUP_1D);
    for step in [json!(6), json!(0)] {
        let mut t = base.clone();
        *t["steps"]
            .as_array_mut()
            .unwrap()
            .last_mut()
            .unwrap()
            .get_mut("step")
            .unwrap() = step.clone();
        check(SETUP_1D, "beyond.json", &text(&t), &[]).refused("step");
    }
    let mut t = base.clone();
    t["steps"][0]["step"] = json!(18446744073709551615u64);
    check(SETUP_1D, "beyond.json", &text(&t), &[])
        .refused("the trace has step 18446744073709551615");
    let csv = output("trace", SETUP_1D, &["--csv"]);
    let huge = csv.replacen("\n1,", "\n18446744073709551616,", 1);
    check(SETUP_1D, "beyond.csv", &huge, &[]).refused("step must be a whole number");
    let half = csv.replacen("\n1,", "\n1.5,", 1);
    check(SETUP_1D, "beyond.csv", &half, &[]).refused("step must be a whole number");
}

#[test]
fn shuffled_or_reversed_trace_steps_are_ordered_by_number_and_a_missing_last_step_is_refused() {
    let base = doc("trace", SETUP_1D);
    let mut t = base.clone();
    t["steps"].as_array_mut().unwrap().reverse();
    check(SETUP_1D, "rev.json", &text(&t), &[]).agrees();
    let mut t = base.clone();
    t["steps"].as_array_mut().unwrap().swap(1, 3);
    check(SETUP_1D, "shuffled.json", &text(&t), &[]).agrees();
    let mut t = base.clone();
    t["steps"].as_array_mut().unwrap().pop();
    check(SETUP_1D, "nolast.json", &text(&t), &[])
        .refused("the trace ends at step 4; its last step must be the run's last, 5");
    let mut t = base.clone();
    let first = t["steps"][0].clone();
    t["steps"].as_array_mut().unwrap().push(first);
    check(SETUP_1D, "twice.json", &text(&t), &[]).refused("the trace has step 1 twice");
    // In CSV, rows of one step may come apart; the same step in two times
    // is refused.
    let csv = output("trace", SETUP_1D, &["--csv"]);
    let mut lines: Vec<&str> = csv.lines().collect();
    let body = lines.split_off(lines.iter().position(|l| l.starts_with("step,")).unwrap() + 1);
    let mut reversed = lines.join("\n") + "\n";
    for l in body.iter().rev() {
        reversed.push_str(l);
        reversed.push('\n');
    }
    check(SETUP_1D, "rev.csv", &reversed, &[]).refused("has index");
}

#[test]
fn a_json_trace_without_a_header_is_taken_as_it_is() {
    let mut t = doc("trace", SETUP_1D);
    t.as_object_mut().unwrap().remove("header");
    let out = check(SETUP_1D, "nohead.json", &text(&t), &[]).agrees();
    assert!(out.contains("and the trace's 18 equations"), "{out}");
    // A newer schema version is refused; an unknown key in a step too.
    let mut t = doc("trace", SETUP_1D);
    t["version"] = json!(2);
    check(SETUP_1D, "v2.json", &text(&t), &[]).refused("schema version 2");
    let mut t = doc("trace", SETUP_1D);
    t["steps"][0]["note"] = json!("x");
    check(SETUP_1D, "unknown.json", &text(&t), &[]).refused("unknown field `note`");
}

#[test]
fn a_file_with_neither_id_nor_x0_is_refused_unless_order_matching_is_asked_for() {
    let p = doc("run", SETUP_1D)["particles"].clone();
    let d = json!({"u": p["u"], "v": p["v"]});
    check(SETUP_1D, "order.json", &text(&d), &[]).refused("give --match order");
    let out = check(SETUP_1D, "order.json", &text(&d), &["--match", "order"]).agrees();
    assert!(out.contains("matched by order (--match order)"), "{out}");
}

#[test]
fn a_trace_quantity_of_the_wrong_length_is_refused_with_both_counts() {
    let mut t = doc("trace", SETUP_1D);
    t["steps"][1]["equations"]["book-4.10"]
        .as_array_mut()
        .unwrap()
        .push(json!(0.0));
    check(SETUP_1D, "len.json", &text(&t), &[])
        .refused("step 2, book-4.10: your trace has 6 values, hompm's has 5");
}

#[test]
fn a_trace_of_the_wrong_schema_is_refused_in_a_short_line() {
    let mut t = doc("trace", SETUP_1D);
    t["steps"] = json!({"1": t["steps"][0].clone()});
    check(SETUP_1D, "schema.json", &text(&t), &[]).refused("does not follow hompm's schema");
}

#[test]
fn the_verdict_names_the_column_and_values_of_its_worst_difference() {
    // 2D: a relative difference of 1e-3 in u_y of one particle, nothing
    // else: the verdict's values are that component's.
    let mut d = doc("run", SETUP_2D);
    let uy = d["particles"]["u"][5][1].as_f64().unwrap();
    d["particles"]["u"][5][1] = json!(uy * (1.0 + 1e-3));
    let out = check(SETUP_2D, "worst.json", &text(&d), &[]).differs();
    let first = out.lines().next().unwrap();
    assert!(first.contains("in u (u_y) at particle 5"), "{first}");
    assert!(first.contains(&format!("hompm {uy:e}")), "{first}");
    assert!(first.contains("(1.000e-3 relative"), "{first}");
}

#[test]
fn the_absolute_tolerance_is_scaled_by_the_field_s_size() {
    // Rounding around a zero of the stress: ±5e-13 Pa on σ_xy, whose
    // scale is about 1e4 Pa, agrees; the same change on u (scale 1e-4 m)
    // is a difference.
    let mut d = doc("run", SETUP_2D);
    for k in 0..64 {
        let s = &mut d["particles"]["stress"][k];
        let v = s[1].as_f64().unwrap();
        s[1] = json!(v + 5e-13);
        s[2] = json!(v + 5e-13);
    }
    let out = check(SETUP_2D, "atol.json", &text(&d), &["--json"]).agrees();
    let r: Value = serde_json::from_str(&out).unwrap();
    let stress = &r["fields"]["stress"];
    assert!(stress["scale"].as_f64().unwrap() > 1e3, "{stress}");
    // In 2D the stress's absolute tolerance is at least what F's becomes
    // through the neo-Hookean law, (λ + 2μ)·1e-12·max|F| (E = 1e7,
    // ν = 0.3: λ + 2μ = 1.3462e7).
    let f_scale = r["fields"]["F"]["scale"].as_f64().unwrap();
    let lambda_2mu = 1e7 * 0.3 / (1.3 * 0.4) + 1e7 / 1.3;
    assert_relative_eq!(
        stress["atol_abs"].as_f64().unwrap(),
        (1e-12 * stress["scale"].as_f64().unwrap()).max(lambda_2mu * 1e-12 * f_scale),
        max_relative = 1e-12
    );
    let v = &r["fields"]["v"];
    assert_eq!(
        v["atol_abs"].as_f64().unwrap(),
        1e-12 * v["scale"].as_f64().unwrap()
    );
    let mut d = doc("run", SETUP_2D);
    let v = d["particles"]["u"][4][0].as_f64().unwrap();
    d["particles"]["u"][4][0] = json!(v * (1.0 + 1e-6));
    check(SETUP_2D, "atol.json", &text(&d), &[]).differs();
}

#[test]
fn huge_finite_values_give_a_finite_report_in_text_and_json() {
    for huge in [1e155, 1e200, 1e300, 1.7e308, -1.7e308] {
        let mut d = doc("run", SETUP_1D);
        d["particles"]["u"][3] = json!(huge);
        let out = check(SETUP_1D, "huge.json", &text(&d), &["--json"]).differs();
        let r: Value = serde_json::from_str(&out).unwrap();
        assert!(r["error_ratio"].as_f64().unwrap().is_finite(), "{out}");
        assert!(r["fields"]["u"]["rms_exact"]["yours"].as_f64().unwrap() > 0.0);
        let plain = check(SETUP_1D, "huge.json", &text(&d), &[]).differs();
        assert!(!plain.contains("inf") && !plain.contains("NaN"), "{plain}");
    }
    // The difference of ±1.7e308 overflows a double: written as the largest.
    let mut d = doc("run", SETUP_1D);
    let p = &mut d["particles"];
    let n = p["u"].as_array().unwrap().len();
    p["u"] = json!(vec![1.7e308; n]);
    let yours = text(&d);
    let out = check(SETUP_1D, "huge.json", &yours, &["--json"]).differs();
    let r: Value = serde_json::from_str(&out).unwrap();
    assert!(r["fields"]["u"]["max_rel"].as_f64().unwrap().is_finite());
}

#[test]
fn a_stream_is_read_only_up_to_the_memory_limit() {
    // A FIFO whose writer never stops, and /dev/zero: both end in a
    // refusal at --max-memory / 4 bytes.
    let fifo = scratch("endless.fifo");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    let mut inputs = vec![PathBuf::from("/dev/zero")];
    if made.is_ok_and(|s| s.success()) {
        let f = fifo.clone();
        std::thread::spawn(move || {
            use std::io::Write;
            if let Ok(mut w) = std::fs::OpenOptions::new().write(true).open(&f) {
                let chunk = vec![b'1'; 1 << 16];
                while w.write_all(&chunk).is_ok() {}
            }
        });
        inputs.push(fifo);
    }
    for input in inputs {
        let p = input.to_str().unwrap().to_string();
        let mut args = vec!["--max-memory", "256KiB", "check"];
        args.extend_from_slice(SETUP_1D);
        args.extend_from_slice(&["--input", &p]);
        cli::Result(cli::run(&args)).refused("more than 65536 bytes");
    }
}

#[test]
fn a_header_of_a_hundred_thousand_columns_is_read_and_its_ignored_columns_are_listed_briefly() {
    let csv = particles_csv(SETUP_1D);
    let mut lines = csv.lines();
    let extra: Vec<String> = (0..100_000).map(|k| format!("c{k}")).collect();
    let mut wide = format!("{},{}\n", lines.next().unwrap(), extra.join(","));
    let zeros = vec!["0"; extra.len()].join(",");
    for l in lines {
        wide.push_str(&format!("{l},{zeros}\n"));
    }
    let path = scratch("wide.csv");
    std::fs::write(&path, &wide).unwrap();
    let p = path.to_str().unwrap().to_string();
    let mut args = vec!["check"];
    args.extend_from_slice(SETUP_1D);
    args.extend_from_slice(&["--input", &p]);
    let out = hompm::cli::run(&args).unwrap();
    assert!(out.failure.is_none(), "{}", out.stdout);
    assert!(
        out.warnings[0].contains("c9 and 99990 more"),
        "{:?}",
        out.warnings
    );
    assert!(out.stdout.lines().all(|l| l.len() < 1000));
}

#[test]
fn run_json_counts_its_output_in_the_memory_estimate() {
    // 80 000 particles: the JSON text alone is over 40 MiB.
    let refused = hompm::cli::run([
        "--max-memory",
        "50MiB",
        "run",
        "vibrating-bar",
        "--cells",
        "10000",
        "--ppc",
        "8",
        "--steps",
        "1",
        "--json",
    ]);
    match refused {
        Err(Error::OverLimit { flag, .. }) => assert_eq!(flag, "--max-memory"),
        other => panic!("{other:?}"),
    }
}

/// `hompm run` at `cells` cells as JSON text.
fn run_at(cells: usize, steps: &str) -> String {
    let c = cells.to_string();
    output(
        "run",
        &[
            "vibrating-bar",
            "--method",
            "bsmpm",
            "--cells",
            &c,
            "--dt",
            "1e-3",
            "--steps",
            steps,
        ],
        &["--json"],
    )
}

fn convergence(files: &[(&str, String)], extra: &[&str]) -> hompm::Result<hompm::cli::Output> {
    let paths: Vec<String> = files
        .iter()
        .map(|(name, text)| {
            let p = scratch(name);
            std::fs::write(&p, text).unwrap();
            p.to_str().unwrap().to_string()
        })
        .collect();
    let mut args = vec![
        "check",
        "vibrating-bar",
        "--method",
        "bsmpm",
        "--dt",
        "1e-3",
        "--steps",
        "200",
    ];
    args.extend_from_slice(extra);
    args.push("--convergence");
    args.extend(paths.iter().map(String::as_str));
    hompm::cli::run(&args)
}

#[test]
fn convergence_refuses_a_repeated_resolution_a_cells_list_of_another_length_and_another_scene() {
    let (c4, c8) = (run_at(4, "200"), run_at(8, "200"));
    let repeated = convergence(
        &[
            ("r1.json", c4.clone()),
            ("r2.json", c4.clone()),
            ("r3.json", c8.clone()),
        ],
        &[],
    );
    cli::Result(repeated).refused("4 cells follows 4");
    let listed = convergence(
        &[
            ("l1.json", c4.clone()),
            ("l2.json", c8.clone()),
            ("l3.json", c8.clone()),
        ],
        &["--cells", "4,8"],
    );
    cli::Result(listed).refused("--cells lists 2 resolutions for 3 files");
    let column = output(
        "run",
        &[
            "column-self-weight",
            "--cells",
            "8",
            "--dt",
            "1e-3",
            "--steps",
            "200",
        ],
        &["--json"],
    );
    let other = convergence(&[("s1.json", c4), ("s2.json", column)], &[]);
    cli::Result(other).refused("the file says scene = column-self-weight");
}

#[test]
fn convergence_says_when_the_reference_itself_does_not_converge() {
    // hompm's own output on 4, 8, 16 cells: the errors of v grow under
    // refinement at 200 steps, so no order of v can be judged: exit 1.
    let files: Vec<(&str, String)> = vec![
        ("o4.json", run_at(4, "200")),
        ("o8.json", run_at(8, "200")),
        ("o16.json", run_at(16, "200")),
    ];
    let out = convergence(&files, &["--json"]).unwrap();
    let r: Value = serde_json::from_str(&out.stdout).unwrap();
    assert_eq!(
        r["fields"]["v"]["verdict"], "reference does not converge",
        "{}",
        out.stdout
    );
    assert!(r["fields"]["v"]["hompm"]["order"].as_f64().unwrap() < 0.0);
    match out.failure {
        Some(e @ Error::Differs(_)) => {
            assert!(
                e.to_string().contains("v reference does not converge"),
                "{e}"
            )
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn exact_refuses_a_2d_point_outside_the_unit_square() {
    match hompm::cli::run([
        "exact",
        "aligned-vibration",
        "--time",
        "0",
        "--at",
        "0.5,1.1",
    ]) {
        Err(e) => {
            assert_eq!(cli::exit_code(&e), 2);
            assert!(e.to_string().contains("1.1"), "{e}");
        }
        Ok(out) => panic!("accepted: {}", out.stdout),
    }
}

#[test]
fn a_table_s_digits_status_is_a_word_in_json_never_null() {
    let out = hompm::cli::run(["table", "book-4.5-large", "--json"]).unwrap();
    let r: Value = serde_json::from_str(&out.stdout).unwrap();
    for entry in r["to_digits"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|row| row.as_array().unwrap())
    {
        assert!(
            ["yes", "no", "n/a"].contains(&entry.as_str().unwrap()),
            "{entry}"
        );
    }
}

#[test]
fn a_file_of_another_run_is_refused_by_its_metadata() {
    let mut d = doc("run", SETUP_1D);
    d["steps"] = json!(200);
    check(SETUP_1D, "meta.json", &text(&d), &[])
        .refused("the file says steps = 200, this check's setup has 5");
    let csv = format!("# dt: 1e-4\n{}", particles_csv(SETUP_1D));
    check(SETUP_1D, "meta.csv", &csv, &[]).refused("the file says dt = 1e-4");
}

#[test]
fn an_agreeing_check_says_how_small_a_first_order_difference_in_dt_it_can_see() {
    // The bar on 16 cells, 20 steps of 1e-3 s: hompm's own first-order
    // time error, measured from a second run at 2e-3 s, written out here.
    let setup = [
        "vibrating-bar",
        "--cells",
        "16",
        "--dt",
        "1e-3",
        "--steps",
        "20",
    ];
    let fine = doc("run", &setup);
    let coarse = doc(
        "run",
        &[
            "vibrating-bar",
            "--cells",
            "16",
            "--dt",
            "2e-3",
            "--steps",
            "10",
        ],
    );
    let column = |d: &Value, c: &str| -> Vec<f64> {
        d["particles"][c]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    let (v, v2) = (column(&fine, "v"), column(&coarse, "v"));
    let change = v
        .iter()
        .zip(&v2)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let scale = v.iter().map(|a| a.abs()).fold(0.0, f64::max);
    // Δt' − Δt = Δt: E = change, e = change/scale.
    let own = change / scale;
    let out = check(&setup, "res.json", &text(&fine), &["--json"]).agrees();
    let r: Value = serde_json::from_str(&out).unwrap();
    let res = &r["time_resolution"];
    assert_eq!(res["coarse_dt"].as_f64().unwrap(), 2e-3);
    let got = res["fields"]["v"]["own_error"].as_f64().unwrap();
    assert!((got - own).abs() <= 1e-12 * own, "{got} {own}");
    assert!(
        (res["fields"]["v"]["fraction_of_own_error"]
            .as_f64()
            .unwrap()
            - 1e-9 / own)
            .abs()
            <= 1e-12
    );
    assert!(
        r["verdict"]
            .as_str()
            .unwrap()
            .contains("of hompm's own time error"),
        "{out}"
    );
    // A tolerance that lets through more than hompm's own time error: the
    // check says it cannot see a first-order difference.
    let loose = check(
        &setup,
        "res.json",
        &text(&fine),
        &["--rtol", "1", "--atol", "1"],
    )
    .agrees();
    assert!(
        loose.contains("warning: at Δt = 1e-3 a difference of first order in Δt"),
        "{loose}"
    );
    assert!(loose.contains("cannot see it"), "{loose}");
}
