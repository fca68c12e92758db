//! How a configuration names an input file: path, format, column map, constants.

use crate::base::quantity::Quantity;
use crate::base::si::Constant;
use crate::io::formats::{Format, FormatChoice};
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
    pub froude: Option<crate::io::froude::Froude>,
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

/// The longest run name, in characters: a name labels the run in the report and names the
/// file of its state series (`states/NAME.csv`), which must stay within the 255 bytes a file
/// name may have.
pub const MAX_RUN_NAME_CHARS: usize = 200;

/// Highest 1-based column number a column map may name (a CFD export has far fewer).
pub const MAX_COLUMN_INDEX: u64 = 1_000_000;

/// Most title lines `skip_lines` may skip.
pub const MAX_SKIP_LINES: u64 = 100_000;

impl InputSpec {
    /// How the reader is to read the file: `names`, `skip_lines` and `dt` (in s).
    pub fn read_options(&self) -> crate::io::formats::ReadOptions {
        crate::io::formats::ReadOptions {
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
        crate::base::si::value::<D, crate::base::si::Time>(d)
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
        let thrust = crate::base::quantity::Quantity::Thrust.dim();
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
