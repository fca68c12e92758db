//! `hydroid export fmu OUTDIR`: the identified model of an output folder as an FMI 2.0
//! co-simulation FMU for Linux x86-64 (docs/fmu.md): modelDescription.xml, the shared
//! library of the `hydroid-fmu` crate as binaries/linux64/IDENTIFIER.so, and the model
//! (vehicle, coefficients, inputs and states) as resources/model.json, which the library
//! reads when it is instantiated.

pub mod assemble;
pub mod description;
pub mod folder;
pub mod library;
pub mod spec;

pub use assemble::from_parts;
pub use folder::{read_folder, Exported, Starts};

use crate::base::error::{Error, Result};
use crate::model::coefficients::{Coefficient, CoefficientSet, Source};
use crate::model::models::{Model, ModelVisitor, RunVehicle};
use spec::FmuSpec;
use std::io::Write;

/// The archive's path of the model file.
pub const MODEL_JSON: &str = "resources/model.json";

/// The FMU's model identifier (the library's name inside it) for a model: `hydroid_mmg3`.
pub fn model_identifier(spec: &FmuSpec) -> String {
    format!("hydroid_{}", spec.model)
}

/// The FMU archive (a zip, deflated, entries in a fixed order with a fixed time stamp, so
/// that the same folder and library give the same bytes): modelDescription.xml,
/// resources/model.json and `library` as binaries/linux64/IDENTIFIER.so.
pub fn package(spec: &FmuSpec, library: &[u8]) -> Result<Vec<u8>> {
    spec.check()?;
    let json = crate::io::output::to_json(spec)?;
    let guid = description::guid(&json);
    let identifier = model_identifier(spec);
    let xml = description::model_description(spec, &guid, &identifier);
    let so = format!("binaries/linux64/{identifier}.so");
    let entries: [(&str, &[u8], u32); 3] = [
        ("modelDescription.xml", xml.as_bytes(), 0o644),
        (MODEL_JSON, &json, 0o644),
        (&so, library, 0o755),
    ];
    let fail = |e: String| Error::Usage(format!("cannot write the FMU archive: {e}"));
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    for (name, bytes, mode) in entries {
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .last_modified_time(zip::DateTime::default())
            .unix_permissions(mode);
        zip.start_file(name, options)
            .map_err(|e| fail(e.to_string()))?;
        zip.write_all(bytes).map_err(|e| fail(e.to_string()))?;
    }
    let cursor = zip.finish().map_err(|e| fail(e.to_string()))?;
    Ok(cursor.into_inner())
}

/// The FMU's model of a registered model at its example vehicle and coefficients, for tests.
pub fn example(name: crate::model::models::ModelName) -> Result<FmuSpec> {
    struct Example;
    impl ModelVisitor for Example {
        type Output = CoefficientSet;
        fn visit<M: Model>(self, m: &M) -> CoefficientSet {
            let mut set = CoefficientSet::new();
            for (n, v) in m.example().coefficients {
                set.insert(Coefficient::new(n, *v, None, Source::Config));
            }
            set
        }
    }
    let vehicle = RunVehicle {
        vehicle: name.example_vehicle(),
        yaw_moment: Default::default(),
    };
    let set = crate::model::models::with_model(name, &vehicle, Example)
        .map_err(|_| Error::Usage(format!("{} does not build at its example", name.as_str())))?;
    from_parts(
        name.as_str(),
        &vehicle,
        &set,
        &[],
        crate::numerics::ode::DEFAULT_MAX_STEP,
        Some("example".into()),
    )
}

#[cfg(test)]
mod tests;
