//! VTK and NumPy files as `hompm check --input` (issue #36): the files in
//! tests/fixtures/formats were written by the formats' own writers (VTK
//! 9.7's vtkPolyDataWriter, vtkXMLPolyDataWriter and
//! vtkXMLUnstructuredGridWriter; NumPy's np.save, np.savez and
//! np.savez_compressed) from hompm's own runs, by
//! `scripts/formats_check.py OUT --fixtures tests/fixtures/formats`, which
//! also checks 78 variants outside CI. If hompm's numbers change, that
//! command regenerates them. Each must agree; the float32 copy must differ;
//! each corruption must be one line and exit 2 (`oracle::input_vtk`,
//! `oracle::input_vtk_xml`, `oracle::input_npy`).

use std::path::PathBuf;

const AV: [&str; 11] = [
    "aligned-vibration",
    "--method",
    "bsmpm",
    "--cells",
    "4",
    "--ppc",
    "4",
    "--steps",
    "20",
    "--amplitude",
    "0.05",
];
const AV_YOUNG: [&str; 2] = ["--young", "2e7"];
const BAR: [&str; 10] = [
    "vibrating-bar",
    "--method",
    "bsmpm",
    "--cells",
    "4",
    "--ppc",
    "2",
    "--dt",
    "1e-3",
    "--steps",
];
const BAR_STEPS: &str = "50";

/// hompm's 2D names for VTK's three-component vectors and nine-component
/// (row-major) tensors.
const VTK_2D: &str = "x_x=Points:0,x_y=Points:1,x0_x=x0:0,x0_y=x0:1,u_x=u:0,u_y=u:1,v_x=v:0,v_y=v:1,stress_xx=stress:0,stress_xy=stress:1,stress_yx=stress:3,stress_yy=stress:4,F_xx=F:0,F_xy=F:1,F_yx=F:3,F_yy=F:4";

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/formats")
        .join(name)
}

fn scratch(name: &str, bytes: &[u8]) -> String {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("formats-input");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path.to_str().unwrap().to_string()
}

fn check_2d(path: &str, columns: &str) -> hompm::Result<hompm::cli::Output> {
    let mut args = vec!["check"];
    args.extend_from_slice(&AV);
    args.extend_from_slice(&AV_YOUNG);
    args.extend_from_slice(&["--input", path]);
    if !columns.is_empty() {
        args.extend_from_slice(&["--columns", columns]);
    }
    hompm::cli::run(&args)
}

fn check_1d(path: &str, columns: &str) -> hompm::Result<hompm::cli::Output> {
    let mut args = vec!["check"];
    args.extend_from_slice(&BAR);
    args.extend_from_slice(&[BAR_STEPS, "--input", path]);
    if !columns.is_empty() {
        args.extend_from_slice(&["--columns", columns]);
    }
    hompm::cli::run(&args)
}

fn agrees(out: hompm::Result<hompm::cli::Output>, fields: &str) {
    let out = out.unwrap();
    assert!(out.stdout.starts_with("agrees"), "{}", out.stdout);
    assert!(out.stdout.contains(fields), "{}", out.stdout);
}

#[test]
fn every_vtk_writer_s_file_of_hompm_s_2d_run_agrees_in_every_field() {
    for name in [
        "av-legacy42-binary.vtk",
        "av-legacy51-ascii.vtk",
        "av-binary-raw-UInt32.vtp",
        "av-binary-zlib-UInt32.vtp",
        "av-appended-base64-zlib-UInt32.vtp",
        "av-appended-raw-raw-UInt64.vtu",
    ] {
        let path = fixture(name);
        agrees(
            check_2d(path.to_str().unwrap(), VTK_2D),
            "in u, v, stress, F, x0, x",
        );
    }
}

