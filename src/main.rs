//! The `hydroid` command line: parse, call the library, print, exit code (all of it in
//! the library's [`hydroid::cli`] layer, so that the command line uses the crate's private
//! helpers and the library's public API stays what users call).
//!
//! Exit codes: 0 ok, 1 run failed, 2 usage or configuration error. Messages go to stderr,
//! results to stdout.

fn main() {
    std::process::exit(hydroid::cli::main());
}
