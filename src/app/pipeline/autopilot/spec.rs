//! The plant `[autopilot.plant]` names: its vehicle file read and parsed, the section's
//! coefficients over the file's (docs/autopilot.md).

use crate::base::error::{ConfigProblem, Error, InputError, Place, Result};
use crate::config::autopilot::AutopilotConfig;
use crate::config::autopilot_plant::PlantConfig;
use crate::config::{Config, FluidConfig, VehicleConfig};
use crate::model::coefficients::{Coefficient, CoefficientSet, Source};
use crate::model::models::{ModelName, RunVehicle};
use std::collections::BTreeMap;
use std::path::Path;

/// The plant `[autopilot.plant]` names, ready to build: None for the identified model.
#[derive(Debug, Clone)]
pub struct PlantSpec {
    /// The model.
    pub name: ModelName,
    /// Its vehicle: the vehicle file's, or the run's.
    pub vehicle: RunVehicle,
    /// Its coefficients: the vehicle file's with the section's over them.
    pub coefficients: CoefficientSet,
    /// The section as configured.
    pub cfg: PlantConfig,
}

/// A vehicle file: the sections of configs/vehicles/*.toml.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct VehicleFile {
    vehicle: VehicleConfig,
    #[serde(default)]
    fluid: Option<FluidConfig>,
    #[serde(default)]
    coefficients: BTreeMap<String, f64>,
}

/// The plant of `cfg` (the run's `config`, its folder `base`): its vehicle file read and
/// parsed, or an error naming the file and `autopilot.plant.vehicle_file`.
pub fn load_plant(
    cfg: &AutopilotConfig,
    config: &Config,
    base: &Path,
) -> Result<Option<PlantSpec>> {
    let Some(pc) = &cfg.plant else {
        return Ok(None);
    };
    let Some(name) = pc.model_name().map_err(|m| {
        Error::Config(vec![ConfigProblem {
            file: base.to_path_buf(),
            line: None,
            key: Some("autopilot.plant.model".into()),
            message: m,
        }])
    })?
    else {
        return Ok(None);
    };
    let (vehicle, mut coefficients) = match &pc.vehicle_file {
        None => (config.vehicle.clone(), BTreeMap::new()),
        Some(file) => {
            let path = base.join(file);
            let text = crate::config::read(&path)?;
            let f: VehicleFile = toml::from_str(&text).map_err(|e| {
                Error::from(
                    InputError::new(
                        Place::file(&path),
                        format!("autopilot.plant.vehicle_file: {}", e.message()),
                    )
                    .expected(
                        "a vehicle file: [vehicle] (with [vehicle.particulars]), optional \
                         [fluid] and [coefficients], as configs/vehicles/*.toml",
                    ),
                )
            })?;
            let fluid = f.fluid.unwrap_or_else(|| config.fluid.clone());
            return Ok(Some(spec(
                name,
                f.vehicle.for_model(&fluid),
                f.coefficients,
                pc,
            )));
        }
    };
    coefficients.extend(config.coefficients.clone());
    Ok(Some(spec(
        name,
        vehicle.for_model(&config.fluid),
        coefficients,
        pc,
    )))
}

/// The plant spec of the model `name` on `vehicle` with the `file`'s coefficients and the
/// section's over them.
fn spec(
    name: ModelName,
    vehicle: RunVehicle,
    mut file: BTreeMap<String, f64>,
    pc: &PlantConfig,
) -> PlantSpec {
    file.extend(pc.coefficients.clone());
    let mut coefficients = CoefficientSet::new();
    for (n, v) in &file {
        coefficients.insert(Coefficient::new(n, *v, None, Source::Config));
    }
    PlantSpec {
        name,
        vehicle,
        coefficients,
        cfg: pc.clone(),
    }
}
