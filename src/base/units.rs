//! Units as CFD codes write them in column headers, conversion to SI, and angle unwrapping.
//!
//! A unit is parsed into a factor to SI and a dimension vector over (mass, length, time,
//! angle). Angle is kept as its own base dimension so that degrees and radians are told apart
//! and an angle column cannot be given a length unit by mistake. Revolutions are 2 pi rad.
//!
//! Accepted spellings include everything listed in docs/formats.md: `m s^-1`, `m/s`, `m.s-1`,
//! `degree s^-1`, `deg/s`, `N-m`, `N m`, `kg m^2`, `kg.m2`, `1/s`, `rpm`, `kn`, `-` and `1`.

use std::f64::consts::PI;
use std::fmt;

/// Exponents of (mass, length, time, angle).
pub type Dim = [i8; 4];

/// The dimension of a pure number.
pub const DIMENSIONLESS: Dim = [0, 0, 0, 0];

/// A parsed unit: multiply a value by `factor` to get SI (radians for angles).
#[derive(Debug, Clone, PartialEq)]
pub struct Unit {
    /// The unit as written in the file or configuration.
    pub text: String,
    /// Factor to SI.
    pub factor: f64,
    /// Dimension exponents over (kg, m, s, rad).
    pub dim: Dim,
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.text.is_empty() {
            write!(f, "1")
        } else {
            write!(f, "{}", self.text)
        }
    }
}

/// A unit string that could not be understood.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitError {
    /// The text given.
    pub text: String,
    /// Why it failed.
    pub reason: String,
}

impl fmt::Display for UnitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown unit '{}' ({}); known units include m, mm, s, kg, N, kN, N m, rad, deg, \
             rev, rpm, m/s, kn, deg/s, rad/s, Hz, Pa, 1",
            self.text, self.reason
        )
    }
}

impl std::error::Error for UnitError {}

/// (symbols, factor to SI, dimension) of every base symbol the parser knows.
const SYMBOLS: &[(&[&str], f64, Dim)] = &[
    (
        &["m", "meter", "meters", "metre", "metres"],
        1.0,
        [0, 1, 0, 0],
    ),
    (&["mm"], 1e-3, [0, 1, 0, 0]),
    (&["cm"], 1e-2, [0, 1, 0, 0]),
    (&["km"], 1e3, [0, 1, 0, 0]),
    (&["ft", "feet"], 0.3048, [0, 1, 0, 0]),
    (&["in", "inch"], 0.0254, [0, 1, 0, 0]),
    (&["kg"], 1.0, [1, 0, 0, 0]),
    (&["g"], 1e-3, [1, 0, 0, 0]),
    (&["t", "tonne", "tonnes"], 1e3, [1, 0, 0, 0]),
    (
        &["s", "sec", "secs", "second", "seconds"],
        1.0,
        [0, 0, 1, 0],
    ),
    (&["ms"], 1e-3, [0, 0, 1, 0]),
    (&["min"], 60.0, [0, 0, 1, 0]),
    (&["h", "hr", "hour", "hours"], 3600.0, [0, 0, 1, 0]),
    (&["rad", "radian", "radians"], 1.0, [0, 0, 0, 1]),
    (&["deg", "degree", "degrees", "°"], PI / 180.0, [0, 0, 0, 1]),
    (
        &["rev", "revolution", "revolutions", "r"],
        2.0 * PI,
        [0, 0, 0, 1],
    ),
    (&["N", "newton", "newtons"], 1.0, [1, 1, -2, 0]),
    (&["kN"], 1e3, [1, 1, -2, 0]),
    (&["mN"], 1e-3, [1, 1, -2, 0]),
    (&["MN"], 1e6, [1, 1, -2, 0]),
    (&["kgf"], 9.80665, [1, 1, -2, 0]),
    // pound-force: the avoirdupois pound (0.45359237 kg) under standard gravity
    (&["lbf"], 0.453_592_37 * 9.80665, [1, 1, -2, 0]),
    (&["Pa"], 1.0, [1, -1, -2, 0]),
    (&["kPa"], 1e3, [1, -1, -2, 0]),
    (&["J"], 1.0, [1, 2, -2, 0]),
    (&["W"], 1.0, [1, 2, -3, 0]),
    (&["kW"], 1e3, [1, 2, -3, 0]),
    (&["Hz"], 1.0, [0, 0, -1, 0]),
    (&["rpm"], 2.0 * PI / 60.0, [0, 0, -1, 1]),
    (&["rps"], 2.0 * PI, [0, 0, -1, 1]),
    (
        &["kn", "kt", "kts", "knot", "knots"],
        1852.0 / 3600.0,
        [0, 1, -1, 0],
    ),
    (&["1", "-", "", "none", "dimensionless"], 1.0, DIMENSIONLESS),
    (&["%", "percent"], 0.01, DIMENSIONLESS),
];

