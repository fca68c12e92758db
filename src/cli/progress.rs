//! Progress on stderr: one-line stage summaries, and for the filter passes a bar when stderr
//! is a terminal or, in logs, CI and pipes, a plain line every 10 % of a long filter run.
//! `--quiet` shows none of it.

use super::{Say, Verbosity};
use crate::base::progress::Progress;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Filter work (samples times passes) above which plain progress lines are printed from the
/// start: about 2 s of filtering in a release build.
const LONG_WORK: usize = 20_000;

/// Time after which a filter run counts as long whatever its size.
const LONG_TIME: Duration = Duration::from_secs(2);

/// Progress for the command line.
pub struct Cli {
    say: Say,
    bar: Option<ProgressBar>,
    terminal: bool,
    lines: Lines,
    /// Warnings raised so far, said grouped when the run ends ([`super::warnings`]).
    held: Vec<crate::base::warning::Warning>,
}

impl Cli {
    /// A bar if stderr is a terminal, plain lines otherwise; nothing with `--quiet`.
    pub fn new(say: Say) -> Self {
        Cli {
            say,
            bar: None,
            terminal: std::io::stderr().is_terminal(),
            lines: Lines::default(),
            held: Vec::new(),
        }
    }

    /// Says the warnings raised so far, grouped by kind (once: a second call says nothing).
    pub fn say_warnings(&mut self) {
        self.finish_bar();
        for line in super::warnings::render(&std::mem::take(&mut self.held)) {
            super::note(&line);
        }
    }

    fn finish_bar(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
    }

    fn draw_bar(&mut self, pass: usize, passes: usize, done: usize, total: usize) {
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
    /// A run that fails says the warnings raised before it, ahead of its error.
    fn drop(&mut self) {
        self.say_warnings();
    }
}

impl Progress for Cli {
    fn stage(&mut self, line: &str) {
        self.finish_bar();
        self.say.note(line);
    }

    /// Kept, and said grouped by kind when the run ends or fails, whatever the verbosity.
    fn warning(&mut self, w: &crate::base::warning::Warning) {
        self.held.push(w.clone());
    }

    fn filter(&mut self, pass: usize, passes: usize, done: usize, total: usize) {
        if self.say.verbosity == Verbosity::Quiet {
            return;
        }
        if self.terminal {
            self.draw_bar(pass, passes, done, total);
        } else if let Some(line) = self.lines.update(pass, passes, done, total, Instant::now()) {
            self.say.note(&line);
        }
    }
}

/// Plain progress lines for a log: one at every tenth of the filter's work (all passes
/// together), once the run is long (more than [`LONG_WORK`] samples times passes, or running
/// for more than [`LONG_TIME`]).
#[derive(Debug, Default)]
struct Lines {
    /// The run being followed: (passes, samples per pass), when it started, work done.
    run: Option<((usize, usize), Instant, usize)>,
    /// The next tenth to print.
    next: usize,
}

impl Lines {
    /// The line to print for this report, if any.
    fn update(
        &mut self,
        pass: usize,
        passes: usize,
        done: usize,
        total: usize,
        now: Instant,
    ) -> Option<String> {
        let work = passes * total;
        if work == 0 {
            return None;
        }
        let so_far = (pass.saturating_sub(1) * total + done).min(work);
        let same_run = self
            .run
            .is_some_and(|(shape, _, last)| shape == (passes, total) && so_far >= last);
        if !same_run {
            // a new filter run: start counting afresh
            self.run = Some(((passes, total), now, so_far));
            self.next = 1;
        }
        let (shape, start, _) = self.run?;
        self.run = Some((shape, start, so_far));
        let long = work > LONG_WORK || now.duration_since(start) > LONG_TIME;
        let tenth = so_far * 10 / work;
        if !long || tenth < self.next {
            return None;
        }
        self.next = tenth + 1;
        Some(format!(
            "hekf: {} % of the filter work done (pass {pass}/{passes})",
            tenth * 10
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Feeds a whole filter run reported every `every` samples, at `dt` per report.
    fn follow(passes: usize, total: usize, every: usize, dt: Duration) -> Vec<String> {
        let mut lines = Lines::default();
        let t0 = Instant::now();
        let mut out = Vec::new();
        let mut k = 0;
        for pass in 1..=passes {
            let mut done = 0;
            while done < total {
                done = (done + every).min(total);
                k += 1;
                out.extend(lines.update(pass, passes, done, total, t0 + dt * k));
            }
        }
        out
    }

    #[test]
    fn a_long_run_prints_every_tenth_once() {
        let lines = follow(3, 10_000, 250, Duration::ZERO);
        assert_eq!(lines.len(), 10, "{lines:#?}");
        assert_eq!(lines[0], "hekf: 10 % of the filter work done (pass 1/3)");
        assert_eq!(lines[3], "hekf: 40 % of the filter work done (pass 2/3)");
        assert_eq!(lines[9], "hekf: 100 % of the filter work done (pass 3/3)");
    }

    #[test]
    fn a_short_run_prints_nothing() {
        // 3 x 2001 samples reported every 250, 1 ms apart: well under 2 s
        assert!(follow(3, 2001, 250, Duration::from_millis(1)).is_empty());
    }

    #[test]
    fn a_small_but_slow_run_prints_once_it_has_taken_two_seconds() {
        // 3 x 2001 samples, 0.2 s per report of 250 samples: 2 s pass at report 11 (~46 %)
        let lines = follow(3, 2001, 250, Duration::from_millis(200));
        assert_eq!(
            lines.first().map(String::as_str),
            Some("hekf: 40 % of the filter work done (pass 2/3)")
        );
        assert_eq!(lines.len(), 7, "{lines:#?}");
    }

    #[test]
    fn a_second_filter_run_starts_afresh() {
        let mut lines = Lines::default();
        let t = Instant::now();
        assert!(lines.update(1, 1, 30_000, 30_000, t).is_some());
        assert_eq!(
            lines.update(1, 1, 3_000, 30_000, t).as_deref(),
            Some("hekf: 10 % of the filter work done (pass 1/1)")
        );
    }
}
