//! How a configuration names an input file: path, format, column map, constants.

use crate::formats::{Format, FormatChoice};
use crate::quantity::Quantity;
use crate::units::{check_dim, Dim, Unit};
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;

/// One input file and how to read it.
///
/// ```toml
/// file = "../cfd_exports/turn.csv"   # relative to the configuration file
/// format = "auto"                    # or cfx, starccm, fluent, delimited, openfoam-...
/// velocity_frame = "body"            # or "earth" (then u, v, w, p, q, r are rotated)
/// [columns]
/// time = "Time"
/// yaw = { column = "Heading", unit = "deg" }
/// [constants]
/// thrust = "22 N"
/// ```
///
/// A quantity that changes in steps and has no column can be given as `steps` (the syntax of
/// `hydroid simulate`): `constants = { thrust = "15 N" }` from the start, then
/// `steps = [{ time = 10.0, thrust = "30 N" }]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputSpec {
    /// A name for reports (defaults to the file name).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The file, relative to the configuration file.
    pub file: PathBuf,
    /// The layout, or `auto` to detect it from the content.
    #[serde(default)]
    pub format: FormatSetting,
    /// Column names for a file without a header line, in file order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub names: Option<Vec<String>>,
    /// Lines at the top of the file that are not part of the table, whatever they hold
    /// (the title lines of a model-test log); kept as titles.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skip_lines: Option<usize>,
    /// The sampling interval of a log whose time column is printed with too few digits
    /// (stamps repeat while the rows differ): the time base is rebuilt as `t0 + k dt`.
    /// Detected from the stamps when not given. A number in s or a string with a unit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<Constant>,
    /// Froude scaling applied when the file is read: `{ lambda = 45.7, to = "model" }`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub froude: Option<crate::froude::Froude>,
    /// Which file column holds each quantity, with its unit if the header does not say it.
    #[serde(default, deserialize_with = "column_map")]
    pub columns: BTreeMap<Quantity, ColumnSpec>,
    /// Quantities that are constant over the run and not in the file (e.g. `thrust = "22 N"`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub constants: BTreeMap<Quantity, Constant>,
    /// Quantities that change in steps over the run and are not in the file: at each step's
    /// time (s) the listed quantities take its values and hold them; before the first step a
    /// quantity has its value in `constants`. Times increase.
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "increasing_steps"
    )]
    pub steps: Vec<Step>,
    /// How each sampled input is read between its samples (docs/hekf.md, "Inputs between
    /// samples"): `between = { rudder = "linear" }`; an input not listed is `auto`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub between: BTreeMap<Quantity, Between>,
    /// Frame of the velocity columns: `body` (default) or `earth`.
    #[serde(default)]
    pub velocity_frame: VelocityFrame,
    /// Frame of the angular rate columns p, q, r when it differs from `velocity_frame` (a
    /// log of earth-frame dx/dt, dy/dt with body yaw and roll rates: `rate_frame = "body"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_frame: Option<VelocityFrame>,
    /// The nominal angles of the run's manoeuvre (HEKF runs only), for `hydroid manoeuvre`
    /// and the report's re-simulation: `manoeuvre = { rudder = "20 deg", check = "10 deg" }`;
    /// an angle not given is inferred from the run (docs/manoeuvres.md, "Nominal angles").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub manoeuvre: Option<ManoeuvreSpec>,
    /// Where the data come from, for the words of the report: `"measured"` (a basin,
    /// sea-trial or captive-test log) or `"cfd"` (a CFD export); by default from the layout
    /// the file is read as ([`DataSource::of_format`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<DataSource>,
}

/// Where an input's data come from: what the report calls them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DataSource {
    /// Measured: a basin or sea-trial log, a captive test.
    Measured,
    /// A CFD export.
    Cfd,
}

impl DataSource {
    /// The default for a file read as `format`: `cfd` for the layouts CFD codes write (CFX,
    /// STAR-CCM+, Fluent, OpenFOAM), `measured` for a plain delimited table (model-test and
    /// sea-trial logs are most often headerless or plain tables).
    pub fn of_format(format: Format) -> Self {
        match format {
            Format::Delimited => DataSource::Measured,
            _ => DataSource::Cfd,
        }
    }

