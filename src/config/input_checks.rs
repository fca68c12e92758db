//! The configuration's checks of an input specification ([`InputSpec`]) and of a run's
//! nominal manoeuvre angles ([`ManoeuvreSpec`]): the types live in `io::input_spec`, their
//! validation with the rest of the configuration's.

use super::Problems;
use crate::base::units::{check_dim, Unit};
use crate::io::input_spec::{
    InputSpec, ManoeuvreSpec, MAX_COLUMN_INDEX, MAX_NOMINAL_ANGLE_DEG, MAX_RUN_NAME_CHARS,
    MAX_SKIP_LINES,
};

impl InputSpec {
    /// Adds every problem with this input (at key path `key`, e.g. `hekf.runs[0]`) to `p`,
    /// except whether its file exists: a name of at most [`MAX_RUN_NAME_CHARS`] characters,
    /// constants finite and of their quantity's dimension, column units known and of their
    /// quantity's dimension, column numbers from 1, scales finite and not zero, names listed
    /// once, no quantity both a column and a constant.
    pub fn validate(&self, key: &str, p: &mut Problems) {
        if self.file.as_os_str().is_empty() {
            p.add(&format!("{key}.file"), "is empty; name the export to read");
        }
        if let Some(n) = self.name.as_ref().map(|n| n.chars().count()) {
            if n > MAX_RUN_NAME_CHARS {
                p.add(
                    &format!("{key}.name"),
                    format!(
                        "is {n} characters long, more than the {MAX_RUN_NAME_CHARS} a run name \
                         may have (it labels the run in the report and, for an HEKF run, names \
                         its file in the output, states/NAME.csv, which a file system limits \
                         to 255 bytes): shorten it"
                    ),
                );
            }
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
    fn validate_constants(&self, key: &str, p: &mut Problems) {
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
    fn validate_columns(&self, key: &str, p: &mut Problems) {
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
    fn validate_reading(&self, key: &str, p: &mut Problems) {
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
}

impl ManoeuvreSpec {
    /// Adds every problem with the angles (at key path `key`, e.g.
    /// `hekf.runs[0].manoeuvre`) to `p`: each an angle, not zero, at most
    /// [`MAX_NOMINAL_ANGLE_DEG`].
    pub(crate) fn validate(&self, key: &str, p: &mut Problems) {
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
                        crate::base::numfmt::num(deg)
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
