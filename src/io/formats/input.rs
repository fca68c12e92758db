//! Opening an input file: the one place where hydroid reads a file it is given (CFD exports,
//! configurations, the hashes of a run's inputs).
//!
//! Only regular files are read. A folder, a named pipe, a device (`/dev/zero`,
//! `/dev/urandom`, `/dev/stdin` on a terminal), a socket, a dangling symbolic link or a loop of
//! links is refused with what it is, before anything is opened (opening a pipe could block
//! forever, reading a device never ends). Symbolic links to regular files are followed.
//!
//! Reads are bounded: a file larger than [`Limits::max_bytes`] is refused from its size
//! before reading, and the bound is enforced again while reading because a file can grow
//! (a solver still writing it). A line longer than [`Limits::max_line_bytes`] stops the read
//! with the line's number. A table wider than [`Limits::max_columns`] is refused by the
//! readers before any line is split into cells (`formats::text::check_width`). The bounds can
//! be raised with environment variables ([`MAX_SIZE_ENV`], [`MAX_LINE_ENV`],
//! [`MAX_COLUMNS_ENV`]).

use crate::base::error::{InputError, Place};
use std::fs::{self, File};
use std::io::{self, Read};
use std::path::{Path, PathBuf};

/// The environment variable that sets the largest file hydroid reads (`4G`, `512M`).
pub const MAX_SIZE_ENV: &str = "HYDROID_MAX_INPUT_SIZE";
/// The environment variable that sets the longest line hydroid reads (`256M`).
pub const MAX_LINE_ENV: &str = "HYDROID_MAX_LINE_LENGTH";
/// The environment variable that sets the widest table hydroid reads (`100000`).
pub const MAX_COLUMNS_ENV: &str = "HYDROID_MAX_COLUMNS";

/// How much of one file hydroid reads at most.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// The largest file, in bytes.
    pub max_bytes: u64,
    /// The longest line, in bytes (terminator excluded).
    pub max_line_bytes: u64,
    /// The most cells on one line of a table (its columns).
    pub max_columns: u64,
}

impl Limits {
    /// 2 GiB. Reading a table takes memory in proportion to its cells (the text, the line
    /// index, the copy the CSV parser reads, the numbers): some 20 times the file, up to 50
    /// times for a file of empty cells (tests/memory_bound.rs). The largest CFD histories
    /// seen (10^7 rows of 10 channels) are about 1.5 GB.
    pub const DEFAULT_MAX_BYTES: u64 = 2 << 30;
    /// 64 MiB: the column limit bounds the cells of a line; this bounds its bytes.
    pub const DEFAULT_MAX_LINE_BYTES: u64 = 64 << 20;
    /// 10,000 columns: far more than any CFD export or test log has (a few hundred monitors
    /// at most), and few enough that the structures kept per column stay small beside the
    /// numbers: a table of any shape then takes memory in proportion to its cells (docs/formats.md).
    pub const DEFAULT_MAX_COLUMNS: u64 = 10_000;

    /// The most [`MAX_COLUMNS_ENV`] may be: 100,000 columns. What a table keeps per column
    /// does not depend on its rows (following an earlier refusal's advice,
    /// `HYDROID_MAX_COLUMNS=33554432`, aborted at 7.5 GB); a table at this maximum reads
    /// within the hostile corpus's 3 GiB (tests/hostile/lines.rs).
    pub const MOST_COLUMNS: u64 = 100_000;
    /// The most [`MAX_SIZE_ENV`] and [`MAX_LINE_ENV`] may be: 64 GiB. These limits cost
    /// nothing themselves (a read takes memory in proportion to the file actually read, about
    /// 20 times its size); beyond this no table is read whole.
    pub const MOST_BYTES: u64 = 64 << 30;

    /// The defaults, overridden by [`MAX_SIZE_ENV`], [`MAX_LINE_ENV`] and [`MAX_COLUMNS_ENV`]
    /// when they are set. A value that is not a size (a count of columns), or is above its
    /// maximum ([`Limits::MOST_BYTES`], [`Limits::MOST_COLUMNS`]), is an error naming the
    /// variable and what it may be.
    pub fn from_env() -> Result<Limits, String> {
        let mut limits = Limits::default();
        for (var, slot) in [
            (MAX_SIZE_ENV, &mut limits.max_bytes),
            (MAX_LINE_ENV, &mut limits.max_line_bytes),
            (MAX_COLUMNS_ENV, &mut limits.max_columns),
        ] {
            if let Some(value) = std::env::var_os(var) {
                *slot = env_limit(var, &value.to_string_lossy())?;
            }
        }
        Ok(limits)
    }

