//! Tests of one part of the specification; see tests/spec/main.rs.

mod check_claims;
mod check_strict;
mod cli_contract;
mod cli_fuzz;
mod commands;
mod conventions_cli;
mod dump_input;
mod formats_input;
mod oracle;
mod oracle_doc;
