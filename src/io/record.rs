//! A CFD record: the quantities a stage needs, in SI, picked from a table by the
//! configuration's column map, with the checks every stage relies on.

use crate::base::error::{InputError, Place};
use crate::base::quantity::{unwrap_attitude, Quantity};
use crate::base::units::{dim_to_string, Unit};
use crate::io::formats::{self, Format};
use crate::io::input_spec::{ColumnSpec, InputSpec, VelocityFrame};
use crate::io::table::Table;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Quantities in SI from one input file.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Name for reports.
    pub name: String,
    /// The file.
    pub source: PathBuf,
    /// The layout it was read as.
    pub format: Format,
    /// Sampled quantities, each as long as `lines`. Time, when present, is `Quantity::Time`.
    pub channels: BTreeMap<Quantity, Vec<f64>>,
    /// Quantities constant over the run, from the configuration.
    pub constants: BTreeMap<Quantity, f64>,
    /// The unit each channel was read in (for reports: "deg" when converted from degrees).
    pub units: BTreeMap<Quantity, String>,
    /// The file column each channel was read from, for messages that name it (empty for a
    /// record made in memory, and for quantities given as steps or read from a quaternion).
    pub columns: BTreeMap<Quantity, ColumnOrigin>,
    /// 1-based file line of each row.
    pub lines: Vec<usize>,
    /// Header metadata of the file.
    pub meta: Vec<(String, String)>,
    /// Things fixed or noticed while reading.
    pub warnings: Vec<String>,
    /// The print resolution of each sample (SI) of the channels printed with so few digits
    /// that their rounding is part of the measurement noise (`crate::numerics::printed`); absent for a
    /// channel printed finely enough or made in memory.
    pub resolution: BTreeMap<Quantity, Vec<f64>>,
    /// How an input is read between its samples, where the configuration says
    /// (`between`); `auto` for the others.
    pub between: BTreeMap<Quantity, crate::io::input_spec::Between>,
}

/// Where a channel of a record came from.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnOrigin {
    /// The column's name in the file (or in `names`).
    pub name: String,
    /// Its 1-based number.
    pub number: usize,
    /// The `scale` factor applied after the unit conversion.
    pub scale: f64,
}

impl std::fmt::Display for ColumnOrigin {
    /// `column 'delta' (10)`, with ` scaled by -1` when a scale was applied.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "column '{}' ({})", self.name, self.number)?;
        if self.scale != 1.0 {
            write!(f, " scaled by {}", self.scale)?;
        }
        Ok(())
    }
}

/// What a stage needs from a record.
#[derive(Debug, Clone, Copy)]
pub struct Needs<'a> {
    /// Quantities that must be present (as a column or a constant).
    pub required: &'a [Quantity],
    /// Quantities used when present.
    pub optional: &'a [Quantity],
    /// Fewest rows that make sense.
    pub min_rows: usize,
}

impl Record {
    /// A record of sampled channels made in memory (a test, a synthetic run): delimited
    /// format, no constants or units, file lines 2, 3 ... as under a one-line header.
    pub fn from_channels(name: &str, source: &str, channels: BTreeMap<Quantity, Vec<f64>>) -> Self {
        let rows = channels.values().map(Vec::len).max().unwrap_or(0);
        Record {
            name: name.into(),
            source: source.into(),
            format: Format::Delimited,
            channels,
            constants: BTreeMap::new(),
            units: BTreeMap::new(),
            columns: BTreeMap::new(),
            lines: (2..rows + 2).collect(),
            meta: Vec::new(),
            warnings: Vec::new(),
            resolution: BTreeMap::new(),
            between: BTreeMap::new(),
        }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.lines.len()
    }

    /// A sampled quantity.
    pub fn channel(&self, q: Quantity) -> Option<&[f64]> {
        self.channels.get(&q).map(Vec::as_slice)
    }

    /// The time axis, if the record has one.
    pub fn time(&self) -> Option<&[f64]> {
        self.channel(Quantity::Time)
    }