#[test]
fn a_legacy_ascii_vtk_file_of_the_1d_bar_agrees() {
    let path = fixture("bar-legacy42-ascii.vtk");
    agrees(
        check_1d(path.to_str().unwrap(), "x=Points:0"),
        "in u, v, stress, x0, x",
    );
}

#[test]
fn numpy_arrays_agree_by_their_names_or_their_fields_and_fortran_order_is_read_by_rows() {
    agrees(
        check_2d(fixture("av-structured.npy").to_str().unwrap(), ""),
        "in u, v, stress, x0",
    );
    let fortran = fixture("av-fortran.npy");
    agrees(
        check_2d(
            fortran.to_str().unwrap(),
            "x0_x=0,x0_y=1,u_x=2,u_y=3,v_x=4,v_y=5,stress_xx=6,stress_xy=7,stress_yx=8,stress_yy=9",
        ),
        "in u, v, stress, x0",
    );
    for name in ["bar-named.npz", "bar-compressed.npz"] {
        agrees(
            check_1d(fixture(name).to_str().unwrap(), ""),
            "in u, v, stress, x0, x",
        );
    }
}

#[test]
fn a_float32_copy_differs_at_the_size_of_float32_rounding() {
    let out = check_2d(fixture("av-float32.npz").to_str().unwrap(), "").unwrap();
    assert!(out.stdout.starts_with("differs"), "{}", out.stdout);
    // The worst difference is float32's rounding: relative 2^-24 ≈ 6e-8
    // at most, and more than the tolerance (1e-9).
    let number = |after: &str| -> f64 {
        let at = out.stdout.find(after).unwrap() + after.len();
        let text: String = out.stdout[at..]
            .chars()
            .take_while(|c| !matches!(c, ',' | ' ' | '\n'))
            .collect();
        text.parse().unwrap()
    };
    let (yours, ours) = (number("yours "), number("hompm "));
    let relative = (yours - ours).abs() / ours.abs();
    assert!(
        relative > 1e-9 && relative <= 2f64.powi(-24),
        "{relative:e}: {}",
        out.stdout
    );
}

#[test]
fn vtk_s_three_components_leave_the_unused_z_columns_named_as_ignored() {
    let path = fixture("av-binary-zlib-UInt32.vtp");
    let out = check_2d(path.to_str().unwrap(), VTK_2D).unwrap();
    assert!(out.stdout.contains("x0:2, u:2, v:2"), "{}", out.stdout);
}

fn one_line_exit_2(result: hompm::Result<hompm::cli::Output>, wanted: &str) {
    match result {
        Ok(out) => panic!("accepted: {}", out.stdout),
        Err(e) => {
            let text = e.to_string();
            assert_eq!(hompm::cli::exit_code(&e), 2, "{text}");
            assert!(!text.trim().contains('\n'), "{text}");
            assert!(text.contains(wanted), "wanted '{wanted}' in: {text}");
        }
    }
}

#[test]
fn a_cut_or_padded_numpy_file_is_refused_naming_its_length() {
    let good = std::fs::read(fixture("av-fortran.npy")).unwrap();
    let cut = scratch("cut.npy", &good[..good.len() - 3]);
    one_line_exit_2(check_2d(&cut, "u_x=2"), "cut short");
    let mut padded = good.clone();
    padded.extend([0u8; 8]);
    let padded = scratch("padded.npy", &padded);
    one_line_exit_2(check_2d(&padded, "u_x=2"), "trailing bytes");
}

#[test]
fn a_numpy_header_with_another_key_or_type_is_refused() {
    let good = std::fs::read(fixture("av-fortran.npy")).unwrap();
    let swap = |from: &str, to: &str| {
        assert_eq!(from.len(), to.len());
        let mut bytes = good.clone();
        let at = bytes
            .windows(from.len())
            .position(|w| w == from.as_bytes())
            .unwrap();
        bytes[at..at + from.len()].copy_from_slice(to.as_bytes());
        bytes
    };
    let other_key = scratch("key.npy", &swap("'fortran_order'", "'fortran_ordex'"));
    one_line_exit_2(check_2d(&other_key, "u_x=2"), "fortran_ordex");
    let complex = scratch("complex.npy", &swap("'<f8'", "'<c8'"));
    one_line_exit_2(check_2d(&complex, "u_x=2"), "is complex");
}

