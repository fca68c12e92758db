//! Hydrodynamic coefficients: the coefficient set every stage fills in and the geometric
//! symmetry relations of the spheroid paper (eq. 4). What each coefficient means and its unit
//! is said by the models that use it ([`crate::model::models::registry::all_coefficients`]).
//!
//! Names are SNAME symbols written in ASCII: `Xud` = X_udot, `Nrr` = N_r|r|,
//! `Yuvl` = lift part of Y_uv, `Nuva` = Munk (added-mass) part of N_uv.

mod conflict;
mod relations;
mod uncertainty;

pub use conflict::Conflict;

pub use relations::{CompiledRelations, Relation, YawMoment, AXISYMMETRY, SYMMETRY};
pub use uncertainty::{directions_of, Correlation, Direction};

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// Relative standard deviation above which a coefficient is flagged as uncertain.
pub const UNCERTAIN: f64 = 0.1;

/// Correlation above which two estimates are flagged as not separately identifiable.
pub const CORRELATED: f64 = 0.9;

/// Where a coefficient value came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum Source {
    /// Static polar fit (paper eq. 5).
    Polar,
    /// Surge acceleration run (paper eq. 21).
    Surge,
    /// Steady captive runs (static drift, drift with rudder, circular motion).
    Captive,
    /// Hybrid EKF on motion histories (paper eq. 9-19).
    Hekf,
    /// A symmetry relation (paper eq. 4).
    Symmetry,
    /// Fossen's analytic added mass (Lamb's k-factors).
    Analytic,
    /// Given in the configuration.
    Config,
}

impl fmt::Display for Source {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            Source::Polar => "polar",
            Source::Surge => "surge",
            Source::Captive => "captive",
            Source::Hekf => "hekf",
            Source::Symmetry => "symmetry",
            Source::Analytic => "analytic",
            Source::Config => "config",
        };
        f.write_str(s)
    }
}

/// One coefficient with its uncertainty and provenance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Coefficient {
    /// ASCII SNAME name.
    pub name: String,
    /// Value in SI.
    pub value: f64,
    /// One standard deviation, when known.
    pub sigma: Option<f64>,
    /// SI unit.
    pub unit: String,
    /// Where the value came from.
    pub source: Source,
    /// How it was obtained, e.g. the relation used.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub note: Option<String>,
}

impl Coefficient {
    /// A coefficient with the catalogue unit of `name` (or `-` when unknown).
    pub fn new(name: &str, value: f64, sigma: Option<f64>, source: Source) -> Self {
        Coefficient {
            name: name.to_string(),
            value,
            sigma,
            unit: crate::model::models::registry::coefficient(name)
                .map_or("-", |i| i.unit)
                .to_string(),
            source,
            note: None,
        }
    }

    /// Adds a note.
    pub fn with_note(mut self, note: impl Into<String>) -> Self {
        self.note = Some(note.into());
        self
    }

    /// Marks the coefficient as held by a constraint of its fit (`why`, e.g. `b = 0
    /// (polar.drag.symmetric)`): its value is imposed, not estimated, so it has no sigma (a
    /// sigma of 0 would read as exactly measured) and its note says so ([`HELD`]).
    pub fn held(mut self, why: &str) -> Self {
        self.sigma = None;
        let note = self
            .note
            .take()
            .map(|n| format!("{n}; "))
            .unwrap_or_default();
        self.note = Some(format!("{note}{HELD}: {why}"));
        self
    }

    /// True for a coefficient a constraint of its fit holds ([`Coefficient::held`]).
    pub fn is_held(&self) -> bool {
        self.sigma.is_none() && self.note.as_deref().is_some_and(|n| n.contains(HELD))
    }
}

/// The words that mark a coefficient held by a constraint, not estimated
/// ([`Coefficient::held`]); the comparison table shows such a value as `0 (held)`.
pub const HELD: &str = "held by a constraint, not estimated";

/// The coefficients known so far, each with value, sigma, unit and source.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CoefficientSet {
    coefficients: BTreeMap<String, Coefficient>,
    /// Correlations between the coefficients estimated together (the HEKF's): what the data
    /// of one run can and cannot separate.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub correlation: Option<Correlation>,
    /// Independent sources of uncertainty and what each changes.
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub directions: Vec<Direction>,
}

