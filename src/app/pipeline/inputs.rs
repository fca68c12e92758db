//! The input files of a run, by the stage that reads them and what it reads them as: built
//! once from the configuration, then read (each file checked and hashed) before any stage
//! runs.

use crate::app::results::LoadedInput;
use crate::base::error::Result;
use crate::config::{Config, DataSource, InputSpec, LoadedConfig};
use crate::io::formats::input::file_sha256;
use crate::io::record::{self, Needs};
use crate::stages::{captive, hekf, polar, surge};

/// The input files of the enabled stages, by what each stage reads them as, in the order of
/// the configuration. `T` is what is known of each file: the plan ([`PlannedInput`]) or the
/// file read ([`LoadedInput`]).
#[derive(Debug, Clone, PartialEq)]
pub struct InputsByStage<T> {
    /// The steady runs of the static polar sweep (`polar.runs`).
    pub polar: Vec<T>,
    /// The straight-line acceleration runs of the surge stage (`surge.runs`).
    pub surge: Vec<T>,
    /// The tables of steady captive conditions (`captive.runs`).
    pub captive: Vec<T>,
    /// The manoeuvres the HEKF fits (`hekf.runs`).
    pub hekf_fit: Vec<T>,
    /// The manoeuvres kept to validate the identified model (`hekf.validation`).
    pub hekf_validation: Vec<T>,
}

impl<T> Default for InputsByStage<T> {
    fn default() -> Self {
        InputsByStage {
            polar: Vec::new(),
            surge: Vec::new(),
            captive: Vec::new(),
            hekf_fit: Vec::new(),
            hekf_validation: Vec::new(),
        }
    }
}

impl<T> InputsByStage<T> {
    /// Every file in the order of the configuration: polar, surge, captive, HEKF fit runs,
    /// HEKF validation runs.
    pub fn iter(&self) -> impl Iterator<Item = &T> {
        self.polar
            .iter()
            .chain(&self.surge)
            .chain(&self.captive)
            .chain(&self.hekf_fit)
            .chain(&self.hekf_validation)
    }

    /// The runs each stage fits, by stage name, in the order of [`Self::iter`] (the HEKF's
    /// validation runs fit nothing).
    pub fn fitted(&self) -> [(&'static str, &Vec<T>); 4] {
        [
            ("polar", &self.polar),
            ("surge", &self.surge),
            ("captive", &self.captive),
            ("hekf", &self.hekf_fit),
        ]
    }

    /// [`Self::fitted`], to change.
    pub fn fitted_mut(&mut self) -> [&mut Vec<T>; 4] {
        [
            &mut self.polar,
            &mut self.surge,
            &mut self.captive,
            &mut self.hekf_fit,
        ]
    }

    /// The HEKF's manoeuvres: the fit runs, then the validation runs.
    pub fn hekf_all(&self) -> impl Iterator<Item = &T> {
        self.hekf_fit.iter().chain(&self.hekf_validation)
    }

    /// Each file turned into something else by `f`, in the order of [`Self::iter`]; the
    /// first error stops.
    pub fn try_map<U, E>(
        self,
        mut f: impl FnMut(T) -> std::result::Result<U, E>,
    ) -> std::result::Result<InputsByStage<U>, E> {
        let mut each =
            |v: Vec<T>| -> std::result::Result<Vec<U>, E> { v.into_iter().map(&mut f).collect() };
        Ok(InputsByStage {
            polar: each(self.polar)?,
            surge: each(self.surge)?,
            captive: each(self.captive)?,
            hekf_fit: each(self.hekf_fit)?,
            hekf_validation: each(self.hekf_validation)?,
        })
    }
}

impl<T> InputsByStage<Option<T>> {
    /// The files that are there (those that could be read).
    pub fn present(self) -> InputsByStage<T> {
        let keep = |v: Vec<Option<T>>| v.into_iter().flatten().collect();
        InputsByStage {
            polar: keep(self.polar),
            surge: keep(self.surge),
            captive: keep(self.captive),
            hekf_fit: keep(self.hekf_fit),
            hekf_validation: keep(self.hekf_validation),
        }
    }
}

/// One input file a stage will read.
#[derive(Debug, Clone)]
pub struct PlannedInput<'a> {
    /// Configuration key (`hekf.runs[0]`): a label for messages and results.json.
    pub key: String,
    /// The file and how to read it.
    pub spec: &'a InputSpec,
    /// What the stage needs from it.
    pub needs: Needs<'static>,
}

