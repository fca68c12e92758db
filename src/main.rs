//! The `hydroid` command line: parse, call the library, print, exit code.
//!
//! Exit codes: 0 ok, 1 run failed, 2 usage or configuration error. Messages go to stderr,
//! results to stdout.

mod cli;

fn main() {
    std::process::exit(cli::main());
}
