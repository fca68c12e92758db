//! Estimates against their truth (issue 28, item 2): per coefficient z = (estimate - truth) /
//! sigma, whether the run determines it (sigma below half of |truth|) and whether hydroid
//! flags it as undetermined. Accuracy counts ("within 2 sigma") take only the determined
//! coefficients; the others are asserted to be flagged instead, so that a coefficient whose
//! sigma is as large as its value cannot pass a 2-sigma check with the wrong sign.
//!
//! Shared by the twin tests (`common::accuracy`) and the independent-generator tests
//! (tests/independent/accuracy.rs includes this file).

/// One estimated coefficient against its truth.
#[derive(Debug, Clone)]
pub struct Row {
    pub name: String,
    pub truth: f64,
    pub estimate: f64,
    pub sigma: f64,
    /// (estimate - truth) / sigma.
    pub z: f64,
    /// The run determines it: sigma below half of |truth| (a coefficient whose truth is 0
    /// counts as determined: its z is still a test).
    pub determined: bool,
    /// hydroid names it among the estimates the runs leave undetermined or correlated
    /// (its identifiability advice).
    pub flagged: bool,
}

impl Row {
    /// The row of `name`, its z and whether it is determined computed from the others.
    pub fn new(name: &str, truth: f64, estimate: f64, sigma: f64, flagged: bool) -> Row {
        Row {
            name: name.to_string(),
            truth,
            estimate,
            sigma,
            z: (estimate - truth) / sigma,
            determined: truth == 0.0 || sigma < 0.5 * truth.abs(),
            flagged,
        }
    }

    /// 100 (estimate - truth) / truth (NaN for a zero truth).
    pub fn error_percent(&self) -> f64 {
        if self.truth == 0.0 {
            f64::NAN
        } else {
            100.0 * (self.estimate - self.truth) / self.truth
        }
    }
}

/// The estimates of one run against their truth.
#[derive(Debug, Clone)]
pub struct Accuracy {
    /// A heading for the table.
    pub title: String,
    pub rows: Vec<Row>,
}

impl Accuracy {
    /// The coefficients of `list` (a results.json `coefficients` array: `name`, `value`,
    /// `sigma`) named in `truth`, each flagged when `flagged` names it.
    pub fn from_json(
        title: &str,
        list: &serde_json::Value,
        truth: &[(&str, f64)],
        flagged: &[String],
    ) -> Accuracy {
        let rows = truth
            .iter()
            .map(|&(name, t)| {
                let c = list
                    .as_array()
                    .and_then(|l| l.iter().find(|c| c["name"] == name))
                    .unwrap_or_else(|| panic!("{name} is not in {list}"));
                let value = c["value"].as_f64().unwrap();
                let sigma = c["sigma"]
                    .as_f64()
                    .unwrap_or_else(|| panic!("{name} has no sigma: {c}"));
                Row::new(name, t, value, sigma, flagged.iter().any(|f| f == name))
            })
            .collect();
        Accuracy {
            title: title.to_string(),
            rows,
        }
    }

    /// The HEKF estimates of a results.json against `truth`, flagged as its identifiability
    /// advice (`stages.hekf.identifiability`) names them.
    pub fn of_hekf(title: &str, results: &serde_json::Value, truth: &[(&str, f64)]) -> Accuracy {
        Accuracy::from_json(
            title,
            &results["coefficients"],
            truth,
            &hekf_flagged(results),
        )
    }

    /// The estimates of an HEKF stage's result (in memory) against `truth` (the truth of a
    /// coefficient by name), flagged as its identifiability advice names them.
    pub fn of_hekf_result(
        title: &str,
        h: &hydroid::stages::hekf::HekfResult,
        truth: impl Fn(&str) -> f64,
    ) -> Accuracy {
        let rows = h
            .coefficients
            .iter()
            .map(|c| {
                let flagged = h.identifiability.iter().any(|a| a.coefficient == c.name);
                let sigma = c.sigma.expect("a sigma");
                Row::new(&c.name, truth(&c.name), c.value, sigma, flagged)
            })
            .collect();
        Accuracy {
            title: title.to_string(),
            rows,
        }
    }

    /// The row of `name`.
    pub fn row(&self, name: &str) -> &Row {
        self.rows
            .iter()
            .find(|r| r.name == name)
            .unwrap_or_else(|| panic!("{name} was not estimated"))
    }

    /// The determined coefficients.
    pub fn determined(&self) -> impl Iterator<Item = &Row> {
        self.rows.iter().filter(|r| r.determined)
    }

    /// How many determined coefficients lie within 2 sigma, of how many determined.
    pub fn within_two_sigma(&self) -> (usize, usize) {
        let d: Vec<&Row> = self.determined().collect();
        (d.iter().filter(|r| r.z.abs() <= 2.0).count(), d.len())
    }

    /// The undetermined coefficients.
    pub fn undetermined(&self) -> Vec<&Row> {
        self.rows.iter().filter(|r| !r.determined).collect()
    }

    /// The names of the undetermined coefficients.
    pub fn undetermined_names(&self) -> Vec<&str> {
        self.undetermined()
            .iter()
            .map(|r| r.name.as_str())
            .collect()
    }

    /// The largest |z| of the determined coefficients.
    pub fn worst_z(&self) -> f64 {
        self.determined().map(|r| r.z.abs()).fold(0.0, f64::max)
    }

    /// The largest |error| in percent of the determined coefficients with a non-zero truth.
    pub fn worst_error_percent(&self) -> f64 {
        self.determined()
            .filter(|r| r.truth != 0.0)
            .map(|r| r.error_percent().abs())
            .fold(0.0, f64::max)
    }