    /// [`Limits::from_env`] with its error placed on `path` (the file about to be read).
    pub fn for_file(path: &Path) -> Result<Limits, InputError> {
        Limits::from_env().map_err(|m| InputError::new(Place::file(path), m))
    }
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_bytes: Limits::DEFAULT_MAX_BYTES,
            max_line_bytes: Limits::DEFAULT_MAX_LINE_BYTES,
            max_columns: Limits::DEFAULT_MAX_COLUMNS,
        }
    }
}

/// The value `text` of the limit variable `var`: a size (a count of columns) from 1 to its
/// maximum, or an error saying what to write.
fn env_limit(var: &str, text: &str) -> Result<u64, String> {
    let (what, most, example) = if var == MAX_COLUMNS_ENV {
        (
            "a number of columns (a whole number above 0, K = 1024)",
            Limits::MOST_COLUMNS,
            "100000".to_string(),
        )
    } else {
        (
            "a number of bytes with an optional K, M, G or T suffix (powers of 1024)",
            Limits::MOST_BYTES,
            if var == MAX_LINE_ENV { "1G" } else { "8G" }.to_string(),
        )
    };
    let shown: String = text.chars().take(40).collect();
    let most_text = if var == MAX_COLUMNS_ENV {
        most.to_string()
    } else {
        suggested_size(most)
    };
    match parse_size(text) {
        Some(n) if n <= most => Ok(n),
        Some(_) => Err(format!(
            "the environment variable {var}='{shown}' is above {most_text}, the most it may be \
             ({}); write at most {var}={most_text}",
            if var == MAX_COLUMNS_ENV {
                "a wider table would take memory out of proportion with its numbers"
            } else {
                "no file larger than this is read whole"
            }
        )),
        None => Err(format!(
            "the environment variable {var}='{shown}' is not a size; write {what} from 1 to \
             {most_text}, e.g. {var}={example}"
        )),
    }
}

/// The smallest size of the form `parse_size` reads (`700K`, `3M`, `4G`) that is at least
/// `bytes`: the value to give a limit so that it admits `bytes`.
pub fn suggested_size(bytes: u64) -> String {
    let mut shift = 0;
    while shift < 40 && bytes >> (shift + 10) > 0 {
        shift += 10;
    }
    let unit = 1u64 << shift;
    let n = bytes.div_ceil(unit);
    let suffix = ["", "K", "M", "G", "T"][shift / 10];
    format!("{n}{suffix}")
}

/// `4096`, `64K`, `512M`, `2G`, `1T` (also `2GiB`, `2GB`, `2 g`): bytes, powers of 1024.
/// Zero is not a size.
pub fn parse_size(text: &str) -> Option<u64> {
    let t = text.trim();
    let digits = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (number, suffix) = t.split_at(digits);
    let n: u64 = number.parse().ok()?;
    let suffix = suffix.trim().to_ascii_lowercase();
    let suffix = suffix
        .strip_suffix("ib")
        .or_else(|| suffix.strip_suffix('b'))
        .unwrap_or(&suffix);
    let shift = match suffix {
        "" => 0,
        "k" => 10,
        "m" => 20,
        "g" => 30,
        "t" => 40,
        _ => return None,
    };
    n.checked_mul(1 << shift).filter(|&b| b > 0)
}