    /// A quantity at row `i`: the sample if it is a column, else the constant.
    pub fn value_at(&self, q: Quantity, i: usize) -> Option<f64> {
        match self.channels.get(&q) {
            Some(v) => v.get(i).copied(),
            None => self.constants.get(&q).copied(),
        }
    }

    /// True when the record has `q` as a column or a constant.
    pub fn has(&self, q: Quantity) -> bool {
        self.channels.contains_key(&q) || self.constants.contains_key(&q)
    }
}

/// `path` as written in reports: relative to the configuration's folder `base` when inside it,
/// with forward slashes, so that results do not depend on where hydroid was started.
pub fn report_path(path: &Path, base: &Path) -> String {
    path.strip_prefix(base)
        .unwrap_or(path)
        .to_string_lossy()
        .replace('\\', "/")
}

/// Reads the file `spec` names (relative to `base`) and picks the quantities `needs` asks for.
pub fn load(spec: &InputSpec, base: &Path, needs: &Needs) -> Result<Record, InputError> {
    let path = base.join(&spec.file);
    let table = formats::read(&path, spec.format.0, &spec.read_options())?;
    from_table(table, spec, needs)
}

/// Picks the quantities `needs` asks for from an already read table.
pub fn from_table(mut table: Table, spec: &InputSpec, needs: &Needs) -> Result<Record, InputError> {
    let file_place = Place::file(&table.source);
    let mut constants = constants_of(spec, &file_place)?;
    // An attitude quaternion mapped in full stands for roll, pitch and yaw.
    let from_quaternion = attitude_from_quaternion(spec, &file_place)?;
    let skip = |q: Quantity| {
        constants.contains_key(&q)
            || spec.steps.iter().any(|s| s.values.contains_key(&q))
            || (from_quaternion && q.is_euler_angle())
    };
    let (picks, implicit_skipped) = pick_columns(&table, spec, needs, skip)?;

    // Time first: dedupe restarts and check order on the mapped time column.
    if let Some(&(_, t_idx, ref t_unit, _)) = picks.iter().find(|p| p.0 == Quantity::Time) {
        if let Some(u) = t_unit {
            rescale_column(&mut table, t_idx, u);
        }
        table.drop_repeated_times(t_idx, spec.dt.as_ref().map(|c| c.si))?;
    }
    let time_history = picks.iter().any(|p| p.0 == Quantity::Time);
    let mut read = read_channels(&mut table, &picks, time_history)?;
    if from_quaternion {
        euler_from_quaternion(&table, time_history, &mut read.channels, &mut read.units)?;
        for q in Quantity::QUATERNION {
            read.columns.remove(&q);
        }
    }
    check_rows_and_time(&table, &read.channels, needs, &file_place)?;

    // quantities given as steps: sampled at the time stamps, as if the file had a column
    let time = read.channels.get(&Quantity::Time).map(Vec::as_slice);
    let sampled = crate::io::steps::sampled_steps(spec, time)
        .map_err(|m| InputError::new(file_place.clone(), m))?;
    for (q, values) in sampled {
        constants.remove(&q);
        read.units.insert(q, q.si_symbol().to_string());
        read.channels.insert(q, values);
    }

    let mut warnings = table.warnings.clone();
    warnings.extend(implicit_skipped);
    if let Some(froude) = &spec.froude {
        froude_scale(froude, &mut read, &mut constants);
        warnings.push(froude.describe());
    }
    warnings.extend(to_body_frame(spec, &table, &mut read, &constants)?);

    Ok(Record {
        name: spec.display_name(),
        source: table.source.clone(),
        format: table.format,
        channels: read.channels,
        constants,
        units: read.units,
        columns: read.columns,
        lines: table.lines.clone(),
        meta: table.meta.clone(),
        warnings,
        resolution: read.resolution,
        between: spec.between.clone(),
    })
}

/// A quantity read from a column: (quantity, column index, the column's unit if any, scale).
type Pick = (Quantity, usize, Option<Unit>, f64);

