//! Progress reporting from the pipeline to whoever runs it (a terminal progress bar, plain
//! lines in a log, or nothing in tests).

/// Receives progress while the pipeline runs.
pub trait Progress {
    /// A step finished; `line` says what it did.
    fn stage(&mut self, line: &str);

    /// The filter has processed `done` of `total` samples of pass `pass` (1-based) of
    /// `passes`.
    fn filter(&mut self, pass: usize, passes: usize, done: usize, total: usize) {
        let _ = (pass, passes, done, total);
    }

    /// Something the user should know, said as soon as it arises (the run's result lists
    /// every warning again).
    fn warning(&mut self, warning: &crate::base::warning::Warning) {
        let _ = warning;
    }
}

/// Discards everything.
#[derive(Debug, Default, Clone, Copy)]
pub struct Silent;

impl Progress for Silent {
    fn stage(&mut self, _line: &str) {}
}