    /// The word the report uses for such data: "measured" or "CFD".
    pub fn word(self) -> &'static str {
        match self {
            DataSource::Measured => "measured",
            DataSource::Cfd => "CFD",
        }
    }
}

/// The nominal angles of a run's turning circle or zig-zag (`manoeuvre = { ... }`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ManoeuvreSpec {
    /// The test's rudder angle, a magnitude: `"35 deg"` for a 35 deg turning circle, `"20 deg"`
    /// for a 20/10 zig-zag.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rudder: Option<Constant>,
    /// The zig-zag's check (execute heading) angle, a magnitude: `"10 deg"` for a 20/10.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub check: Option<Constant>,
}

/// Largest nominal rudder or check angle, deg (a bare number is in rad: 20 would be 1146 deg).
pub const MAX_NOMINAL_ANGLE_DEG: f64 = 90.0;

impl ManoeuvreSpec {
    /// The nominal angles given, rad (magnitudes).
    pub fn nominal(&self) -> crate::manoeuvre::Nominal {
        crate::manoeuvre::Nominal {
            rudder: self.rudder.as_ref().map(|c| c.si.abs()),
            check: self.check.as_ref().map(|c| c.si.abs()),
        }
    }

    /// Adds every problem with the angles (at key path `key`, e.g.
    /// `hekf.runs[0].manoeuvre`) to `p`: each an angle, not zero, at most
    /// [`MAX_NOMINAL_ANGLE_DEG`].
    fn validate(&self, key: &str, p: &mut super::Problems) {
        for (name, c) in [("rudder", &self.rudder), ("check", &self.check)] {
            let Some(c) = c else { continue };
            let k = format!("{key}.{name}");
            if let Err(m) = c.expect_dim([0, 0, 0, 1]) {
                p.add(&k, m);
                continue;
            }
            let deg = c.si.abs().to_degrees();
            if !(deg > 0.0 && deg <= MAX_NOMINAL_ANGLE_DEG) {
                p.add(
                    &k,
                    format!(
                        "must be an angle above 0 and at most {MAX_NOMINAL_ANGLE_DEG} deg, got {} \
                         ({} deg); a number without a unit is in rad: write e.g. \"20 deg\"",
                        c.text,
                        crate::numfmt::num(deg)
                    ),
                );
            }
        }
        if self.rudder.is_none() && self.check.is_none() {
            p.add(
                key,
                "gives no angle: give `rudder` and, for a zig-zag, `check` (e.g. \
                 { rudder = \"20 deg\", check = \"10 deg\" }), or leave the key out",
            );
        }
    }
}

/// Highest 1-based column number a column map may name (a CFD export has far fewer).
pub const MAX_COLUMN_INDEX: u64 = 1_000_000;

/// Most title lines `skip_lines` may skip.
pub const MAX_SKIP_LINES: u64 = 100_000;

impl InputSpec {
    /// Adds every problem with this input (at key path `key`, e.g. `hekf.runs[0]`) to `p`,
    /// except whether its file exists: constants finite and of their quantity's dimension,
    /// column units known and of their quantity's dimension, column numbers from 1, scales
    /// finite and not zero, names listed once, no quantity both a column and a constant.
    pub fn validate(&self, key: &str, p: &mut super::Problems) {
        if self.file.as_os_str().is_empty() {
            p.add(&format!("{key}.file"), "is empty; name the export to read");
        }
        self.validate_constants(key, p);
        self.validate_columns(key, p);
        self.validate_reading(key, p);
        if let Some(m) = &self.manoeuvre {
            if key.starts_with("hekf.") {
                m.validate(&format!("{key}.manoeuvre"), p);
            } else {
                p.add(
                    &format!("{key}.manoeuvre"),
                    "is read only for the runs of hekf.runs and hekf.validation (the manoeuvres \
                     `hydroid manoeuvre` measures); leave it out here",
                );
            }
        }
        if let Some(f) = &self.froude {
            if !(f.lambda.is_finite() && f.lambda > 1.0) {
                p.add(
                    &format!("{key}.froude.lambda"),
                    format!(
                        "must be the scale ratio L_ship / L_model, a number greater than 1 \
                         (e.g. 45.7), got {}",
                        f.lambda
                    ),
                );
            }
        }
    }

