//! # The hompm command line
//!
//! A thin wrapper: [`hompm::cli::run`] does all the work and returns the
//! text to print. Warnings and errors go to stderr, one line each with
//! control characters escaped; an error exits 1 (2 for a usage error).

use std::io::Write;
use std::process::ExitCode;

fn print(out: &str) {
    let mut stdout = std::io::stdout().lock();
    let _ = stdout.write_all(out.as_bytes());
    let _ = stdout.flush();
}

fn fail(e: &hompm::Error) -> ExitCode {
    eprintln!("error: {}", hompm::cli::one_line(&e.to_string()));
    ExitCode::from(hompm::cli::exit_code(e))
}

fn main() -> ExitCode {
    match hompm::cli::run(std::env::args_os().skip(1)) {
        Ok(out) => {
            for w in &out.warnings {
                eprintln!("warning: {}", hompm::cli::one_line(w));
            }
            print(&out.stdout);
            match &out.failure {
                Some(e) => fail(e),
                None => ExitCode::SUCCESS,
            }
        }
        Err(e) => fail(&e),
    }
}