impl Unit {
    /// The SI unit of `dim` (radians for angles), written `text`.
    pub fn si(text: &str, dim: Dim) -> Unit {
        Unit {
            text: text.to_string(),
            factor: 1.0,
            dim,
        }
    }

    /// Parses a unit as written in a header or a configuration.
    pub fn parse(text: &str) -> Result<Unit, UnitError> {
        let trimmed = text.trim();
        let inner = strip_brackets(trimmed);
        let mut p = Parser {
            chars: inner.chars().collect(),
            pos: 0,
            depth: 0,
            text: trimmed,
        };
        let (factor, dim) = p.expr()?;
        p.skip_separators();
        if p.pos < p.chars.len() {
            return Err(p.error(format!("unexpected '{}'", p.chars[p.pos])));
        }
        Ok(Unit {
            text: inner.trim().to_string(),
            factor,
            dim,
        })
    }

    /// Converts a value in this unit to SI.
    pub fn to_si(&self, value: f64) -> f64 {
        value * self.factor
    }

    /// True when the unit is an angle (rad, deg, rev).
    pub fn is_angle(&self) -> bool {
        self.dim == [0, 0, 0, 1]
    }

    /// True for degrees and degree-based rates, where conversion changes the numbers a user
    /// reads (used to say so in reports).
    pub fn is_degrees(&self) -> bool {
        self.dim[3] != 0 && (self.factor - PI / 180.0).abs() < 1e-12
    }
}

/// Removes one pair of surrounding brackets: `[ m s^-1 ]`, `(m/s)`, `{deg}`.
fn strip_brackets(s: &str) -> &str {
    let s = s.trim();
    for (open, close) in [('[', ']'), ('(', ')'), ('{', '}')] {
        if s.starts_with(open) && s.ends_with(close) && s.len() >= 2 {
            return s[1..s.len() - 1].trim();
        }
    }
    s
}

struct Parser<'a> {
    chars: Vec<char>,
    pos: usize,
    /// Open brackets around `pos`.
    depth: usize,
    text: &'a str,
}