/// A size for people: `512 B`, `64 KiB`, `2 GiB`, `3.1 GiB`.
pub fn format_size(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 || value.fract() == 0.0 {
        format!("{value} {}", UNITS[unit])
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

const REGULAR: &str = "a regular file (a CFD export or a configuration)";

/// Checks that `path` names a regular file (following symbolic links) and returns its size.
/// Anything else is an error saying what the path is.
pub fn check_regular(path: &Path) -> Result<u64, InputError> {
    let refuse = |what: String| InputError::new(Place::file(path), what).expected(REGULAR);
    match fs::metadata(path) {
        Ok(m) if m.is_file() => Ok(m.len()),
        Ok(m) => Err(refuse(describe_special(&m.file_type()))),
        Err(e) => {
            let is_link = fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
            let what = match link_trouble(path) {
                Some(what) if is_link => what,
                _ => describe_io(&e),
            };
            Err(refuse(what))
        }
    }
}

/// What a file type other than a regular file is, for a message.
fn describe_special(t: &fs::FileType) -> String {
    if t.is_dir() {
        return "is a directory, not a file".into();
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let not_read = "hydroid reads only regular files";
        if t.is_fifo() {
            return format!(
                "is a named pipe (FIFO), not a file; {not_read} (reading a pipe can wait \
                 forever for a writer)"
            );
        }
        if t.is_char_device() {
            return format!(
                "is a character device (such as /dev/zero, /dev/urandom or a terminal), not a \
                 file; {not_read} (a device can produce data without end)"
            );
        }
        if t.is_block_device() {
            return format!("is a block device (a disk), not a file; {not_read}");
        }
        if t.is_socket() {
            return format!("is a socket, not a file; {not_read}");
        }
    }
    "is not a regular file".into()
}

/// An operating-system error on `metadata` or `open`, for a message.
fn describe_io(e: &io::Error) -> String {
    match e.kind() {
        io::ErrorKind::NotFound => "file does not exist".into(),
        io::ErrorKind::PermissionDenied => {
            "permission denied: hydroid may not read this file (or a folder on its path)".into()
        }
        io::ErrorKind::NotADirectory => {
            "cannot be reached: a part of the path before the file name is a file, not a folder"
                .into()
        }
        _ => format!("cannot read the file: {e}"),
    }
}

/// Follows a chain of symbolic links from `path`: a dangling link or a loop, described; `None`
/// when the chain ends at something that exists (the problem is then elsewhere).
fn link_trouble(path: &Path) -> Option<String> {
    // Linux gives up after 40 links (ELOOP); so does this walk.
    const MAX_HOPS: usize = 40;
    let mut at: PathBuf = path.to_path_buf();
    for _ in 0..MAX_HOPS {
        match fs::symlink_metadata(&at) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = fs::read_link(&at).ok()?;
                at = match at.parent() {
                    Some(dir) => dir.join(&target),
                    None => target,
                };
            }
            Ok(_) => return None,
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                return Some(format!(
                    "is a symbolic link to '{}', which does not exist (a dangling link)",
                    at.display()
                ));
            }
            Err(_) => return None,
        }
    }
    Some(format!(
        "is a symbolic link that loops: following it never reaches a file (more than \
         {MAX_HOPS} links)"
    ))
}

/// The error for a file over the size limit.
fn too_large(path: &Path, size: Option<u64>, limits: &Limits) -> InputError {
    let how = match size {
        Some(s) => format!("the file is {}, larger than", format_size(s)),
        None => "the file grew while being read beyond".to_string(),
    };
    // what to set that reads the file (when it is known and within the maximum)
    let advice = match size {
        Some(s) if s > Limits::MOST_BYTES => format!(
            "no file larger than {} is read (the most {MAX_SIZE_ENV} may be): split it, or \
             keep only the rows the run needs",
            format_size(Limits::MOST_BYTES)
        ),
        Some(s) => format!(
            "set the environment variable {MAX_SIZE_ENV} to raise the limit, to \
             {MAX_SIZE_ENV}={} for this file (reading it takes about 20 times its size in \
             memory)",
            suggested_size(s)
        ),
        None => format!(
            "set the environment variable {MAX_SIZE_ENV} above the file's size, once it is \
             written whole, to raise the limit (at most {})",
            suggested_size(Limits::MOST_BYTES)
        ),
    };
    InputError::new(
        Place::file(path),
        format!(
            "{how} the {} hydroid reads from one file; {advice}",
            format_size(limits.max_bytes)
        ),
    )
    .expected(format!(
        "a file of at most {}",
        format_size(limits.max_bytes)
    ))
}