/// The channels read from the picked columns, with what the record says about each.
struct ReadChannels {
    channels: BTreeMap<Quantity, Vec<f64>>,
    units: BTreeMap<Quantity, String>,
    columns: BTreeMap<Quantity, ColumnOrigin>,
    resolution: BTreeMap<Quantity, Vec<f64>>,
}

/// The input's constants in hydroid's internal units; a quantity both a constant and a
/// column is an error naming the file.
fn constants_of(spec: &InputSpec, place: &Place) -> Result<BTreeMap<Quantity, f64>, InputError> {
    let mut constants = BTreeMap::new();
    for (q, c) in &spec.constants {
        if spec.columns.contains_key(q) {
            return Err(InputError::new(
                place.clone(),
                format!("{q} is given both as a column and as a constant"),
            ));
        }
        constants.insert(*q, c.si / q.internal_unit().factor);
    }
    Ok(constants)
}

/// Resolves every wanted quantity (required, optional, then every mapped one) to a column:
/// the explicit map first, then by name; `skip` says which are given otherwise (constants,
/// steps, Euler angles from a quaternion). Returns the picks and a note for each column found
/// by name but left out because nothing gives its unit.
fn pick_columns(
    table: &Table,
    spec: &InputSpec,
    needs: &Needs,
    skip: impl Fn(Quantity) -> bool,
) -> Result<(Vec<Pick>, Vec<String>), InputError> {
    let mut picks: Vec<Pick> = Vec::new();
    let mut implicit_skipped = Vec::new();
    let wanted = needs.required.iter().chain(needs.optional).copied();
    let mut seen = Vec::new();
    for q in wanted.chain(spec.columns.keys().copied()) {
        if seen.contains(&q) || skip(q) {
            continue;
        }
        seen.push(q);
        let (idx, unit_text, scale) = match spec.columns.get(&q) {
            Some(cs) => mapped_column(table, q, cs)?,
            None => match implicit_column(table, q) {
                Some(i) => (i, None, 1.0),
                None if needs.required.contains(&q) => {
                    return Err(missing_column(table, q, "not mapped", None));
                }
                None => continue,
            },
        };
        let unit = match column_unit(table, idx, q, unit_text.as_deref()) {
            Ok(u) => u,
            // a column found only by its name, for a quantity the run can do without, whose
            // unit nothing gives: left out with a note rather than stopping the run
            Err(_) if !spec.columns.contains_key(&q) && !needs.required.contains(&q) => {
                implicit_skipped.push(format!(
                    "column '{}' was not used for {q}: it is not in the column map and the \
                     header gives no unit (map it with a unit to use it)",
                    table.columns[idx].name
                ));
                continue;
            }
            Err(e) => return Err(e),
        };
        picks.push((q, idx, unit, scale));
    }
    Ok((picks, implicit_skipped))
}

/// The column the map gives for `q` (by name or 1-based number), with the map's unit text
/// and scale.
fn mapped_column(
    table: &Table,
    q: Quantity,
    cs: &ColumnSpec,
) -> Result<(usize, Option<String>, f64), InputError> {
    let file_place = || Place::file(&table.source);
    let idx = match (&cs.column, cs.index) {
        (Some(name), _) => table
            .column_index(name)
            .ok_or_else(|| missing_column(table, q, &format!("'{name}'"), Some(name)))?,
        (None, Some(i)) if i >= 1 && i <= table.columns.len() => i - 1,
        (None, Some(i)) => {
            return Err(InputError::new(
                file_place(),
                format!(
                    "{q} is mapped to column number {i}, but the file has {} columns",
                    table.columns.len()
                ),
            ))
        }
        (None, None) => {
            return Err(InputError::new(
                file_place(),
                format!("the column map for {q} gives neither `column` nor `index`"),
            ))
        }
    };
    Ok((idx, cs.unit.clone(), cs.scale.unwrap_or(1.0)))
}