    /// The constants and the steps' values: each of its quantity's dimension, and no
    /// constant also a column.
    fn validate_constants(&self, key: &str, p: &mut super::Problems) {
        for (q, c) in &self.constants {
            if let Err(m) = c.expect_quantity(*q) {
                p.add(&format!("{key}.constants.{q}"), m);
            }
            if self.columns.contains_key(q) {
                p.add(
                    &format!("{key}.constants.{q}"),
                    format!("{q} is given both as a column (columns.{q}) and as a constant"),
                );
            }
        }
        for (i, step) in self.steps.iter().enumerate() {
            for (q, c) in &step.values {
                if let Err(m) = c.expect_quantity(*q) {
                    p.add(&format!("{key}.steps[{i}].{q}"), m);
                }
            }
        }
    }

    /// The column mappings: column numbers from 1, scales finite and not zero, units of the
    /// quantity's dimension, and each naming a column.
    fn validate_columns(&self, key: &str, p: &mut super::Problems) {
        for (q, c) in &self.columns {
            let k = format!("{key}.columns.{q}");
            if let Some(i) = c.index {
                p.count_within(
                    &format!("{k}.index"),
                    i as u64,
                    1,
                    MAX_COLUMN_INDEX,
                    "1-based",
                );
            }
            if let Some(f) = c.scale {
                if !(f.is_finite() && f != 0.0) {
                    p.add(
                        &format!("{k}.scale"),
                        format!("must be a finite number other than 0, got {f}"),
                    );
                }
            }
            if let Some(u) = &c.unit {
                let dim = match Unit::parse(u) {
                    Ok(unit) => {
                        check_dim(&q.column_unit(unit), q.dim()).map_err(|m| format!("{q}: {m}"))
                    }
                    Err(e) => Err(e.to_string()),
                };
                if let Err(m) = dim {
                    p.add(&format!("{k}.unit"), m);
                }
            }
            if c.column.is_none() && c.index.is_none() {
                p.add(
                    &k,
                    "names no column: give `column` (a name) or `index` (from 1)",
                );
            }
        }
    }

    /// The reading options: names listed once, lines to skip within the limit, a positive
    /// sample interval.
    fn validate_reading(&self, key: &str, p: &mut super::Problems) {
        if let Some(names) = &self.names {
            p.no_duplicates(&format!("{key}.names"), names.iter().map(String::as_str));
        }
        if let Some(n) = self.skip_lines {
            p.count_within(
                &format!("{key}.skip_lines"),
                n as u64,
                0,
                MAX_SKIP_LINES,
                "lines",
            );
        }
        if let Some(dt) = &self.dt {
            match dt.expect_dim([0, 0, 1, 0]) {
                Ok(()) => p.positive(&format!("{key}.dt"), dt.si, "s"),
                Err(m) => p.add(&format!("{key}.dt"), m),
            }
        }
    }

    /// How the reader is to read the file: `names`, `skip_lines` and `dt` (in s).
    pub fn read_options(&self) -> crate::formats::ReadOptions {
        crate::formats::ReadOptions {
            names: self.names.clone(),
            skip_lines: self.skip_lines.unwrap_or(0),
            dt: self.dt.as_ref().map(|c| c.si),
        }
    }

    /// The name for reports: the configured one, or the file name.
    pub fn display_name(&self) -> String {
        self.name.clone().unwrap_or_else(|| {
            self.file.file_name().map_or_else(
                || self.file.display().to_string(),
                |f| f.to_string_lossy().into_owned(),
            )
        })
    }
}