/// Opens `path` for reading after [`check_regular`] and the size check.
fn open(path: &Path, limits: &Limits) -> Result<File, InputError> {
    let size = check_regular(path)?;
    if size > limits.max_bytes {
        return Err(too_large(path, Some(size), limits));
    }
    let file = File::open(path)
        .map_err(|e| InputError::new(Place::file(path), describe_io(&e)).expected(REGULAR))?;
    // The path may have been replaced between the check and the open.
    match file.metadata() {
        Ok(m) if m.is_file() => Ok(file),
        Ok(m) => Err(
            InputError::new(Place::file(path), describe_special(&m.file_type())).expected(REGULAR),
        ),
        Err(e) => Err(InputError::new(Place::file(path), describe_io(&e))),
    }
}

/// Reads the regular file at `path` in chunks, handing each to `sink`, never more than
/// `limits.max_bytes` in all. Returns the number of bytes read. A `sink` error stops the read.
pub fn stream(
    path: &Path,
    limits: &Limits,
    sink: impl FnMut(&[u8]) -> Result<(), InputError>,
) -> Result<u64, InputError> {
    pump(open(path, limits)?, path, limits, sink)
}

/// The read loop of [`stream`], over any reader: at most `limits.max_bytes`, whatever the
/// size said before reading.
fn pump(
    reader: impl Read,
    path: &Path,
    limits: &Limits,
    mut sink: impl FnMut(&[u8]) -> Result<(), InputError>,
) -> Result<u64, InputError> {
    const CHUNK: usize = 1 << 16;
    // One byte more than allowed tells a file that grew past the limit.
    let mut reader = reader.take(limits.max_bytes.saturating_add(1));
    let mut buf = vec![0u8; CHUNK];
    let mut total: u64 = 0;
    loop {
        let n = match reader.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => {
                return Err(InputError::new(
                    Place::file(path),
                    format!("cannot read the file after {total} bytes: {e}"),
                ))
            }
        };
        total += n as u64;
        if total > limits.max_bytes {
            return Err(too_large(path, None, limits));
        }
        sink(&buf[..n])?;
    }
    Ok(total)
}

/// Reads the whole regular file at `path`, refusing a file over `limits.max_bytes` or a line
/// over `limits.max_line_bytes` (`\n`, `\r\n` and a lone `\r` end a line). The read stops at
/// the first over-long line.
pub fn read_bytes(path: &Path, limits: &Limits) -> Result<Vec<u8>, InputError> {
    let mut out: Vec<u8> = Vec::new();
    // Bytes since the last line terminator, and the terminators so far.
    let mut run: u64 = 0;
    let (mut lf, mut cr) = (0usize, 0usize);
    stream(path, limits, |chunk| {
        for &b in chunk {
            match b {
                b'\n' => {
                    lf += 1;
                    run = 0;
                }
                b'\r' => {
                    cr += 1;
                    run = 0;
                }
                _ => {
                    run += 1;
                    if run > limits.max_line_bytes {
                        // Lines end in `\n` when the file has any (`\r\n` too), else in `\r`.
                        let line = 1 + if lf > 0 { lf } else { cr };
                        return Err(line_too_long(path, line, limits));
                    }
                }
            }
        }
        out.extend_from_slice(chunk);
        Ok(())
    })?;
    Ok(out)
}

/// The error for line `line` (1-based), longer than the limit. The value advised is the
/// file's size, which no line of it can exceed.
fn line_too_long(path: &Path, line: usize, limits: &Limits) -> InputError {
    let size = fs::metadata(path).map_or(0, |m| m.len());
    let enough = size.max(limits.max_line_bytes + 1).min(Limits::MOST_BYTES);
    InputError::new(
        Place::line(path, line),
        format!(
            "line {line} is longer than {}, the longest line hydroid reads; set the environment \
             variable {MAX_LINE_ENV} to raise the limit (the file's size, \
             {MAX_LINE_ENV}={}, admits any line of it)",
            format_size(limits.max_line_bytes),
            suggested_size(enough)
        ),
    )
    .expected("a text export with line ends (a file without them is binary data or a stream)")
}

/// SHA-256 of a file, hex. The file is read like every input (`formats::input`: a regular
/// file within the size limit), in chunks.
pub fn file_sha256(path: &Path) -> crate::base::error::Result<String> {
    use sha2::{Digest, Sha256};
    let mut hasher = Sha256::new();
    stream(path, &Limits::for_file(path)?, |chunk| {
        hasher.update(chunk);
        Ok(())
    })?;
    Ok(hex(&hasher.finalize()))
}