#[test]
fn a_damaged_npz_member_is_refused_by_its_checksum() {
    let mut bytes = std::fs::read(fixture("bar-named.npz")).unwrap();
    // A byte inside the first member's data (after its 30-byte local
    // header, the name and the .npy header).
    let at = bytes.len() / 4;
    bytes[at] ^= 0x55;
    let path = scratch("damaged.npz", &bytes);
    one_line_exit_2(check_1d(&path, ""), "npz");
}

#[test]
fn a_legacy_vtk_file_with_other_point_counts_is_refused_naming_the_line() {
    let good = std::fs::read_to_string(fixture("av-legacy51-ascii.vtk")).unwrap();
    let bad = good.replacen("POINT_DATA 64", "POINT_DATA 63", 1);
    assert_ne!(good, bad);
    let path = scratch("count.vtk", bad.as_bytes());
    one_line_exit_2(check_2d(&path, VTK_2D), "POINT_DATA counts other points");
}

#[test]
fn a_vtk_xml_file_of_two_pieces_or_lz4_or_broken_base64_is_refused() {
    let good = std::fs::read_to_string(fixture("av-binary-zlib-UInt32.vtp")).unwrap();
    let lz4 = good.replace("vtkZLibDataCompressor", "vtkLZ4DataCompressor");
    one_line_exit_2(
        check_2d(&scratch("lz4.vtp", lz4.as_bytes()), VTK_2D),
        "compressor",
    );
    let piece_start = good.find("<Piece").unwrap();
    let piece_end = good.find("</Piece>").unwrap() + "</Piece>".len();
    let two = format!(
        "{}{}{}",
        &good[..piece_end],
        &good[piece_start..piece_end],
        &good[piece_end..]
    );
    one_line_exit_2(
        check_2d(&scratch("two.vtp", two.as_bytes()), VTK_2D),
        "more than one Piece",
    );
    let broken = good.replacen("format=\"binary\"", "format=\"binary\" ", 1);
    let at = broken.find("format=\"binary\" ").unwrap();
    let content = broken[at..].find('>').unwrap() + at + 1;
    let mut bytes = broken.into_bytes();
    // A character outside base64's alphabet inside the first array.
    let k = (content..bytes.len())
        .find(|&k| bytes[k].is_ascii_alphanumeric())
        .unwrap();
    bytes[k] = b'!';
    one_line_exit_2(check_2d(&scratch("b64.vtp", &bytes), VTK_2D), "base64");
}

#[test]
fn a_non_finite_value_in_a_vtk_ascii_array_names_its_row() {
    let good = std::fs::read_to_string(fixture("bar-legacy42-ascii.vtk")).unwrap();
    let at = good.find("\nu 1 8 double\n").unwrap() + "\nu 1 8 double\n".len();
    let (values, end) = (at, at + good[at..].find(' ').unwrap());
    let bad = format!("{}nan{}", &good[..values], &good[end..]);
    let path = scratch("nan.vtk", bad.as_bytes());
    one_line_exit_2(check_1d(&path, "x=Points:0"), "finite");
}

/// A legacy VTK fixture with one more point array, `tag`, of VTK type `ty`
/// (one component), whose values are `data` (text in an ASCII file,
/// big-endian bytes in a binary one), appended after its last array.
fn with_tag(fixture_name: &str, fields: usize, ty: &str, data: &[u8], name: &str) -> String {
    let mut bytes = std::fs::read(fixture(fixture_name)).unwrap();
    let from = format!("FIELD FieldData {fields}");
    let at = bytes
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap();
    let to = format!("FIELD FieldData {}", fields + 1);
    bytes.splice(at..at + from.len(), to.bytes());
    let points = if fixture_name.starts_with("bar") {
        8
    } else {
        64
    };
    bytes.extend(format!("tag 1 {points} {ty}\n").bytes());
    bytes.extend(data);
    bytes.push(b'\n');
    scratch(name, &bytes)
}