/// Every input of every enabled stage with its key and what the stage needs from it.
pub fn stage_inputs(cfg: &Config) -> InputsByStage<PlannedInput<'_>> {
    let mut v = InputsByStage::default();
    if let Some(c) = cfg.polar.as_ref().filter(|c| c.enabled) {
        v.polar = planned(c.inputs(), polar::needs(c));
    }
    if let Some(c) = cfg.surge.as_ref().filter(|c| c.enabled) {
        v.surge = planned(c.inputs(), surge::needs(c));
    }
    if let Some(c) = cfg.captive.as_ref().filter(|c| c.enabled) {
        v.captive = planned(c.inputs(), captive::needs(c));
    }
    if let Some(c) = cfg.hekf.as_ref().filter(|c| c.enabled) {
        // a fit run is one of the specs of `hekf.runs`; the others are `hekf.validation`
        let (fit, validation) = c
            .inputs()
            .into_iter()
            .partition(|(_, spec)| c.runs.iter().any(|r| std::ptr::eq(r, *spec)));
        v.hekf_fit = planned(fit, hekf::needs(c));
        v.hekf_validation = planned(validation, hekf::needs(c));
    }
    v
}

/// The files a section names, each with what its stage needs from it.
fn planned<'a>(
    inputs: Vec<(String, &'a InputSpec)>,
    needs: Needs<'static>,
) -> Vec<PlannedInput<'a>> {
    inputs
        .into_iter()
        .map(|(key, spec)| PlannedInput { key, spec, needs })
        .collect()
}

/// Reads every planned input; the first file that cannot be used stops.
pub fn load_inputs(
    loaded: &LoadedConfig,
    planned: InputsByStage<PlannedInput>,
) -> Result<InputsByStage<LoadedInput>> {
    planned.try_map(|p| load_input(loaded, &p))
}

/// Loads one input file for a stage.
pub fn load_input(loaded: &LoadedConfig, input: &PlannedInput) -> Result<LoadedInput> {
    let record = record::load(input.spec, &loaded.base_dir, &input.needs)?;
    let sha256 = file_sha256(&record.source)?;
    let source = input
        .spec
        .source
        .unwrap_or_else(|| DataSource::of_format(record.format));
    Ok(LoadedInput {
        key: input.key.clone(),
        record,
        sha256,
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(hekf: &str) -> Config {
        let text = format!(
            "[vehicle]\nname = \"v\"\nmass = 1\nlength = 1\nizz = 1\nreference_area = 1\n\
             reference_length = 1\n[fluid]\nrho = 1000\nmu = 0.001\n[hekf]\n{hekf}"
        );
        toml::from_str(&text).expect("a valid configuration")
    }

    #[test]
    fn hekf_runs_are_told_from_validation_runs_by_the_section_they_are_in() {
        let c = config(
            "estimate = [\"Yvd\"]\nruns = [{ file = \"a.csv\" }, { file = \"b.csv\" }]\n\
             validation = [{ file = \"c.csv\" }]\n",
        );
        let p = stage_inputs(&c);
        let keys = |v: &[PlannedInput]| v.iter().map(|p| p.key.clone()).collect::<Vec<_>>();
        assert_eq!(keys(&p.hekf_fit), ["hekf.runs[0]", "hekf.runs[1]"]);
        assert_eq!(keys(&p.hekf_validation), ["hekf.validation[0]"]);
        assert!(p.polar.is_empty() && p.surge.is_empty());
        let files: Vec<_> = p.iter().map(|p| p.spec.file.clone()).collect();
        assert_eq!(
            files,
            ["a.csv", "b.csv", "c.csv"].map(std::path::PathBuf::from)
        );
    }
}
