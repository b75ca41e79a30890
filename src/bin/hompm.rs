//! # The hompm command line
//!
//! A thin wrapper: [`hompm::cli::run`] does all the work and returns the
//! text to print. Warnings and errors go to stderr, one line each with
//! control characters escaped; an error exits 1 (2 for a usage error).
//! Its global allocator starts large arrays at staggered offsets within
//! the page (`hompm::placement`), which changes no result.

use std::io::Write;
use std::process::ExitCode;

/// Large arrays start at staggered offsets within the page
/// (`hompm::placement`): placement only, the same bits.
#[global_allocator]
static ALLOCATOR: hompm::placement::StaggeredAllocator =
    hompm::placement::StaggeredAllocator::new();

fn print(out: &str) {
    let mut stdout = std::io::stdout().lock();
    let _ = stdout.write_all(out.as_bytes());
    let _ = stdout.flush();
}

/// One line on stderr; a closed stderr is not a reason to panic.
fn line_to_stderr(kind: &str, text: &str) {
    let _ = writeln!(
        std::io::stderr().lock(),
        "{kind}: {}",
        hompm::cli::one_line(text)
    );
}

fn fail(e: &hompm::Error) -> ExitCode {
    line_to_stderr("error", &e.to_string());
    ExitCode::from(hompm::cli::exit_code(e))
}

fn main() -> ExitCode {
    match hompm::cli::run(std::env::args_os().skip(1)) {
        Ok(out) => {
            for w in &out.warnings {
                line_to_stderr("warning", w);
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