impl Parser<'_> {
    fn error(&self, reason: String) -> UnitError {
        UnitError {
            text: self.text.to_string(),
            reason,
        }
    }

    fn peek(&self) -> Option<char> {
        self.chars.get(self.pos).copied()
    }

    fn skip_separators(&mut self) -> bool {
        let start = self.pos;
        while let Some(c) = self.peek() {
            // '-' separates symbols in `N-m`; as a sign it only follows '^' or a symbol
            // directly (`s-1`), which `exponent` consumes first.
            if c.is_whitespace() || c == '*' || c == '.' || c == '·' || c == '-' {
                self.pos += 1;
            } else {
                break;
            }
        }
        self.pos > start
    }

    /// `a + k b` over the dimension exponents; an exponent beyond +-127 is an error, not an
    /// overflow.
    fn combine(&self, a: Dim, b: Dim, k: i8) -> Result<Dim, UnitError> {
        let mut out = a;
        for (o, x) in out.iter_mut().zip(b) {
            *o = x
                .checked_mul(k)
                .and_then(|kx| o.checked_add(kx))
                .ok_or_else(|| self.error("the exponents are too large".into()))?;
        }
        Ok(out)
    }

    /// expr := term ((sep | '/') term)*
    fn expr(&mut self) -> Result<(f64, Dim), UnitError> {
        self.skip_separators();
        if self.peek().is_none() {
            return Ok((1.0, DIMENSIONLESS));
        }
        let (mut factor, mut dim) = self.term()?;
        loop {
            self.skip_separators();
            match self.peek() {
                None | Some(')') => break,
                Some('/') => {
                    self.pos += 1;
                    self.skip_separators();
                    let (f, d) = self.term()?;
                    factor /= f;
                    dim = self.combine(dim, d, -1)?;
                }
                Some(_) => {
                    let (f, d) = self.term()?;
                    factor *= f;
                    dim = self.combine(dim, d, 1)?;
                }
            }
        }
        Ok((factor, dim))
    }

    /// term := atom exponent?
    fn term(&mut self) -> Result<(f64, Dim), UnitError> {
        let (factor, dim) = self.atom()?;
        let e = self.exponent()?;
        let d = self.combine(DIMENSIONLESS, dim, e)?;
        Ok((factor.powi(e as i32), d))
    }

    fn atom(&mut self) -> Result<(f64, Dim), UnitError> {
        match self.peek() {
            Some('(') => {
                // Units nest a level or two; the bound keeps the recursion shallow.
                if self.depth >= 16 {
                    return Err(self.error("brackets nested too deep".into()));
                }
                self.pos += 1;
                self.depth += 1;
                let r = self.expr()?;
                self.depth -= 1;
                if self.peek() != Some(')') {
                    return Err(self.error("missing ')'".into()));
                }
                self.pos += 1;
                Ok(r)
            }
            Some('1') => {
                self.pos += 1;
                Ok((1.0, DIMENSIONLESS))
            }
            Some(c) if c.is_alphabetic() || c == '°' || c == '%' => {
                let start = self.pos;
                while let Some(c) = self.peek() {
                    if c.is_alphabetic() || c == '°' || c == '%' {
                        self.pos += 1;
                    } else {
                        break;
                    }
                }
                let sym: String = self.chars[start..self.pos].iter().collect();
                lookup(&sym).ok_or_else(|| self.error(format!("'{sym}' is not a known unit")))
            }
            Some(c) => Err(self.error(format!("unexpected '{c}'"))),
            None => Err(self.error("a unit is missing after '/'".into())),
        }
    }

    /// exponent := ('^' | '**')? '-'? digits, or nothing (1).
    fn exponent(&mut self) -> Result<i8, UnitError> {
        let save = self.pos;
        let mut explicit = false;
        if self.peek() == Some('^') {
            self.pos += 1;
            explicit = true;
        } else if self.peek() == Some('*') && self.chars.get(self.pos + 1) == Some(&'*') {
            self.pos += 2;
            explicit = true;
        }
        let mut sign = 1i8;
        if matches!(self.peek(), Some('-') | Some('+')) {
            let next = self.chars.get(self.pos + 1);
            if next.is_some_and(|c| c.is_ascii_digit()) {
                if self.peek() == Some('-') {
                    sign = -1;
                }
                self.pos += 1;
            }
        }
        let start = self.pos;
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.pos += 1;
        }
        if self.pos == start {
            if explicit {
                return Err(self.error("an exponent is missing after '^'".into()));
            }
            self.pos = save;
            return Ok(1);
        }
        let digits: String = self.chars[start..self.pos].iter().collect();
        let e: i8 = digits
            .parse()
            .map_err(|_| self.error(format!("exponent '{digits}' is too large")))?;
        Ok(sign * e)
    }
}

fn lookup(sym: &str) -> Option<(f64, Dim)> {
    // Exact (case-sensitive) first, so `mN` and `MN` differ; then case-insensitive for words.
    for (names, factor, dim) in SYMBOLS {
        if names.contains(&sym) {
            return Some((*factor, *dim));
        }
    }
    if sym.len() > 2 {
        let lower = sym.to_lowercase();
        for (names, factor, dim) in SYMBOLS {
            if names
                .iter()
                .any(|n| n.len() > 2 && n.to_lowercase() == lower)
            {
                return Some((*factor, *dim));
            }
        }
    }
    None
}

/// Writes a dimension in SI symbols, e.g. `kg m^2` or `m s^-1`.
pub fn dim_to_string(dim: Dim) -> String {
    let names = ["kg", "m", "s", "rad"];
    let mut parts = Vec::new();
    for (i, &e) in dim.iter().enumerate() {
        match e {
            0 => {}
            1 => parts.push(names[i].to_string()),
            _ => parts.push(format!("{}^{}", names[i], e)),
        }
    }
    if parts.is_empty() {
        "1".to_string()
    } else {
        parts.join(" ")
    }
}

