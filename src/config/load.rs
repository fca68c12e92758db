//! Reading a configuration: TOML syntax, `--set` overrides, schema (unknown keys with
//! suggestions, types, units), then validation; every problem is collected, not only the
//! first (see `collect`).

use super::collect::read_collecting;
use super::{Config, Problems};
use crate::base::error::{ConfigProblem, Error, Result};
use crate::model::models::RunVehicle;
use std::path::{Path, PathBuf};

/// A configuration that parsed and validated.
#[derive(Debug, Clone)]
pub struct LoadedConfig {
    /// The configuration.
    pub config: Config,
    /// The run's vehicle (SI data and the yaw-moment reading), built once from
    /// `config.vehicle` and `config.fluid` after the reading was resolved.
    pub vehicle: RunVehicle,
    /// The file it came from.
    pub path: PathBuf,
    /// The folder paths in it are relative to.
    pub base_dir: PathBuf,
    /// The `--set` overrides applied, as given.
    pub overrides: Vec<String>,
    /// Keys whose values could not be used (each is among the problems found); the
    /// configuration holds placeholders there. Empty for a configuration without problems.
    pub unusable: Vec<String>,
}

impl LoadedConfig {
    /// Resolves a path from the configuration against its folder.
    pub fn resolve(&self, p: &Path) -> PathBuf {
        self.base_dir.join(p)
    }

    /// True when a key at or inside `key` (e.g. `hekf.runs[0]`), or a table holding it,
    /// could not be used.
    pub fn touches_unusable(&self, key: &str) -> bool {
        use super::problems::under;
        self.unusable.iter().any(|u| under(u, key) || under(key, u))
    }

    /// The effective configuration (after defaults and overrides) as TOML.
    pub fn effective_toml(&self) -> String {
        toml::to_string_pretty(&self.config)
            .unwrap_or_else(|e| format!("# could not serialise the configuration: {e}\n"))
    }
}

/// Reads and validates the configuration at `path`, applying `overrides` (`KEY=VALUE`).
pub fn load(path: &Path, overrides: &[String]) -> Result<LoadedConfig> {
    load_str(path, &read(path)?, overrides)
}

/// The text of a configuration file, or the problem reading it. The file is read like every
/// input (`formats::input`): a regular file, within the size and line limits, UTF-8.
pub fn read(path: &Path) -> Result<String> {
    use crate::io::formats::input::{read_bytes, Limits};
    let problem = |line: Option<usize>, message: String| {
        Error::Config(vec![ConfigProblem {
            file: path.to_path_buf(),
            line,
            key: None,
            message,
        }])
    };
    let bytes = Limits::for_file(path)
        .and_then(|limits| read_bytes(path, &limits))
        .map_err(|e| {
            let expected = e
                .expected
                .map(|x| format!(" (expected {x})"))
                .unwrap_or_default();
            problem(
                e.place.line,
                format!("cannot read the configuration: {}{expected}", e.message),
            )
        })?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count();
        problem(
            Some(line),
            format!("the configuration is not UTF-8 text (byte offset {at}); save it as UTF-8"),
        )
    })
}

/// Like [`load`], from text already read (`path` places messages and resolves relative paths).
pub fn load_str(path: &Path, text: &str, overrides: &[String]) -> Result<LoadedConfig> {
    match load_lenient(path, text, overrides) {
        (Some(c), p) if p.is_empty() => Ok(c),
        (_, p) => Err(Error::Config(p)),
    }
}