/// Reads the picked columns into channels in hydroid's internal units (the printed
/// resolution of each kept, converted alike); a missing or non-finite value is an error
/// naming its row and column. Attitude angles of a time history are unwrapped.
fn read_channels(
    table: &mut Table,
    picks: &[Pick],
    time_history: bool,
) -> Result<ReadChannels, InputError> {
    let mut read = ReadChannels {
        channels: BTreeMap::new(),
        units: BTreeMap::new(),
        columns: BTreeMap::new(),
        resolution: BTreeMap::new(),
    };
    for (q, idx, unit, scale) in picks {
        if *q != Quantity::Time {
            // the digits as printed, before any conversion
            if let Some(res) =
                crate::numerics::printed::coarse_resolutions(&table.columns[*idx].values)
            {
                let header = table.columns[*idx].unit.as_ref().map_or(1.0, |u| u.factor);
                let f = unit.as_ref().map_or(header, |u| u.factor) / q.internal_unit().factor
                    * scale.abs();
                let res = res.into_iter().map(|r| r * f).collect::<Vec<f64>>();
                read.resolution.insert(*q, res);
            }
            if let Some(u) = unit {
                rescale_column(table, *idx, u);
            }
        }
        let col = &table.columns[*idx];
        let internal = q.internal_unit().factor;
        let mut values: Vec<f64> = col.values.iter().map(|v| v / internal * scale).collect();
        if let Some(row) = values.iter().position(|v| !v.is_finite()) {
            let missing = table.missing.iter().any(|&(r, c)| r == row && c == *idx);
            return Err(InputError::new(
                table
                    .place(row)
                    .with_column(*idx + 1)
                    .with_column_name(col.name.clone()),
                if missing {
                    format!("missing or non-numeric value for {q}")
                } else {
                    format!("non-finite value ({}) for {q}", values[row])
                },
            )
            .expected("a finite number"));
        }
        unwrap_attitude(*q, time_history, &mut values);
        let origin = ColumnOrigin {
            name: col.name.clone(),
            number: *idx + 1,
            scale: *scale,
        };
        read.columns.insert(*q, origin);
        let unit = unit
            .as_ref()
            .map_or_else(|| q.si_symbol().to_string(), |u| u.to_string());
        read.units.insert(*q, unit);
        read.channels.insert(*q, values);
    }
    Ok(read)
}

/// At least the rows the stage needs, and a time that increases.
fn check_rows_and_time(
    table: &Table,
    channels: &BTreeMap<Quantity, Vec<f64>>,
    needs: &Needs,
    file_place: &Place,
) -> Result<(), InputError> {
    let rows = table.rows();
    if rows < needs.min_rows {
        return Err(InputError::new(
            file_place.clone(),
            format!(
                "only {rows} data row{} after the header",
                if rows == 1 { "" } else { "s" }
            ),
        )
        .expected(format!("at least {} rows", needs.min_rows)));
    }
    if let Some(t) = channels.get(&Quantity::Time) {
        if let Some(i) = (1..t.len()).find(|&i| t[i] <= t[i - 1]) {
            return Err(InputError::new(
                table.place(i),
                format!("time does not increase ({} then {})", t[i - 1], t[i]),
            ));
        }
    }
    Ok(())
}

/// Froude-scales every channel, constant and resolution of a model-scale run to full scale.
fn froude_scale(
    froude: &crate::io::froude::Froude,
    read: &mut ReadChannels,
    constants: &mut BTreeMap<Quantity, f64>,
) {
    for (q, values) in &mut read.channels {
        let f = froude.factor(*q);
        values.iter_mut().for_each(|v| *v *= f);
    }
    for (q, v) in constants.iter_mut() {
        *v *= froude.factor(*q);
    }
    for (q, values) in &mut read.resolution {
        let f = froude.factor(*q).abs();
        values.iter_mut().for_each(|v: &mut f64| *v *= f);
    }
}