    /// The table, one line per coefficient.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{}\n{:>8} {:>14} {:>14} {:>10} {:>8} {:>7}  note\n",
            self.title, "coef", "truth", "estimate", "sigma", "error %", "z"
        );
        for r in &self.rows {
            s.push_str(&format!(
                "{:>8} {:>14.6e} {:>14.6e} {:>10.3e} {:>+8.3} {:>+7.2}  {}{}\n",
                r.name,
                r.truth,
                r.estimate,
                r.sigma,
                r.error_percent(),
                r.z,
                if r.determined { "" } else { "undetermined" },
                if r.flagged {
                    " (flagged by hydroid)"
                } else {
                    ""
                }
            ));
        }
        let (k, n) = self.within_two_sigma();
        s.push_str(&format!(
            "determined: {n} of {}, within 2 sigma: {k} of {n}, worst |z| {:.2}\n",
            self.rows.len(),
            self.worst_z()
        ));
        s
    }

    /// Asserts that every undetermined coefficient is flagged by hydroid.
    #[track_caller]
    pub fn assert_undetermined_flagged(&self) {
        for r in self.undetermined() {
            assert!(
                r.flagged,
                "{} is undetermined (sigma {:.2e} against {:.2e}) but hydroid does not flag it\n{}",
                r.name,
                r.sigma,
                r.truth,
                self.table()
            );
        }
    }

    /// Asserts the determined and undetermined sets (`undetermined` names the latter, in
    /// any order), that every undetermined one is flagged, and that every determined one
    /// lies within `z_max` sigma of its truth.
    #[track_caller]
    pub fn assert_determined_within(&self, undetermined: &[&str], z_max: f64) {
        let mut got = self.undetermined_names();
        got.sort_unstable();
        let mut want = undetermined.to_vec();
        want.sort_unstable();
        assert_eq!(got, want, "undetermined\n{}", self.table());
        self.assert_undetermined_flagged();
        for r in self.determined() {
            assert!(
                r.z.abs() <= z_max,
                "{} is {:+.2} sigma from its truth (at most {z_max})\n{}",
                r.name,
                r.z,
                self.table()
            );
        }
    }
}

/// `x` printed with the digits of `shown` ("-0.05013", "8.364e-4"): as many decimals (of the
/// mantissa, for a number in e-notation), the sign as `shown` gives it ("+0.2").
pub fn printed_as(x: f64, shown: &str) -> String {
    let (mantissa, exponent) = match shown.split_once('e') {
        Some((m, _)) => (m, true),
        None => (shown, false),
    };
    let d = mantissa.split_once('.').map_or(0, |(_, f)| f.len());
    match (exponent, shown.starts_with('+')) {
        (true, _) => format!("{x:.d$e}"),
        (false, true) => format!("{x:+.d$}"),
        (false, false) => format!("{x:.d$}"),
    }
}

impl Accuracy {
    /// The row of `name` as a docs table prints it, at the digits of `like`: "value ± sigma",
    /// or "value ± sigma | column" with the error in percent ("0.25 %", of its size) or z
    /// ("+0.2") as the column.
    pub fn printed_row(&self, name: &str, like: &str) -> String {
        let r = self.row(name);
        let (estimate, rest) = like.split_once(" ± ").expect("value ± sigma");
        let (sigma, column) = match rest.split_once(" | ") {
            Some((sigma, column)) => (sigma, Some(column)),
            None => (rest, None),
        };
        let shown = format!(
            "{} ± {}",
            printed_as(r.estimate, estimate),
            printed_as(r.sigma, sigma)
        );
        match column.map(|c| (c, c.strip_suffix(" %"))) {
            None => shown,
            Some((_, Some(e))) => {
                format!("{shown} | {} %", printed_as(r.error_percent().abs(), e))
            }
            Some((z, None)) => format!("{shown} | {}", printed_as(r.z, z)),
        }
    }

    /// Asserts that a docs table's rows, (name, "value ± sigma | column" as
    /// [`Accuracy::printed_row`] reads it), are what this run gives at their digits; the
    /// failure lists every row as this run prints it.
    #[track_caller]
    pub fn assert_printed(&self, rows: &[(&str, &str)]) {
        let got: Vec<(&str, String)> = rows
            .iter()
            .map(|(name, like)| (*name, self.printed_row(name, like)))
            .collect();
        let want: Vec<(&str, String)> = rows.iter().map(|(n, l)| (*n, l.to_string())).collect();
        assert_eq!(
            got,
            want,
            "the docs table (right) against this run (left)\n{}",
            self.table()
        );
    }
}

/// The coefficients whose row of a results.json's comparison table carries a flag (sigma
/// above 10 % of the value, a correlation above 0.9; docs/results.md, `flags`): how the
/// final coefficients of a run without an HEKF stage are flagged.
pub fn comparison_flagged(results: &serde_json::Value) -> Vec<String> {
    results["comparison"]
        .as_array()
        .expect("a comparison table")
        .iter()
        .filter(|c| c["flags"].as_array().is_some_and(|f| !f.is_empty()))
        .map(|c| c["name"].as_str().unwrap().to_string())
        .collect()
}

/// The coefficients the HEKF's identifiability advice of a results.json names
/// (`stages.hekf.identifiability[].coefficient`; absent when every estimate is determined).
pub fn hekf_flagged(results: &serde_json::Value) -> Vec<String> {
    results["stages"]["hekf"]["identifiability"]
        .as_array()
        .map(|advice| {
            advice
                .iter()
                .map(|a| a["coefficient"].as_str().unwrap().to_string())
                .collect()
        })
        .unwrap_or_default()
}