/// SHA-256 of bytes in memory (a file about to be written), hex, as [`file_sha256`] gives it
/// for the same bytes in a file.
pub fn bytes_sha256(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    hex(&Sha256::digest(bytes))
}

/// Bytes as lower-case hex digits.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_and_its_bytes_hash_alike() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        std::fs::write(&p, "t,u\n0,1\n").unwrap();
        assert_eq!(file_sha256(&p).unwrap(), bytes_sha256(b"t,u\n0,1\n"));
        assert_eq!(
            bytes_sha256(b""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
    }

    #[test]
    fn sizes() {
        assert_eq!(parse_size("4096"), Some(4096));
        assert_eq!(parse_size("64K"), Some(64 << 10));
        assert_eq!(parse_size("2G"), Some(2 << 30));
        assert_eq!(parse_size("2 GiB"), Some(2 << 30));
        assert_eq!(parse_size("512mb"), Some(512 << 20));
        assert_eq!(parse_size("0"), None);
        assert_eq!(parse_size("lots"), None);
        assert_eq!(parse_size("4X"), None);
        assert_eq!(parse_size("99999999999T"), None);
        assert_eq!(format_size(2 << 30), "2 GiB");
        assert_eq!(format_size(100), "100 B");
        assert_eq!(format_size(3 << 29), "1.5 GiB");
        for (bytes, text) in [
            (1, "1"),
            (1023, "1023"),
            (1024, "1K"),
            (1025, "2K"),
            (700 << 10, "700K"),
            ((3 << 30) + 1, "4G"),
            (64 << 30, "64G"),
            (5 << 40, "5T"),
        ] {
            assert_eq!(suggested_size(bytes), text);
            assert!(parse_size(text).unwrap() >= bytes);
        }
    }

    #[test]
    fn every_limit_has_a_maximum_and_garbage_is_named() {
        let ok = |var: &str, text: &str| env_limit(var, text).unwrap();
        let err = |var: &str, text: &str| env_limit(var, text).unwrap_err();
        assert_eq!(ok(MAX_COLUMNS_ENV, "100000"), 100_000);
        assert_eq!(ok(MAX_SIZE_ENV, "64G"), 64 << 30);
        assert_eq!(ok(MAX_LINE_ENV, "1"), 1);
        // the refusal's old advice, which aborted at 7.5 GB
        assert_eq!(
            err(MAX_COLUMNS_ENV, "33554432"),
            "the environment variable HYDROID_MAX_COLUMNS='33554432' is above 100000, the most \
             it may be (a wider table would take memory out of proportion with its numbers); \
             write at most HYDROID_MAX_COLUMNS=100000"
        );
        assert!(err(MAX_COLUMNS_ENV, "100001").contains("above 100000"));
        assert!(err(MAX_SIZE_ENV, "65G").contains("above 64G, the most it may be"));
        assert!(err(MAX_LINE_ENV, "1T").contains("write at most HYDROID_MAX_LINE_LENGTH=64G"));
        for bad in ["0", "-1", "lots", "", "1e5", "99999999999T", "0x10"] {
            let e = err(MAX_COLUMNS_ENV, bad);
            assert!(
                e.contains("is not a size") && e.contains("from 1 to 100000"),
                "{e}"
            );
        }
    }

    /// A file that grows after its size was checked is still cut at the limit.
    #[test]
    fn the_limit_holds_while_reading() {
        let limits = Limits {
            max_bytes: 1000,
            max_line_bytes: 100,
            ..Limits::default()
        };
        let growing = io::Cursor::new(vec![b'1'; 5000]);
        let mut seen = 0;
        let e = pump(growing, Path::new("log.csv"), &limits, |c| {
            seen += c.len();
            Ok(())
        })
        .unwrap_err()
        .to_string();
        assert!(seen <= 1000, "{seen} bytes handed on");
        assert!(
            e.contains("grew while being read") && e.contains("1000 B") && e.contains(MAX_SIZE_ENV),
            "{e}"
        );
        let ok = pump(
            io::Cursor::new(vec![b'1'; 1000]),
            Path::new("x"),
            &limits,
            |_| Ok(()),
        );
        assert_eq!(ok.unwrap(), 1000);
    }
}