/// Dimensions with a name: (dimension, words, SI unit, an example value with its unit).
const NAMED_DIMS: &[(Dim, &str, &str, &str)] = &[
    (DIMENSIONLESS, "a pure number", "-", "0.5"),
    ([1, 0, 0, 0], "a mass", "kg", "50 kg"),
    ([0, 1, 0, 0], "a length", "m", "1.2 m"),
    ([0, 2, 0, 0], "an area", "m^2", "0.0314 m^2"),
    ([0, 0, 1, 0], "a time", "s", "20 s"),
    ([0, 0, 0, 1], "an angle", "rad", "4 deg"),
    ([0, 1, -1, 0], "a speed", "m/s", "3 m/s"),
    ([0, 1, -2, 0], "an acceleration", "m/s^2", "0.5 m/s^2"),
    ([0, 0, -1, 1], "an angular rate", "rad/s", "2 deg/s"),
    ([0, 0, -1, 0], "a frequency", "1/s", "2 Hz"),
    ([1, 1, -2, 0], "a force", "N", "22 N"),
    ([1, 2, -2, 0], "a moment", "N m", "5 N m"),
    ([1, 2, 0, 0], "a moment of inertia", "kg m^2", "3.7 kg m^2"),
    ([1, -3, 0, 0], "a density", "kg/m^3", "1025 kg/m^3"),
    ([1, -1, -1, 0], "a dynamic viscosity", "Pa s", "0.001 Pa s"),
    ([1, -1, -2, 0], "a pressure", "Pa", "1000 Pa"),
    ([1, 2, -3, 0], "a power", "W", "100 W"),
];

/// A dimension in words with its SI unit, e.g. `a speed (m/s)`.
pub fn dim_words(dim: Dim) -> String {
    match NAMED_DIMS.iter().find(|(d, ..)| *d == dim) {
        Some((_, words, si, _)) => format!("{words} ({si})"),
        None => format!("a quantity in {}", dim_to_string(dim)),
    }
}

/// An example value of a dimension with its unit, e.g. `22 N`.
pub fn dim_example(dim: Dim) -> String {
    match NAMED_DIMS.iter().find(|(d, ..)| *d == dim) {
        Some((.., example)) => (*example).to_string(),
        None => format!("1 {}", dim_to_string(dim)),
    }
}

/// Checks that `unit` measures `expected`; the error says what the unit measures and what
/// was expected, e.g. `unit 'm/s' is a speed (m/s); expected a force (N), e.g. "22 N"`.
/// Angles may be given in any angle unit (rad, deg, rev): they share one dimension.
pub fn check_dim(unit: &Unit, expected: Dim) -> Result<(), String> {
    if unit.dim == expected {
        return Ok(());
    }
    Err(format!(
        "unit '{unit}' is {}; expected {}, e.g. \"{}\"",
        dim_words(unit.dim),
        dim_words(expected),
        dim_example(expected)
    ))
}

/// Removes 2 pi jumps from a sampled angle (radians) in place, so that a heading that
/// passes +-180 deg becomes continuous. Jumps larger than pi between samples are taken as
/// wraps; NaNs are left alone and do not reset the running offset.
pub fn unwrap_angles(values: &mut [f64]) {
    let mut offset = 0.0;
    let mut prev: Option<f64> = None;
    for v in values.iter_mut() {
        if !v.is_finite() {
            continue;
        }
        let raw = *v;
        if let Some(p) = prev {
            let d = raw - p;
            if d > PI {
                offset -= 2.0 * PI * ((d + PI) / (2.0 * PI)).floor();
            } else if d < -PI {
                offset += 2.0 * PI * ((-d + PI) / (2.0 * PI)).floor();
            }
        }
        prev = Some(raw);
        *v = raw + offset;
    }
}

