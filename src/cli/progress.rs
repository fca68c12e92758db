//! Progress on stderr: a bar for the filter passes when stderr is a terminal, plain one-line
//! stage summaries otherwise (logs, CI, pipes).

use hydroid::progress::Progress;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;

/// Progress for the command line.
pub struct Cli {
    bar: Option<ProgressBar>,
    terminal: bool,
}

impl Cli {
    /// A bar if stderr is a terminal, plain lines otherwise.
    pub fn new() -> Self {
        Cli {
            bar: None,
            terminal: std::io::stderr().is_terminal(),
        }
    }

    fn finish_bar(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
    }
}

impl Progress for Cli {
    fn stage(&mut self, line: &str) {
        self.finish_bar();
        super::note(line);
    }

    fn warning(&mut self, w: &hydroid::warning::Warning) {
        self.finish_bar();
        super::note(&format!("warning: {w}"));
    }

    fn filter(&mut self, pass: usize, passes: usize, done: usize, total: usize) {
        if !self.terminal {
            return;
        }
        let bar = self.bar.get_or_insert_with(|| {
            let b = ProgressBar::new((passes * total) as u64);
            if let Ok(style) =
                ProgressStyle::with_template("hekf {msg} [{bar:30}] {percent:>3}% {eta}")
            {
                b.set_style(style.progress_chars("=> "));
            }
            b
        });
        bar.set_message(format!("pass {pass}/{passes}"));
        bar.set_position(((pass - 1) * total + done) as u64);
    }
}

impl Drop for Cli {
    fn drop(&mut self) {
        self.finish_bar();
    }
}