/// How an input is read between its samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Between {
    /// From the samples: `linear` when the signal moves through intermediate values between
    /// its levels (a sampled continuous signal: a rudder moving at its rate), else the model's
    /// own rule (a step log).
    #[default]
    Auto,
    /// Each sample held until the next (a commanded step; a digital controller's output).
    Hold,
    /// Interpolated linearly between samples (a sampled continuous signal).
    Linear,
}

/// The frame in which a file gives linear and angular velocities.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VelocityFrame {
    /// Body-fixed (u, v, w, p, q, r): used as is.
    #[default]
    Body,
    /// Earth-fixed (x_dot, y_dot, z_dot and earth angular velocity): rotated into the body
    /// frame with the roll, pitch and yaw columns.
    Earth,
}

/// A format setting: `auto` or a format name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FormatSetting(pub FormatChoice);

impl Serialize for FormatSetting {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self.0 {
            FormatChoice::Auto => s.serialize_str("auto"),
            FormatChoice::Fixed(f) => s.serialize_str(f.name()),
        }
    }
}

impl<'de> Deserialize<'de> for FormatSetting {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        FormatChoice::parse(&s).map(FormatSetting).ok_or_else(|| {
            let names: Vec<String> = std::iter::once("auto")
                .chain(Format::ALL.iter().map(|f| f.name()))
                .map(|n| format!("`{n}`"))
                .collect();
            de::Error::custom(format!(
                "unknown format `{s}`, expected one of {}",
                names.join(", ")
            ))
        })
    }
}

/// Where a quantity is in the file: a column name, or a table with details.
///
/// `u = "Velocity u"` or `yaw = { column = "Heading", unit = "deg" }` or
/// `u = { index = 3, unit = "m/s" }` (1-based) or `fx = { column = "Drag", scale = -1 }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColumnSpec {
    /// Column name as in the header.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub column: Option<String>,
    /// 1-based column number, for files without usable names.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub index: Option<usize>,
    /// Unit of the values, needed when the header does not state one (overrides it if it does).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// Factor applied after unit conversion (e.g. -1 when the file gives drag, not force).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
}

impl ColumnSpec {
    /// A spec naming a column only.
    pub fn named(name: &str) -> Self {
        ColumnSpec {
            column: Some(name.to_string()),
            index: None,
            unit: None,
            scale: None,
        }
    }

    /// How the spec refers to its column, for messages.
    pub fn describe(&self) -> String {
        match (&self.column, self.index) {
            (Some(c), _) => format!("'{c}'"),
            (None, Some(i)) => format!("number {i}"),
            (None, None) => "(none given)".to_string(),
        }
    }
}

/// Deserializes either a plain string (the column name) or the full table.
pub(crate) fn column_map<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<BTreeMap<Quantity, ColumnSpec>, D::Error> {
    let raw: BTreeMap<Quantity, ColumnSpecRepr> = BTreeMap::deserialize(d)?;
    Ok(raw.into_iter().map(|(k, v)| (k, v.0)).collect())
}

struct ColumnSpecRepr(ColumnSpec);

impl<'de> Deserialize<'de> for ColumnSpecRepr {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = ColumnSpecRepr;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a column name or a table { column, index, unit, scale }")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                Ok(ColumnSpecRepr(ColumnSpec::named(v)))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                ColumnSpec::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(ColumnSpecRepr)
            }
        }
        d.deserialize_any(V)
    }
}

/// A change of time-varying inputs: at `time` (s) the listed quantities take new values and
/// hold them until the next change. The same in a run configuration (an input's `steps`) and
/// a simulation (`manoeuvre.steps`); a value's unit must fit its quantity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Step {
    /// When, s.
    pub time: f64,
    /// New values by quantity.
    #[serde(flatten)]
    pub values: BTreeMap<Quantity, Constant>,
}