/// Wraps an angle to (-pi, pi].
pub fn wrap_pi(a: f64) -> f64 {
    let mut w = a.rem_euclid(2.0 * PI);
    if w > PI {
        w -= 2.0 * PI;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn u(s: &str) -> Unit {
        Unit::parse(s).unwrap_or_else(|e| panic!("{s}: {e}"))
    }

    #[test]
    fn cfd_header_units() {
        assert_eq!(u("[ m s^-1 ]").dim, [0, 1, -1, 0]);
        assert_eq!(u("(m/s)").dim, [0, 1, -1, 0]);
        assert_eq!(u("m.s-1").dim, [0, 1, -1, 0]);
        assert!((u("[ degree ]").factor - PI / 180.0).abs() < 1e-15);
        assert_eq!(u("(deg)").dim, [0, 0, 0, 1]);
        let r = u("[ degree s^-1 ]");
        assert_eq!(r.dim, [0, 0, -1, 1]);
        assert!(r.is_degrees());
        assert_eq!(u("(rad/s)").dim, [0, 0, -1, 1]);
        assert_eq!(u("[ N ]").dim, [1, 1, -2, 0]);
        assert_eq!(u("(N-m)").dim, [1, 2, -2, 0]);
        assert_eq!(u("[ N m ]").dim, [1, 2, -2, 0]);
        assert_eq!(u("[ kg m^2 ]").dim, [1, 2, 0, 0]);
        assert_eq!(u("kg.m2").dim, [1, 2, 0, 0]);
        assert_eq!(u("(s)").dim, [0, 0, 1, 0]);
        assert_eq!(u("[ s ]").dim, [0, 0, 1, 0]);
        assert_eq!(u("1/s").dim, [0, 0, -1, 0]);
        assert_eq!(u("kg/(m s)").dim, [1, -1, -1, 0]);
        assert_eq!(u("-").dim, DIMENSIONLESS);
        assert_eq!(u("").dim, DIMENSIONLESS);
    }

    #[test]
    fn factors() {
        assert!((u("kN").factor - 1e3).abs() < 1e-9);
        assert!((u("km/h").factor - 1.0 / 3.6).abs() < 1e-12);
        assert!((u("kn").factor - 0.514_444_444).abs() < 1e-9);
        assert!((u("lbf").factor - 4.448_221_615).abs() < 1e-9);
        assert!((u("lbf ft").factor - 1.355_817_948).abs() < 1e-9);
        assert!((u("rpm").factor - 2.0 * PI / 60.0).abs() < 1e-12);
        assert!((u("mm").factor - 1e-3).abs() < 1e-15);
        assert!((u("m/s^2").factor - 1.0).abs() < 1e-15);
        assert_eq!(u("m/s^2").dim, [0, 1, -2, 0]);
    }

    #[test]
    fn unknown_units_are_errors() {
        assert!(Unit::parse("furlong").is_err());
        assert!(Unit::parse("m^").is_err());
        assert!(Unit::parse("(m").is_err());
        // Found by tests/fuzz_readers.rs: overflowing exponents, runaway nesting.
        assert!(Unit::parse(&"s ".repeat(200)).is_err());
        assert!(Unit::parse("m^100 m^100").is_err());
        assert!(Unit::parse(&format!("{}m{}", "(".repeat(100_000), ")".repeat(100_000))).is_err());
        assert_eq!(u("((m))/s").dim, [0, 1, -1, 0]);
        let e = Unit::parse("m/").unwrap_err();
        assert!(e.to_string().contains("m/"));
    }

    #[test]
    fn dimensions_in_words() {
        assert_eq!(dim_words([0, 1, -1, 0]), "a speed (m/s)");
        assert_eq!(dim_example([1, 1, -2, 0]), "22 N");
        assert!(dim_words([3, 0, 0, 0]).contains("kg^3"));
        let e = check_dim(&u("m/s"), [1, 1, -2, 0]).unwrap_err();
        assert!(
            e.contains("'m/s' is a speed (m/s)") && e.contains("a force"),
            "{e}"
        );
        assert!(check_dim(&u("deg"), [0, 0, 0, 1]).is_ok());
        assert!(check_dim(&u("rpm"), [0, 0, -1, 1]).is_ok());
        assert!(check_dim(&u("deg"), [0, 1, -1, 0]).is_err());
    }

    #[test]
    fn unwrap_heading() {
        let mut a: Vec<f64> = [170.0, 179.0, -179.0, -170.0, 179.0]
            .iter()
            .map(|d: &f64| d.to_radians())
            .collect();
        unwrap_angles(&mut a);
        let deg: Vec<f64> = a.iter().map(|r| r.to_degrees()).collect();
        let want = [170.0, 179.0, 181.0, 190.0, 179.0];
        for (g, w) in deg.iter().zip(want) {
            assert!((g - w).abs() < 1e-9, "{deg:?}");
        }
    }

    #[test]
    fn wrap() {
        assert!((wrap_pi(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-12);
        assert!((wrap_pi(PI) - PI).abs() < 1e-12);
        // the short way round, and -pi to +pi (the autopilot's heading error)
        assert!((wrap_pi(3.5) - (3.5 - 2.0 * PI)).abs() < 1e-12);
        assert!((wrap_pi(-0.2) + 0.2).abs() < 1e-12);
        assert!((wrap_pi(-PI) - PI).abs() < 1e-12);
    }
}