#[test]
fn integers_as_text_are_read_exactly_over_their_type_s_whole_range_and_refused_beyond_it() {
    // VTK's integer types hold −2^(b−1) … 2^(b−1) − 1 (signed) and
    // 0 … 2^b − 1 (unsigned) for b = 8, 16, 32, 64 bits; a float64 holds
    // every integer only up to 2^53 in magnitude. Each end is accepted
    // (the tag column is then ignored and the file agrees), one past it
    // refused in one line naming the type.
    let cases: [(&str, &str, &[&str]); 8] = [
        ("char", "signed 8-bit", &["-129", "128", "1.5"]),
        ("unsigned_char", "unsigned 8-bit", &["-1", "256"]),
        ("short", "signed 16-bit", &["-32769", "32768"]),
        ("unsigned_short", "unsigned 16-bit", &["-1", "65536"]),
        ("int", "signed 32-bit", &["-2147483649", "2147483648"]),
        ("unsigned_int", "unsigned 32-bit", &["-1", "4294967296"]),
        (
            "long",
            "signed 64-bit",
            &["-9007199254740994", "9007199254740994"],
        ),
        (
            "unsigned_long",
            "unsigned 64-bit",
            &["-1", "9007199254740994"],
        ),
    ];
    let ends = |ty: &str| match ty {
        "char" => ["-128", "127"],
        "unsigned_char" => ["0", "255"],
        "short" => ["-32768", "32767"],
        "unsigned_short" => ["0", "65535"],
        "int" => ["-2147483648", "2147483647"],
        "unsigned_int" => ["0", "4294967295"],
        "long" => ["-9007199254740992", "9007199254740992"],
        _ => ["0", "9007199254740992"],
    };
    for (ty, named, beyond) in cases {
        let [low, high] = ends(ty);
        let text = format!("{low} {high} 0 1 2 3 4 5");
        let path = with_tag(
            "bar-legacy42-ascii.vtk",
            4,
            ty,
            text.as_bytes(),
            &format!("{ty}-ends.vtk"),
        );
        agrees(check_1d(&path, "x=Points:0"), "in u");
        for (k, v) in beyond.iter().enumerate() {
            let text = format!("0 1 2 3 4 5 6 {v}");
            let path = with_tag(
                "bar-legacy42-ascii.vtk",
                4,
                ty,
                text.as_bytes(),
                &format!("{ty}-beyond-{k}.vtk"),
            );
            one_line_exit_2(
                check_1d(&path, "x=Points:0"),
                &format!("{v} is not a whole number of a {named} integer"),
            );
        }
    }
}

#[test]
fn binary_unsigned_integers_are_read_up_to_2_to_the_53_and_refused_one_past_it() {
    // A legacy binary file's unsigned_long array (big-endian bytes):
    // 2^53 is exact in a float64 and read; 2^53 + 1 is not, and refused.
    for (k, last, ok) in [(0, 1u64 << 53, true), (1, (1u64 << 53) + 1, false)] {
        let mut data: Vec<u8> = (0..63u64).flat_map(|v| v.to_be_bytes()).collect();
        data.extend(last.to_be_bytes());
        let path = with_tag(
            "av-legacy42-binary.vtk",
            5,
            "unsigned_long",
            &data,
            &format!("u64-{k}.vtk"),
        );
        let out = check_2d(&path, VTK_2D);
        if ok {
            agrees(out, "in u");
        } else {
            one_line_exit_2(out, "the integer 9007199254740993 is beyond 2^53");
        }
    }
}