impl<'de> Deserialize<'de> for Step {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Step;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a table such as { time = 10.0, thrust = \"30 N\" }")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Step, A::Error> {
                let mut time = None;
                let mut values = BTreeMap::new();
                while let Some(k) = map.next_key::<StepKey>()? {
                    match k {
                        StepKey::Time => time = Some(map.next_value_seed(Seconds)?),
                        StepKey::Value(q) => {
                            values.insert(q, map.next_value::<Constant>()?);
                        }
                    }
                }
                let time: f64 = time.ok_or_else(|| de::Error::missing_field("time"))?;
                if values.is_empty() {
                    return Err(de::Error::custom(format!(
                        "the step at {time} s changes nothing: give a quantity and its value, \
                         e.g. {{ time = {time}, thrust = \"30 N\" }}"
                    )));
                }
                for (q, c) in &values {
                    c.expect_dim(q.dim()).map_err(|m| {
                        de::Error::custom(format!("the step at {time} s gives {q} = {m}"))
                    })?;
                }
                Ok(Step { time, values })
            }
        }
        d.deserialize_map(V)
    }
}

/// A key of a `steps` entry: `time`, or a quantity.
enum StepKey {
    Time,
    Value(Quantity),
}

impl<'de> Deserialize<'de> for StepKey {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(quantity_key(d, "time")?.map_or(StepKey::Time, StepKey::Value))
    }
}

/// Reads a map key: `fixed` (None) or a quantity; an unknown key names the valid ones.
pub(crate) fn quantity_key<'de, D: Deserializer<'de>>(
    d: D,
    fixed: &str,
) -> Result<Option<Quantity>, D::Error> {
    let s = String::deserialize(d)?;
    if s == fixed {
        return Ok(None);
    }
    Quantity::from_key(&s).map(Some).ok_or_else(|| {
        let valid: Vec<String> = std::iter::once(fixed)
            .chain(Quantity::ALL.iter().map(|q| q.key()))
            .map(|k| format!("`{k}`"))
            .collect();
        de::Error::custom(format!(
            "unknown field `{s}`, expected one of {}",
            valid.join(", ")
        ))
    })
}

/// A time in s, or a string with a unit of time.
struct Seconds;

impl<'de> de::DeserializeSeed<'de> for Seconds {
    type Value = f64;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<f64, D::Error> {
        super::si::value::<D, super::si::Time>(d)
    }
}

/// Deserializes steps whose times increase.
fn increasing_steps<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Step>, D::Error> {
    let steps = Vec::<Step>::deserialize(d)?;
    if let Some(w) = steps.windows(2).find(|w| w[1].time <= w[0].time) {
        return Err(de::Error::custom(format!(
            "steps must be in increasing time: {} s then {} s",
            w[0].time, w[1].time
        )));
    }
    Ok(steps)
}

/// A constant value, given as a number in SI or as a string with a unit (`"4 deg"`).
#[derive(Debug, Clone, PartialEq)]
pub struct Constant {
    /// The value as written.
    pub text: String,
    /// The value in SI (radians for angles).
    pub si: f64,
    /// The unit written, if any.
    pub unit: Option<Unit>,
}

impl Constant {
    /// A constant given in SI.
    pub fn si(value: f64) -> Self {
        Constant {
            text: format!("{value}"),
            si: value,
            unit: None,
        }
    }

    /// Parses `"22 N"`, `"4 deg"` or `"3.0"` (a bare number is SI). The number must be
    /// finite; the unit is only parsed here: [`Constant::expect_dim`] checks that it fits.
    pub fn parse(text: &str) -> Result<Self, String> {
        let t = text.trim();
        let split = t
            .find(|c: char| c.is_whitespace() || (c.is_alphabetic() && c != 'e' && c != 'E'))
            .unwrap_or(t.len());
        let (num, unit) = t.split_at(split);
        let value: f64 = num.trim().parse().map_err(|_| {
            format!("\"{t}\" is not a number with an optional unit, like \"4 deg\"")
        })?;
        let unit = unit.trim();
        let (si, unit) = if unit.is_empty() {
            (value, None)
        } else {
            let u = Unit::parse(unit).map_err(|e| e.to_string())?;
            (u.to_si(value), Some(u))
        };
        if !si.is_finite() {
            return Err(format!("\"{t}\" is not a finite number"));
        }
        Ok(Constant {
            text: t.to_string(),
            si,
            unit,
        })
    }