/// Rotates earth-frame velocities and/or rates into the body frame as the input says;
/// returns the note saying what was rotated (none when nothing was).
fn to_body_frame(
    spec: &InputSpec,
    table: &Table,
    read: &mut ReadChannels,
    constants: &BTreeMap<Quantity, f64>,
) -> Result<Option<String>, InputError> {
    use crate::numerics::frames;
    let groups = frames::Groups {
        linear: spec.velocity_frame == VelocityFrame::Earth,
        angular: spec.rate_frame.unwrap_or(spec.velocity_frame) == VelocityFrame::Earth,
    };
    if !(groups.linear || groups.angular) {
        return Ok(None);
    }
    frames::rotate_resolution(&read.channels, constants, &mut read.resolution, groups);
    frames::rotate_to_body(&mut read.channels, constants, &table.source, groups)?;
    let note = match (groups.linear, groups.angular) {
        (true, true) => "velocities rotated from the earth frame into the body frame",
        (true, false) => {
            "velocities rotated from the earth frame into the body frame; rates read \
             as body rates (rate_frame = \"body\")"
        }
        _ => "rates rotated from the earth frame into the body frame",
    };
    Ok(Some(note.into()))
}

/// Whether the column map gives the attitude as a quaternion: all four parts mapped, and no
/// Euler angle given as well; a partial map or both forms is an error naming the file.
fn attitude_from_quaternion(spec: &InputSpec, place: &Place) -> Result<bool, InputError> {
    let mapped: Vec<Quantity> = Quantity::QUATERNION
        .into_iter()
        .filter(|q| spec.columns.contains_key(q))
        .collect();
    if mapped.is_empty() {
        return Ok(false);
    }
    if mapped.len() < 4 {
        let missing: Vec<&str> = Quantity::QUATERNION
            .iter()
            .filter(|q| !mapped.contains(q))
            .map(|q| q.key())
            .collect();
        return Err(InputError::new(
            place.clone(),
            format!(
                "the attitude quaternion needs all four parts in the column map; missing: {}",
                missing.join(", ")
            ),
        )
        .expected("quat_w, quat_x, quat_y and quat_z (scalar part first)"));
    }
    let euler = [Quantity::Roll, Quantity::Pitch, Quantity::Yaw];
    if let Some(q) = euler
        .into_iter()
        .find(|q| spec.columns.contains_key(q) || spec.constants.contains_key(q))
    {
        return Err(InputError::new(
            place.clone(),
            format!("{q} is given both as a column and through the attitude quaternion: keep one"),
        ));
    }
    Ok(true)
}

/// Replaces the four quaternion channels by roll, pitch and yaw (zyx, Fossen 2011 section
/// 2.2.3), unwrapped like read angles. A row whose quaternion is not of unit norm (within
/// [`crate::numerics::frames::QUATERNION_NORM_TOLERANCE`]) is an error naming its line.
fn euler_from_quaternion(
    table: &Table,
    time_history: bool,
    channels: &mut BTreeMap<Quantity, Vec<f64>>,
    units: &mut BTreeMap<Quantity, String>,
) -> Result<(), InputError> {
    let parts = Quantity::QUATERNION.map(|q| {
        units.remove(&q);
        channels.remove(&q).unwrap_or_default()
    });
    let n = parts[0].len();
    let mut angles = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    for i in 0..n {
        let q = [parts[0][i], parts[1][i], parts[2][i], parts[3][i]];
        let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        if (norm - 1.0).abs() > crate::numerics::frames::QUATERNION_NORM_TOLERANCE {
            return Err(InputError::new(
                table.place(i),
                format!("the attitude quaternion has norm {norm:.6}, not 1"),
            )
            .expected("a unit quaternion (quat_w, quat_x, quat_y, quat_z)"));
        }
        let (phi, theta, psi) = crate::numerics::frames::zyx_from_quaternion(q.map(|v| v / norm));
        angles[0][i] = phi;
        angles[1][i] = theta;
        angles[2][i] = psi;
    }
    let [roll, pitch, yaw] = angles;
    for (q, mut values) in [
        (Quantity::Roll, roll),
        (Quantity::Pitch, pitch),
        (Quantity::Yaw, yaw),
    ] {
        unwrap_attitude(q, time_history, &mut values);
        units.insert(q, "rad (from the quaternion)".into());
        channels.insert(q, values);
    }
    Ok(())
}

