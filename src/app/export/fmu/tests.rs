use super::*;
use crate::model::models::ModelName;

/// modelDescription.xml of the mmg3 example, parsed.
fn mmg3_description() -> (FmuSpec, String) {
    let spec = example(ModelName::Mmg3).unwrap();
    let json = crate::io::output::to_json(&spec).unwrap();
    let xml = description::model_description(&spec, &description::guid(&json), "hydroid_mmg3");
    (spec, xml)
}

fn attr<'a>(n: roxmltree::Node<'a, '_>, name: &str) -> &'a str {
    n.attribute(name)
        .unwrap_or_else(|| panic!("{} has no {name}", n.tag_name().name()))
}

#[test]
fn model_description_is_well_formed_and_lists_inputs_outputs_and_parameters() {
    let (_, xml) = mmg3_description();
    let doc = roxmltree::Document::parse(&xml).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "fmiModelDescription");
    assert_eq!(attr(root, "fmiVersion"), "2.0");
    let cs = root
        .children()
        .find(|n| n.has_tag_name("CoSimulation"))
        .unwrap();
    assert_eq!(attr(cs, "modelIdentifier"), "hydroid_mmg3");
    assert_eq!(attr(cs, "canGetAndSetFMUstate"), "false");
    assert!(!root.children().any(|n| n.has_tag_name("ModelExchange")));
    // (name, valueReference, causality, unit), in document order
    let vars: Vec<(String, u32, String, Option<String>)> = root
        .descendants()
        .filter(|n| n.has_tag_name("ScalarVariable"))
        .map(|v| {
            let real = v.children().find(|n| n.has_tag_name("Real")).unwrap();
            (
                attr(v, "name").to_string(),
                attr(v, "valueReference").parse().unwrap(),
                attr(v, "causality").to_string(),
                real.attribute("unit").map(str::to_string),
            )
        })
        .collect();
    // written out from the MMG model's inputs (Yasukawa & Yoshimura 2015: rudder angle,
    // propeller revolutions) and its planar states (u, v, r, x, y, psi)
    let want: [(&str, &str, &str); 14] = [
        ("rudder", "input", "rad"),
        ("rpm", "input", "rev/s"),
        ("u", "output", "m/s"),
        ("v", "output", "m/s"),
        ("r", "output", "rad/s"),
        ("x", "output", "m"),
        ("y", "output", "m"),
        ("psi", "output", "rad"),
        ("u0", "parameter", "m/s"),
        ("v0", "parameter", "m/s"),
        ("r0", "parameter", "rad/s"),
        ("x0", "parameter", "m"),
        ("y0", "parameter", "m"),
        ("psi0", "parameter", "rad"),
    ];
    assert_eq!(vars.len(), want.len(), "{vars:?}");
    for (k, ((name, vr, causality, unit), (n, c, u))) in vars.iter().zip(&want).enumerate() {
        assert_eq!((name.as_str(), causality.as_str()), (*n, *c));
        assert_eq!(unit.as_deref(), Some(*u), "{name}");
        assert_eq!(*vr as usize, k, "value references in order");
    }
    // every unit used is defined; rev/s is 2 pi rad/s
    let units: Vec<roxmltree::Node> = root
        .descendants()
        .filter(|n| n.has_tag_name("Unit"))
        .collect();
    for (_, _, _, u) in &vars {
        let u = u.as_deref().unwrap();
        assert!(units.iter().any(|n| attr(*n, "name") == u), "unit {u}");
    }
    let revs = units.iter().find(|n| attr(**n, "name") == "rev/s").unwrap();
    let base = revs
        .children()
        .find(|n| n.has_tag_name("BaseUnit"))
        .unwrap();
    assert_eq!((attr(base, "s"), attr(base, "rad")), ("-1", "1"));
    let factor: f64 = attr(base, "factor").parse().unwrap();
    assert!((factor - 2.0 * std::f64::consts::PI).abs() < 1e-15);
    // the outputs of the model structure are the six states (1-based indices 3..8)
    let outputs: Vec<usize> = root
        .descendants()
        .find(|n| n.has_tag_name("Outputs"))
        .unwrap()
        .children()
        .filter(|n| n.has_tag_name("Unknown"))
        .map(|n| attr(n, "index").parse().unwrap())
        .collect();
    assert_eq!(outputs, vec![3, 4, 5, 6, 7, 8]);
}

#[test]
fn guid_follows_the_content() {
    let (spec, _) = mmg3_description();
    let json = crate::io::output::to_json(&spec).unwrap();
    let g = description::guid(&json);
    assert_eq!(g.len(), 38, "{g}");
    assert!(g.starts_with('{') && g.ends_with('}'));
    let mut other = spec.clone();
    other.coefficients[0].value += 1e-12;
    assert_ne!(
        description::guid(&crate::io::output::to_json(&other).unwrap()),
        g
    );
}

#[test]
fn the_package_is_a_zip_with_the_three_entries_and_the_same_bytes_twice() {
    let spec = example(ModelName::Mmg3).unwrap();
    let lib = b"\x7fELF not really a library".to_vec();
    let a = package(&spec, &lib).unwrap();
    assert_eq!(a, package(&spec, &lib).unwrap(), "deterministic");
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(a)).unwrap();
    let mut names: Vec<String> = zip.file_names().map(|n| n.unwrap().into_owned()).collect();
    names.sort();
    assert_eq!(
        names,
        [
            "binaries/linux64/hydroid_mmg3.so",
            "modelDescription.xml",
            "resources/model.json"
        ]
    );
    let mut text = String::new();
    std::io::Read::read_to_string(&mut zip.by_name(MODEL_JSON).unwrap(), &mut text).unwrap();
    let back = FmuSpec::from_json(&text, "model.json").unwrap();
    assert_eq!(back, spec);
    back.check().unwrap();
}

#[test]
fn a_spec_of_another_model_layout_is_refused() {
    let mut spec = example(ModelName::Mmg3).unwrap();
    spec.states.swap(0, 1);
    let e = spec.check().unwrap_err().to_string();
    assert!(e.contains("states"), "{e}");
}

#[test]
fn a_missing_folder_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let e = read_folder(dir.path(), 0.01).unwrap_err().to_string();
    assert!(e.contains("no results.json"), "{e}");
}

/// A model.json whose longest step is outside 1e-5 s to 1 s is refused when read (the
/// library reads it at fmi2Instantiate) and when packaged: a step of 1e-300 s would fail every
/// communication step, one of 1e300 s not resolve the motion.
#[test]
fn a_step_outside_its_range_is_refused() {
    let mut spec = example(ModelName::Mmg3).unwrap();
    for step in [1e-300, 9e-6, 0.0, -0.01, 1.5, 1e300, f64::NAN] {
        spec.max_step = step;
        let e = spec.check().unwrap_err().to_string();
        assert!(
            e.contains("max_step") && e.contains("1e-5 s"),
            "{step}: {e}"
        );
        let mut json: serde_json::Value = serde_json::to_value(&spec).unwrap();
        json["max_step"] = serde_json::json!(if step.is_finite() { step } else { -1.0 });
        let e = FmuSpec::from_json(&json.to_string(), "model.json").unwrap_err();
        assert!(
            e.to_string().contains("model.json: max_step"),
            "{step}: {e}"
        );
    }
    for step in [1e-5, 0.01, 1.0] {
        spec.max_step = step;
        spec.check().unwrap();
    }
    // the bounds keep a communication step of 10 s within the steps one may take
    let (lo, _) = spec::MAX_STEP_RANGE;
    assert!(crate::numerics::ode::steps_for(10.0, lo).is_some());
}