    /// [`Constant::expect_dim`] for the dimension of `q`, and a magnitude within
    /// [`Quantity::plausible_bound`]: `"1e300 m/s"` for a speed is an error that says what
    /// the bound is, not a run that overflows later.
    pub fn expect_quantity(&self, q: Quantity) -> Result<(), String> {
        self.expect_dim(q.dim())?;
        match q.plausible_bound() {
            Some((bound, what)) if self.si.abs() > bound => {
                // a bare number's text is its full decimal expansion: shown short
                let shown = match self.unit {
                    Some(_) => self.text.clone(),
                    None => super::problems::short(self.si),
                };
                Err(format!(
                    "{shown} is beyond any plausible {q}: at most {what} in magnitude; a unit or \
                     typing mistake?"
                ))
            }
            _ => Ok(()),
        }
    }

    /// Checks that the value is finite and that its unit measures `dim` (a bare number is
    /// SI and fits any dimension); the error names the unit, what it measures and what was
    /// expected.
    pub fn expect_dim(&self, dim: Dim) -> Result<(), String> {
        if !self.si.is_finite() {
            return Err(format!("must be a finite number, got {}", self.text));
        }
        match &self.unit {
            Some(u) => check_dim(u, dim).map_err(|m| format!("\"{}\": {m}", self.text)),
            None => Ok(()),
        }
    }
}

impl Serialize for Constant {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match &self.unit {
            Some(_) => s.serialize_str(&self.text),
            None => s.serialize_f64(self.si),
        }
    }
}

impl<'de> Deserialize<'de> for Constant {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Constant;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number in SI units or a string with a unit, like \"4 deg\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Constant, E> {
                Ok(Constant::si(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Constant, E> {
                Ok(Constant::si(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Constant, E> {
                Ok(Constant::si(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Constant, E> {
                Constant::parse(v).map_err(E::custom)
            }
        }
        d.deserialize_any(V)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_with_units() {
        assert!((Constant::parse("4 deg").unwrap().si - 4f64.to_radians()).abs() < 1e-15);
        assert_eq!(Constant::parse("22 N").unwrap().si, 22.0);
        assert_eq!(Constant::parse("1.5e-3").unwrap().si, 1.5e-3);
        assert!((Constant::parse("3kn").unwrap().si - 3.0 * 1852.0 / 3600.0).abs() < 1e-12);
        assert!(Constant::parse("fast").is_err());
        assert!(Constant::parse("4 parsecs").is_err());
        assert!(Constant::parse("nan N").is_err());
        assert!(Constant::parse("1e999 N").is_err());
        let thrust = crate::quantity::Quantity::Thrust.dim();
        for wrong in ["22 m/s", "22 kg", "22 s"] {
            let e = Constant::parse(wrong)
                .unwrap()
                .expect_dim(thrust)
                .unwrap_err();
            assert!(e.contains("expected a force"), "{e}");
        }
        assert!(Constant::parse("22").unwrap().expect_dim(thrust).is_ok());
        assert!(Constant::parse("22 kN").unwrap().expect_dim(thrust).is_ok());
    }

    #[test]
    fn column_specs_in_both_forms() {
        #[derive(Deserialize)]
        struct T {
            #[serde(deserialize_with = "column_map")]
            columns: BTreeMap<Quantity, ColumnSpec>,
        }
        let t: T = toml::from_str(
            "[columns]\ntime = \"Time\"\nyaw = { column = \"Heading\", unit = \"deg\" }\n",
        )
        .unwrap();
        assert_eq!(t.columns[&Quantity::Time], ColumnSpec::named("Time"));
        assert_eq!(t.columns[&Quantity::Yaw].unit.as_deref(), Some("deg"));
        let e = toml::from_str::<T>("[columns]\nyawn = \"Heading\"\n")
            .err()
            .unwrap();
        assert!(e.message().contains("yawn"), "{}", e.message());
    }
}