/// A column named exactly like the quantity key (or the table's declared time column).
fn implicit_column(table: &Table, q: Quantity) -> Option<usize> {
    if q == Quantity::Time {
        if let Some(t) = table.time {
            return Some(t);
        }
    }
    table
        .columns
        .iter()
        .position(|c| c.name.eq_ignore_ascii_case(q.key()))
}

fn missing_column(table: &Table, q: Quantity, how: &str, asked: Option<&str>) -> InputError {
    let names = table.names();
    let hint = asked
        .or(Some(q.key()))
        .and_then(|a| crate::base::suggest::nearest(a, names.iter().copied()))
        .map(|c| format!("; closest: '{c}'"))
        .unwrap_or_default();
    InputError::new(
        Place::file(&table.source),
        format!(
            "no column for {q} ({how}); the file has columns: {}{hint}",
            names
                .iter()
                .map(|n| format!("'{n}'"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    )
    .expected(format!(
        "a column map entry such as `{q} = \"<column name>\"`"
    ))
}

/// The unit of column `idx` for quantity `q`: the configured one, else the header's.
fn column_unit(
    table: &Table,
    idx: usize,
    q: Quantity,
    configured: Option<&str>,
) -> Result<Option<Unit>, InputError> {
    let col = &table.columns[idx];
    let place = || {
        Place::file(&table.source)
            .with_column(idx + 1)
            .with_column_name(col.name.clone())
    };
    let unit = match configured {
        Some(text) => Some(Unit::parse(text).map_err(|e| InputError::new(place(), e.to_string()))?),
        None => col.unit.clone(),
    }
    .map(|u| q.column_unit(u));
    match &unit {
        None if q.dim() != crate::base::units::DIMENSIONLESS => {
            return Err(
                InputError::new(place(), format!("the header gives no unit for {q}")).expected(
                    format!(
                "a unit in the configuration, e.g. `{q} = {{ column = \"{}\", unit = \"{}\" }}`",
                col.name,
                q.si_symbol()
            ),
                ),
            )
        }
        Some(u) if u.dim != q.dim() => {
            return Err(InputError::new(
                place(),
                format!("unit '{u}' ({}) does not fit {q}", dim_to_string(u.dim)),
            )
            .expected(format!("a unit of {}", dim_to_string(q.dim()))))
        }
        _ => {}
    }
    Ok(unit)
}

/// Makes column `idx` hold `unit`-converted SI values, undoing the header's conversion when
/// the configuration overrides the header unit.
fn rescale_column(table: &mut Table, idx: usize, unit: &Unit) {
    let col = &mut table.columns[idx];
    let header_factor = col.unit.as_ref().map_or(1.0, |u| u.factor);
    let f = unit.factor / header_factor;
    if f != 1.0 {
        for v in &mut col.values {
            *v *= f;
        }
    }
    col.unit = Some(unit.clone());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::input_spec::ColumnSpec;
    use crate::io::table::Column;

    fn spec(cols: &[(Quantity, ColumnSpec)]) -> InputSpec {
        InputSpec {
            name: None,
            file: "run.csv".into(),
            format: Default::default(),
            names: None,
            skip_lines: None,
            dt: None,
            froude: None,
            columns: cols.iter().cloned().collect(),
            constants: BTreeMap::new(),
            steps: Vec::new(),
            between: BTreeMap::new(),
            velocity_frame: VelocityFrame::Body,
            rate_frame: None,
            manoeuvre: None,
            source: None,
        }
    }

    fn table() -> Table {
        let mut t = Table::new("run.csv", Format::Delimited);
        let mut time = Column::new("Time", vec![0.0, 0.1, 0.2]);
        time.unit = Some(Unit::parse("s").unwrap());
        t.columns.push(time);
        t.columns
            .push(Column::new("Heading", vec![179.0, -179.0, -178.0]));
        let mut u = Column::new("Velocity u", vec![1.0, 1.1, 1.2]);
        u.unit = Some(Unit::parse("m/s").unwrap());
        t.columns.push(u);
        t.lines = vec![3, 4, 5];
        t.time = Some(0);
        t
    }

    const NEEDS: Needs = Needs {
        required: &[Quantity::Time, Quantity::U, Quantity::Yaw],
        optional: &[Quantity::V],
        min_rows: 2,
    };

    #[test]
    fn maps_converts_and_unwraps() {
        let s = spec(&[
            (Quantity::U, ColumnSpec::named("Velocity u")),
            (
                Quantity::Yaw,
                ColumnSpec {
                    unit: Some("deg".into()),
                    ..ColumnSpec::named("Heading")
                },
            ),
        ]);
        let r = from_table(table(), &s, &NEEDS).unwrap();
        let yaw = r.channel(Quantity::Yaw).unwrap();
        assert!((yaw[1].to_degrees() - 181.0).abs() < 1e-9);
        assert_eq!(r.channel(Quantity::U).unwrap(), &[1.0, 1.1, 1.2]);
        assert_eq!(r.units[&Quantity::Yaw], "deg");
        assert!(!r.has(Quantity::V));
    }

    #[test]
    fn missing_unit_is_an_error_naming_the_column() {
        let s = spec(&[
            (Quantity::U, ColumnSpec::named("Velocity u")),
            (Quantity::Yaw, ColumnSpec::named("Heading")),
        ]);
        let e = from_table(table(), &s, &NEEDS).unwrap_err();
        assert_eq!(e.place.column_name.as_deref(), Some("Heading"));
        assert!(e.to_string().contains("no unit"), "{e}");
    }

    #[test]
    fn missing_column_lists_the_columns_and_the_closest() {
        let s = spec(&[
            (Quantity::U, ColumnSpec::named("Velocity U ")),
            (Quantity::Yaw, ColumnSpec::named("Headng")),
        ]);
        let e = from_table(table(), &s, &NEEDS).unwrap_err().to_string();
        assert!(
            e.contains("'Velocity u'") && e.contains("closest: 'Heading'"),
            "{e}"
        );
    }

    #[test]
    fn wrong_dimension_is_an_error() {
        let s = spec(&[
            (
                Quantity::U,
                ColumnSpec {
                    unit: Some("deg".into()),
                    ..ColumnSpec::named("Velocity u")
                },
            ),
            (Quantity::Yaw, ColumnSpec::named("Heading")),
        ]);
        let e = from_table(table(), &s, &NEEDS).unwrap_err().to_string();
        assert!(e.contains("does not fit u"), "{e}");
    }

    #[test]
    fn earth_velocities_rotate_into_the_body_frame() {
        let mut t = table();
        t.columns[1].values = vec![90.0, 90.0, 90.0];
        let mut s = spec(&[
            (Quantity::U, ColumnSpec::named("Velocity u")),
            (
                Quantity::Yaw,
                ColumnSpec {
                    unit: Some("deg".into()),
                    ..ColumnSpec::named("Heading")
                },
            ),
        ]);
        s.velocity_frame = VelocityFrame::Earth;
        let needs = Needs {
            required: &[Quantity::U, Quantity::Yaw],
            optional: &[Quantity::V],
            min_rows: 1,
        };
        let r = from_table(t, &s, &needs).unwrap();
        // heading east, earth velocity north 1 m/s: body u = 0, v = -1
        assert!(r.channel(Quantity::U).unwrap()[0].abs() < 1e-12);
        assert!((r.channel(Quantity::V).unwrap()[0] + 1.0).abs() < 1e-12);
    }
}
