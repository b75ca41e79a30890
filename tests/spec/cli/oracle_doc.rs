//! docs/oracle.md is a guide a user follows command by command: every line
//! of its `sh` blocks runs here, in order, and must exit as the line's
//! `# exit N` comment says (0 if it says nothing). `hompm` lines run in
//! process through `hompm::cli::run`, with `> FILE` written from its
//! stdout; other lines run under `sh`.

use std::path::Path;

/// The lines of the `sh` blocks of a markdown text.
fn sh_lines(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut inside = false;
    for line in text.lines() {
        if line.starts_with("```") {
            inside = line.trim() == "```sh";
            continue;
        }
        if inside && !line.trim().is_empty() {
            out.push(line.trim().to_string());
        }
    }
    out
}

/// `command  # exit N` → (command, N).
fn expected_exit(line: &str) -> (String, u8) {
    match line.split_once("# exit ") {
        Some((cmd, code)) => (cmd.trim().to_string(), code.trim().parse().unwrap()),
        None => (line.to_string(), 0),
    }
}

#[test]
fn every_command_of_the_oracle_guide_runs_as_the_guide_says() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::env::set_current_dir(root).unwrap();
    std::fs::create_dir_all("target/oracle-example").unwrap();
    let text = std::fs::read_to_string(root.join("docs/oracle.md")).unwrap();
    let lines = sh_lines(&text);
    assert!(lines.len() >= 10, "the guide has its commands");
    for line in lines {
        let (command, expected) = expected_exit(&line);
        let (command, target) = match command.split_once(" > ") {
            Some((c, t)) => (c.to_string(), Some(t.trim().to_string())),
            None => (command, None),
        };
        let code = if let Some(args) = command.strip_prefix("hompm ") {
            let args: Vec<&str> = args.split_whitespace().collect();
            let (stdout, code) = match hompm::cli::run(&args) {
                Ok(out) => {
                    let code = out.failure.as_ref().map_or(0, hompm::cli::exit_code);
                    (out.stdout, code)
                }
                Err(e) => (String::new(), hompm::cli::exit_code(&e)),
            };
            if let Some(t) = &target {
                std::fs::write(t, stdout).unwrap();
            }
            code
        } else {
            let full = match &target {
                Some(t) => format!("{command} > {t}"),
                None => command.clone(),
            };
            let status = std::process::Command::new("sh")
                .arg("-c")
                .arg(&full)
                .status()
                .unwrap();
            status.code().unwrap_or(-1) as u8
        };
        assert_eq!(code, expected, "{line}");
    }
}