impl CoefficientSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds or replaces a coefficient.
    pub fn insert(&mut self, c: Coefficient) {
        self.coefficients.insert(c.name.clone(), c);
    }

    /// Looks a coefficient up.
    pub fn get(&self, name: &str) -> Option<&Coefficient> {
        self.coefficients.get(name)
    }

    /// The value of a coefficient.
    pub fn value(&self, name: &str) -> Option<f64> {
        self.get(name).map(|c| c.value)
    }

    /// Whether the set holds `name`.
    pub fn contains(&self, name: &str) -> bool {
        self.coefficients.contains_key(name)
    }

    /// All coefficients, sorted by name.
    pub fn iter(&self) -> impl Iterator<Item = &Coefficient> {
        self.coefficients.values()
    }

    /// Number of coefficients.
    pub fn len(&self) -> usize {
        self.coefficients.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.coefficients.is_empty()
    }

    /// Applies `relations` in order wherever all terms are known, so that derived coefficients
    /// follow the ones they depend on. A derived value replaces any earlier value of its target
    /// (the relation is the definition), except that a target estimated by a stage directly is
    /// kept and reported in the returned list of conflicts. Standard deviations are propagated
    /// linearly along the uncertainty directions when those account for the terms' sigmas
    /// (the derived coefficient joins each direction), else with the correlation matrix where
    /// both terms are in it and as independent otherwise. Only the relations that hold in the
    /// yaw-moment reading `reading` apply.
    pub fn complete(&mut self, relations: &[Relation], reading: YawMoment) -> Vec<String> {
        let mut conflicts = Vec::new();
        for rel in relations.iter().filter(|r| r.holds_in(reading)) {
            let Some(terms) = rel
                .terms
                .iter()
                .map(|(f, n)| self.get(n).map(|c| (*f, c.clone())))
                .collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            let value: f64 = terms.iter().map(|(f, c)| f * c.value).sum();
            let by_directions = terms.iter().all(|(_, c)| self.covered(&c.name))
                && terms.iter().any(|(_, c)| c.sigma.is_some());
            let sigma = if by_directions {
                let mut var = 0.0;
                for d in &mut self.directions {
                    let delta: f64 = terms
                        .iter()
                        .map(|(f, c)| f * d.deltas.get(&c.name).copied().unwrap_or(0.0))
                        .sum();
                    if delta != 0.0 {
                        d.deltas.insert(rel.target.to_string(), delta);
                    }
                    var += delta * delta;
                }
                Some(var.sqrt())
            } else {
                self.combined_sigma(&terms)
            };
            if let Some(existing) = self.get(rel.target) {
                if matches!(
                    existing.source,
                    Source::Polar | Source::Surge | Source::Hekf
                ) {
                    if (existing.value - value).abs() > 1e-9 * value.abs().max(1.0) {
                        conflicts.push(format!(
                            "{} = {:.6} from the {} stage differs from {} = {:.6}; kept the \
                             stage's value",
                            rel.target, existing.value, existing.source, rel.cite, value
                        ));
                    }
                    continue;
                }
            }
            self.insert(
                Coefficient::new(rel.target, value, sigma, Source::Symmetry).with_note(rel.cite),
            );
        }
        conflicts
    }

    /// Adds a stage's coefficients and uncertainty directions, replacing any earlier value of
    /// the same coefficients (whose share in earlier directions no longer applies). A
    /// direction whose source is already in the set adds its changes to it (how the stage's
    /// estimates move along an upstream source of uncertainty); others are new sources.
    pub fn merge_stage(&mut self, coefficients: Vec<Coefficient>, directions: Vec<Direction>) {
        for c in coefficients {
            for d in &mut self.directions {
                d.deltas.remove(&c.name);
            }
            self.insert(c);
        }
        for d in directions {
            match self.directions.iter_mut().find(|e| e.source == d.source) {
                Some(e) => e.deltas.extend(d.deltas),
                None => self.directions.push(d),
            }
        }
        self.directions.retain(|d| !d.deltas.is_empty());
    }

    /// Covariance of two coefficients over the uncertainty directions.
    pub fn covariance(&self, a: &str, b: &str) -> f64 {
        self.directions
            .iter()
            .map(|d| {
                d.deltas.get(a).copied().unwrap_or(0.0) * d.deltas.get(b).copied().unwrap_or(0.0)
            })
            .sum()
    }

    /// Whether the directions account for a coefficient's whole sigma.
    pub fn covered(&self, name: &str) -> bool {
        match self.get(name).and_then(|c| c.sigma) {
            None => true,
            Some(s) => {
                let var = self.covariance(name, name);
                (var.sqrt() - s).abs() <= 1e-6 * s.max(f64::MIN_POSITIVE)
            }
        }
    }

    /// A coefficient's uncertainty by stage: sqrt of the summed squared changes of the
    /// directions from each stage (these add in quadrature to the sigma).
    pub fn budget(&self, name: &str) -> BTreeMap<String, f64> {
        let mut var: BTreeMap<String, f64> = BTreeMap::new();
        for d in &self.directions {
            if let Some(v) = d.deltas.get(name) {
                *var.entry(d.stage().to_string()).or_default() += v * v;
            }
        }
        var.into_iter().map(|(k, v)| (k, v.sqrt())).collect()
    }

    fn combined_sigma(&self, terms: &[(f64, Coefficient)]) -> Option<f64> {
        let mut var = 0.0;
        for (i, (fi, ci)) in terms.iter().enumerate() {
            let si = ci.sigma?;
            var += fi * fi * si * si;
            for (fj, cj) in terms.iter().skip(i + 1) {
                let sj = cj.sigma?;
                let rho = self
                    .correlation
                    .as_ref()
                    .and_then(|c| c.get(&ci.name, &cj.name))
                    .unwrap_or(0.0);
                var += 2.0 * fi * fj * rho * si * sj;
            }
        }
        Some(var.max(0.0).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symmetry_completes_the_paper_set() {
        let mut set = CoefficientSet::new();
        set.insert(Coefficient::new("Xud", -1.164, Some(0.01), Source::Surge));
        set.insert(Coefficient::new("Yvd", -23.626, Some(0.2), Source::Hekf));
        set.insert(Coefficient::new("Yrd", 0.0, Some(0.01), Source::Hekf));
        set.insert(Coefficient::new("Yuvd", 1.33, None, Source::Polar));
        set.insert(Coefficient::new("Yuvl", -16.31, None, Source::Polar));
        set.insert(Coefficient::new("Nuvl", 13.43, None, Source::Polar));
        let conflicts = set.complete(SYMMETRY, YawMoment::LiftOnly);
        assert!(conflicts.is_empty());
        assert_eq!(set.value("Xvr"), Some(23.626));
        assert_eq!(set.value("Yur"), Some(-1.164));
        let nuva = set.value("Nuva").unwrap();
        assert!((nuva - (-23.626 + 1.164)).abs() < 1e-12);
        let nuv = set.value("Nuv").unwrap();
        assert!((nuv - (nuva + 13.43)).abs() < 1e-12);
        // Nuva sigma from independent Xud and Yvd
        let s = set.get("Nuva").unwrap().sigma.unwrap();
        assert!((s - (0.01f64.powi(2) + 0.2f64.powi(2)).sqrt()).abs() < 1e-12);
        assert_eq!(set.get("Xvr").unwrap().source, Source::Symmetry);
        // Nuv has no sigma because the polar gave none for Nuvl
        assert_eq!(set.get("Nuv").unwrap().sigma, None);
    }

    #[test]
    fn correlated_terms_change_the_sigma() {
        let mut set = CoefficientSet::new();
        set.insert(Coefficient::new("Xud", -1.0, Some(0.1), Source::Hekf));
        set.insert(Coefficient::new("Yvd", -20.0, Some(0.1), Source::Hekf));
        set.correlation = Some(Correlation {
            names: vec!["Xud".into(), "Yvd".into()],
            matrix: vec![vec![1.0, 0.9], vec![0.9, 1.0]],
        });
        set.complete(SYMMETRY, YawMoment::LiftOnly);
        // Nuva = -Xud + Yvd: var = 0.01 + 0.01 - 2*0.9*0.01
        let s = set.get("Nuva").unwrap().sigma.unwrap();
        assert!((s - (0.002f64).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn directions_carry_correlations_into_derived_coefficients() {
        // Xud and Yvd perfectly correlated through one shared source: Nuva = -Xud + Yvd
        // cancels it; an independent source on Yvd alone adds in full.
        let mut set = CoefficientSet::new();
        set.insert(Coefficient::new("Xud", -1.0, Some(0.1), Source::Surge));
        set.insert(Coefficient::new(
            "Yvd",
            -20.0,
            Some(0.5f64.hypot(0.1)),
            Source::Hekf,
        ));
        set.directions.push(Direction {
            source: "surge statistics".into(),
            deltas: [("Xud".to_string(), 0.1), ("Yvd".to_string(), 0.1)]
                .into_iter()
                .collect(),
        });
        set.directions.push(Direction {
            source: "hekf 1".into(),
            deltas: [("Yvd".to_string(), 0.5)].into_iter().collect(),
        });
        assert!(set.covered("Xud") && set.covered("Yvd"));
        set.complete(SYMMETRY, YawMoment::LiftOnly);
        let s = set.get("Nuva").unwrap().sigma.unwrap();
        assert!((s - 0.5).abs() < 1e-12, "{s}");
        let b = set.budget("Nuva");
        assert!(b.get("surge").is_none_or(|v| v.abs() < 1e-12));
        assert!((b["hekf"] - 0.5).abs() < 1e-12);
        // Xvr = -Yvd joins both directions
        assert!((set.covariance("Xvr", "Yvd") + set.covariance("Yvd", "Yvd")).abs() < 1e-12);
    }

    #[test]
    fn directions_of_a_covariance_reproduce_it() {
        let cov = vec![vec![4.0, 1.2], vec![1.2, 1.0]];
        let d = directions_of("polar drag", &["Xuu", "Xvv"], &cov);
        let mut set = CoefficientSet::new();
        set.directions = d;
        assert!((set.covariance("Xuu", "Xuu") - 4.0).abs() < 1e-12);
        assert!((set.covariance("Xuu", "Xvv") - 1.2).abs() < 1e-12);
        assert!((set.covariance("Xvv", "Xvv") - 1.0).abs() < 1e-12);
        assert_eq!(set.directions[0].source, "polar drag 1");
    }

    #[test]
    fn compiled_relations_follow_their_terms() {
        let names = ["Xud", "Yvd", "Xvr", "Nuva", "Nuvl", "Nuv"];
        let rel = CompiledRelations::compile(&[SYMMETRY], &names);
        let mut v = [-1.0, -20.0, 0.0, 0.0, 13.0, 0.0];
        rel.apply(&mut v);
        assert_eq!(v[2], 20.0);
        assert_eq!(v[3], -19.0);
        assert_eq!(v[5], -6.0);
        assert_eq!(rel.targets().count(), 3);
        // the total reading: Nuv free, its lift part follows (paper eq. 2 and 4)
        let rel = CompiledRelations::compile_for(&[SYMMETRY], &names, YawMoment::Total);
        let mut v = [-1.0, -20.0, 0.0, 0.0, 0.0, -6.0];
        rel.apply(&mut v);
        assert_eq!((v[3], v[4], v[5]), (-19.0, 13.0, -6.0));
    }

    #[test]
    fn the_total_reading_derives_the_lift_part_with_its_sigma() {
        let mut set = CoefficientSet::new();
        set.insert(Coefficient::new("Xud", -1.164, Some(0.01), Source::Surge));
        set.insert(Coefficient::new("Yvd", -23.626, Some(0.2), Source::Hekf));
        set.insert(Coefficient::new("Nuv", -9.032, Some(0.1), Source::Polar));
        assert!(set.complete(SYMMETRY, YawMoment::Total).is_empty());
        // Nuvl = Nuv - Nuva = Nuv + Xud - Yvd
        let nuvl = set.value("Nuvl").unwrap();
        assert!((nuvl - (-9.032 - 1.164 + 23.626)).abs() < 1e-12, "{nuvl}");
        assert_eq!(set.get("Nuv").unwrap().source, Source::Polar);
        let s = set.get("Nuvl").unwrap().sigma.unwrap();
        let want = (0.1f64.powi(2) + 0.01f64.powi(2) + 0.2f64.powi(2)).sqrt();
        assert!((s - want).abs() < 1e-9, "{s} vs {want}");
    }

    #[test]
    fn names_tell_the_reading() {
        assert_eq!(YawMoment::of_names(["Nuv", "Xud"]), Some(YawMoment::Total));
        assert_eq!(YawMoment::of_names(["Nuvl"]), Some(YawMoment::LiftOnly));
        assert_eq!(YawMoment::of_names(["Xud"]), Some(YawMoment::LiftOnly));
        assert_eq!(YawMoment::of_names(["Nuvl", "Nuv"]), None);
    }
}
