//! modelDescription.xml of an FMI 2.0 co-simulation FMU (FMI 2.0.x standard, chapters 2.2
//! and 4.3): the model's inputs, its states as outputs and their start values as
//! parameters, each with its unit.

use super::spec::{FmuSpec, Variable};
use crate::base::quantity::Quantity;
use std::fmt::Write;

/// The default communication step written as the DefaultExperiment's stepSize, s.
pub const DEFAULT_STEP: f64 = 0.1;

/// The name of an initial-state parameter: the state's name and `0` (`u0`, `psi0`).
pub fn start_parameter(state: &str) -> String {
    format!("{state}0")
}

/// Text escaped for an XML attribute (the report's HTML escaping, which XML shares; control
/// characters, which XML 1.0 does not allow, as spaces).
fn escape(s: &str) -> String {
    crate::app::report::html::escape(&s.replace(|c: char| c.is_control(), " "))
}

/// A `<Unit>` definition for a quantity's internal unit: its SI base-unit exponents over
/// (kg, m, s, rad) and its factor to SI (FMI 2.0 section 2.2.2).
fn unit_definition(q: Quantity) -> Option<String> {
    let unit = q.internal_unit();
    let symbol = q.si_symbol();
    if symbol == "-" {
        return None;
    }
    let mut base = String::new();
    for (name, e) in ["kg", "m", "s", "rad"].iter().zip(unit.dim) {
        if e != 0 {
            let _ = write!(base, " {name}=\"{e}\"");
        }
    }
    if unit.factor != 1.0 {
        let _ = write!(base, " factor=\"{}\"", unit.factor);
    }
    Some(format!(
        "    <Unit name=\"{}\">\n      <BaseUnit{base}/>\n    </Unit>\n",
        escape(symbol)
    ))
}

fn quantity(v: &Variable) -> Option<Quantity> {
    Quantity::from_key(&v.quantity)
}

/// The `unit` attribute of a variable (none for a dimensionless one).
fn unit_attribute(v: &Variable) -> String {
    if v.unit == "-" || v.unit.is_empty() {
        String::new()
    } else {
        format!(" unit=\"{}\"", escape(&v.unit))
    }
}

/// One scalar variable.
struct Scalar<'a> {
    name: String,
    causality: &'a str,
    variability: &'a str,
    initial: Option<&'a str>,
    start: Option<f64>,
    description: String,
    unit: String,
}

impl Scalar<'_> {
    fn xml(&self, reference: usize) -> String {
        let initial = self
            .initial
            .map(|i| format!(" initial=\"{i}\""))
            .unwrap_or_default();
        let start = self
            .start
            .map(|s| format!(" start=\"{s}\""))
            .unwrap_or_default();
        format!(
            "    <ScalarVariable name=\"{}\" valueReference=\"{reference}\" description=\"{}\" \
             causality=\"{}\" variability=\"{}\"{initial}>\n      <Real{}{start}/>\n    \
             </ScalarVariable>\n",
            escape(&self.name),
            escape(&self.description),
            self.causality,
            self.variability,
            self.unit
        )
    }
}

/// The model's variables in value-reference order: the inputs, the outputs (states), the
/// initial-state parameters.
fn variables(spec: &FmuSpec) -> Vec<Scalar<'static>> {
    let mut out = Vec::new();
    for v in &spec.inputs {
        out.push(Scalar {
            name: v.name.clone(),
            causality: "input",
            variability: "continuous",
            initial: None,
            start: Some(v.start),
            description: format!("input {}, held over each communication step", v.quantity),
            unit: unit_attribute(v),
        });
    }
    for v in &spec.states {
        out.push(Scalar {
            name: v.name.clone(),
            causality: "output",
            variability: "continuous",
            initial: Some("calculated"),
            start: None,
            description: format!("state {} ({})", v.name, v.quantity),
            unit: unit_attribute(v),
        });
    }
    for v in &spec.states {
        out.push(Scalar {
            name: start_parameter(&v.name),
            causality: "parameter",
            variability: "fixed",
            initial: Some("exact"),
            start: Some(v.start),
            description: format!("initial value of the state {}", v.name),
            unit: unit_attribute(v),
        });
    }
    out
}

/// The modelDescription.xml of `spec` packaged with the library `identifier`.so.
pub fn model_description(spec: &FmuSpec, guid: &str, identifier: &str) -> String {
    let mut units: Vec<Quantity> = spec
        .inputs
        .iter()
        .chain(&spec.states)
        .filter_map(quantity)
        .collect();
    units.sort_by_key(|q| q.si_symbol());
    units.dedup_by_key(|q| q.si_symbol());
    let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let title = spec.title.as_deref().unwrap_or("identified model");
    let _ = writeln!(
        x,
        "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"{}\" guid=\"{guid}\" \
         description=\"{} ({} model identified by hydroid)\" generationTool=\"hydroid {}\" \
         variableNamingConvention=\"flat\" numberOfEventIndicators=\"0\">",
        escape(identifier),
        escape(title),
        escape(&spec.model),
        escape(&spec.hydroid_version),
    );
    let _ = writeln!(
        x,
        "  <CoSimulation modelIdentifier=\"{identifier}\" \
         canHandleVariableCommunicationStepSize=\"true\" \
         canNotUseMemoryManagementFunctions=\"true\" canGetAndSetFMUstate=\"false\" \
         canSerializeFMUstate=\"false\"/>"
    );
    x.push_str("  <UnitDefinitions>\n");
    for q in units {
        x.push_str(&unit_definition(q).unwrap_or_default());
    }
    x.push_str("  </UnitDefinitions>\n");
    let _ = writeln!(
        x,
        "  <DefaultExperiment startTime=\"0\" stepSize=\"{DEFAULT_STEP}\"/>"
    );
    x.push_str("  <ModelVariables>\n");
    let vars = variables(spec);
    for (i, v) in vars.iter().enumerate() {
        x.push_str(&v.xml(i));
    }
    x.push_str("  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n");
    // 1-based indices of the outputs in ModelVariables; a state does not depend on the
    // inputs of the same instant (no direct feed-through), so `dependencies` is empty
    let outputs = spec.inputs.len() + 1..=spec.inputs.len() + spec.states.len();
    for i in outputs.clone() {
        let _ = writeln!(x, "      <Unknown index=\"{i}\" dependencies=\"\"/>");
    }
    x.push_str("    </Outputs>\n    <InitialUnknowns>\n");
    for i in outputs {
        let _ = writeln!(x, "      <Unknown index=\"{i}\"/>");
    }
    x.push_str("    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n");
    x
}

/// An FMI GUID derived from the content: the first 128 bits of the SHA-256 of model.json,
/// written as `{8-4-4-4-12}` hex digits.
pub fn guid(model_json: &[u8]) -> String {
    use sha2::Digest;
    let h = sha2::Sha256::digest(model_json);
    let hex: String = h.iter().take(16).map(|b| format!("{b:02x}")).collect();
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}
