//! Errors that name the file, the place in it and what was expected.
//!
//! Every failure a user can cause (a bad file, a bad configuration, a filter that diverges)
//! ends up as one of these; nothing in the library panics on bad input.

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in an input file a problem was found.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Place {
    /// The file.
    pub file: PathBuf,
    /// 1-based line number, when the problem is on one line.
    pub line: Option<usize>,
    /// 1-based column number, when the problem is in one column.
    pub column: Option<usize>,
    /// Column name, when the problem is in one named column.
    pub column_name: Option<String>,
}

impl Place {
    /// A whole file.
    pub fn file(file: &Path) -> Self {
        Place {
            file: file.to_path_buf(),
            ..Default::default()
        }
    }

    /// One line of a file.
    pub fn line(file: &Path, line: usize) -> Self {
        Place {
            file: file.to_path_buf(),
            line: Some(line),
            ..Default::default()
        }
    }

    /// Adds a 1-based column number.
    pub fn with_column(mut self, column: usize) -> Self {
        self.column = Some(column);
        self
    }

    /// Adds a column name.
    pub fn with_column_name(mut self, name: impl Into<String>) -> Self {
        self.column_name = Some(name.into());
        self
    }
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        match (&self.column_name, self.column) {
            (Some(name), Some(col)) => write!(f, ", column {col} '{name}'"),
            (Some(name), None) => write!(f, ", column '{name}'"),
            (None, Some(col)) => write!(f, ", column {col}"),
            (None, None) => Ok(()),
        }
    }
}

/// A problem with one input file.
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    /// Where (boxed to keep `Result<_, InputError>` small).
    pub place: Box<Place>,
    /// What is wrong.
    pub message: String,
    /// What was expected instead, when that can be said.
    pub expected: Option<String>,
}

impl InputError {
    /// A new input error at `place`.
    pub fn new(place: Place, message: impl Into<String>) -> Self {
        InputError {
            place: Box::new(place),
            message: message.into(),
            expected: None,
        }
    }

    /// Says what was expected.
    pub fn expected(mut self, expected: impl Into<String>) -> Self {
        self.expected = Some(expected.into());
        self
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.place, self.message)?;
        if let Some(e) = &self.expected {
            write!(f, " (expected {e})")?;
        }
        Ok(())
    }
}

impl std::error::Error for InputError {}

/// One problem found in a configuration (there may be several).
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigProblem {
    /// The configuration file.
    pub file: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// Dotted key path, e.g. `vehicle.mass`.
    pub key: Option<String>,
    /// What is wrong and what would be right.
    pub message: String,
}

impl fmt::Display for ConfigProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(key) = &self.key {
            write!(f, ": {key}")?;
        }
        write!(f, ": {}", self.message)
    }
}

/// Every error hydroid reports.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An input file is missing, unreadable or malformed.
    #[error("{0}")]
    Input(Box<InputError>),
    /// The configuration has one or more problems (all are listed).
    #[error("{}", list_problems(.0))]
    Config(Vec<ConfigProblem>),
    /// A numerical method failed (a filter diverged, a fit was infeasible).
    #[error("{stage}: {message}")]
    Numerical {
        /// The stage that failed (`polar`, `surge`, `hekf`, ...).
        stage: String,
        /// What happened, and when (simulation time) if it applies.
        message: String,
    },
    /// Reading a file, or looking at one, failed at the operating-system level.
    #[error("{}: {}", path.display(), io_reason(source))]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Writing a file or creating a folder failed at the operating-system level (a full
    /// disk, no permission).
    #[error("cannot write {}: {}", path.display(), io_reason(source))]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A usage error on the command line that clap could not catch.
    #[error("{0}")]
    Usage(String),
}

/// What the operating system said, in words and without its error number: "No space left on
/// device", not "No space left on device (os error 28)".
pub fn io_reason(e: &std::io::Error) -> String {
    let text = e.to_string();
    match text.rfind(" (os error ") {
        Some(i) if text.ends_with(')') => text[..i].to_string(),
        _ => text,
    }
}

fn list_problems(problems: &[ConfigProblem]) -> String {
    let mut s = format!(
        "{} problem{} in the configuration:",
        problems.len(),
        if problems.len() == 1 { "" } else { "s" }
    );
    for p in problems {
        s.push_str("\n  - ");
        s.push_str(&p.to_string());
    }
    s
}

impl From<InputError> for Error {
    fn from(e: InputError) -> Self {
        Error::Input(Box::new(e))
    }
}

impl Error {
    /// A numerical failure in `stage`.
    pub fn numerical(stage: &str, message: impl Into<String>) -> Self {
        Error::Numerical {
            stage: stage.to_string(),
            message: message.into(),
        }
    }

    /// An I/O failure on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Error::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// A failure to write `path` (a file, or a folder being created).
    pub fn write(path: &Path, source: std::io::Error) -> Self {
        Error::Write {
            path: path.to_path_buf(),
            source,
        }
    }

    /// The process exit code for this error: 2 for usage and configuration errors, 1 otherwise.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Config(_) | Error::Usage(_) => 2,
            _ => 1,
        }
    }
}

/// Result with hydroid's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;
/// Why a state or a set of coefficients is outside what a model can integrate: what
/// [`Model::check`](crate::model::models::Model::check) and [`crate::numerics::estimation::System::check`] refuse.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Unphysical {
    /// A rigid-body mass or inertia minus its added mass (or a determinant of them) is not
    /// positive.
    #[error("{what} = {value:.4} is not positive: the mass matrix is singular or indefinite")]
    NotPositive {
        /// The expression, e.g. `m - Yvd`.
        what: &'static str,
        /// Its value, SI.
        value: f64,
    },
    /// The 6-DOF mass matrix M_RB + M_A is not positive definite.
    #[error(
        "the mass matrix M_RB + M_A is not positive definite (Cholesky pivot {pivot:.4e} \
         in {direction}): the added-mass coefficients (Xudot, Yvdot, Zwdot, Kpdot, Mqdot, Nrdot \
         and their couplings) outweigh the rigid body"
    )]
    IndefiniteMassMatrix {
        /// The pivot where the Cholesky factorisation failed.
        pivot: f64,
        /// The degree of freedom of that pivot (`surge` ... `yaw`).
        direction: &'static str,
    },
    /// Something is not finite: `what` is `state`, `state or a coefficient`, ...
    #[error("the {0} is not finite")]
    NotFinite(&'static str),
    /// The pitch angle is too close to 90 deg for Euler angles.
    #[error("pitch {degrees:.1} deg is too close to 90 deg for Euler angles")]
    PitchNearVertical {
        /// The pitch angle, deg.
        degrees: f64,
    },
}