/// Reads the configuration and returns it whenever it could be read, together with every
/// problem found: schema problems (unknown keys, wrong types, units, missing keys) and
/// validation problems, all at once. When a key was unusable the configuration holds a
/// placeholder there and [`LoadedConfig::unusable`] names the key, so that `hydroid check`
/// can go on to check the input files the other keys name.
pub fn load_lenient(
    path: &Path,
    text: &str,
    overrides: &[String],
) -> (Option<LoadedConfig>, Vec<ConfigProblem>) {
    let mut p = Problems::new(path, text);
    let Some(config) = read_collecting::<Config>(&mut p, text, overrides) else {
        return (None, p.in_file_order());
    };
    let mut config = config;
    // first: the models the validation builds read the yaw moment as the run will
    match config.yaw_moment() {
        Ok(reading) => config.vehicle.yaw_moment = reading,
        Err((key, message)) => p.add(&key, message),
    }
    // the run's vehicle, built once: validation, every stage and the re-simulation use it
    let vehicle = config.vehicle.for_model(&config.fluid);
    config.validate(&vehicle, &mut p);
    let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let unusable = p.poisoned().to_vec();
    (
        Some(LoadedConfig {
            config,
            vehicle,
            path: path.to_path_buf(),
            base_dir,
            overrides: overrides.to_vec(),
            unusable,
        }),
        p.in_file_order(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::coefficients::YawMoment;

    const GOOD: &str = "[vehicle]\nmass = 50\nlength = 1.2\nizz = 3.7\nreference_area = 0.03\n\
        reference_length = 1\n[fluid]\nrho = 1025\nmu = 0.0009\n[hekf]\nestimate = [\"Yvd\"]\n\
        [[hekf.runs]]\nfile = \"load.rs\"\n";

    fn problems(text: &str, overrides: &[&str]) -> Vec<String> {
        let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        let (_, p) = load_lenient(Path::new("src/config/c.toml"), text, &o);
        p.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn the_yaw_moment_reading_is_resolved_once_and_nuv_with_nuvl_is_refused() {
        let read = |text: &str| {
            let (c, p) = load_lenient(Path::new("src/config/c.toml"), text, &[]);
            assert!(p.is_empty(), "{p:?}");
            c.unwrap().vehicle
        };
        let with = |c: &str| GOOD.replace("[hekf]", &format!("[coefficients]\n{c}\n[hekf]"));
        assert_eq!(read(GOOD).yaw_moment, YawMoment::LiftOnly);
        assert_eq!(read(&with("Nuv = -9.0")).yaw_moment, YawMoment::Total);
        assert_eq!(read(&with("Nuvl = 13.4")).yaw_moment, YawMoment::LiftOnly);
        let all = problems(&with("Nuv = -9.0\nNuvl = 13.4"), &[]).join("\n");
        assert!(
            all.contains("coefficients.Nuvl")
                && all.contains("Nuv (from coefficients.Nuv) and Nuvl (from coefficients.Nuvl)"),
            "{all}"
        );
        // a polar with the default total reading gives Nuv: with a given Nuvl, both
        let polar = GOOD.replace(
            "[hekf]",
            "[coefficients]\nNuvl = 13.4\n[polar]\n[[polar.runs]]\nfile = \"load.rs\"\n[hekf]",
        );
        let all = problems(&polar, &[]).join("\n");
        assert!(
            all.contains("Nuv (from polar.moment.part = \"total\")"),
            "{all}"
        );
    }

    #[test]
    fn a_type_error_does_not_hide_the_other_problems() {
        assert_eq!(problems(GOOD, &[]), Vec::<String>::new());
        let bad = GOOD
            .replace("mass = 50", "mass = \"heavy\"")
            .replace("rho = 1025", "rho = -1")
            .replace("[\"Yvd\"]", "[\"Yvd\", \"Yvd\"]");
        let all = problems(&bad, &[]).join("\n");
        assert!(
            all.contains(":2: vehicle.mass: \"heavy\" is not a number"),
            "{all}"
        );
        assert!(all.contains(":8: fluid.rho"), "{all}");
        assert!(
            all.contains("hekf.estimate[1]: 'Yvd' is listed twice"),
            "{all}"
        );
    }

    #[test]
    fn overrides_are_named_in_messages() {
        let all = problems(GOOD, &["hekf.passes=0", "vehicle.mass=\"50 m\""]).join("\n");
        assert!(
            all.contains("hekf.passes: (from --set hekf.passes=0)"),
            "{all}"
        );
        assert!(
            all.contains("vehicle.mass: (from --set vehicle.mass=\"50 m\")"),
            "{all}"
        );
        assert!(
            all.contains("c.toml: hekf.passes") && !all.contains("c.toml:1"),
            "{all}"
        );
    }
}
