//! The C API of the FMU library called as an importer calls it: instantiate from a
//! temporary resources folder, set the inputs, step, read the outputs; compared with one
//! `dynamics::sim::simulate` of the same model over the whole time grid with the inputs held
//! at their samples.

use hydroid::app::export::fmu::{description, example};
use hydroid::dynamics::sim::inputs::Input;
use hydroid::dynamics::sim::{simulate, InputSeries};
use hydroid::model::models::{Mmg3, Model, ModelName};
use hydroid_fmu::*;
use std::ffi::{c_char, c_void, CStr, CString};
use std::sync::Mutex;

/// Messages the logger got.
static LOG: Mutex<Vec<String>> = Mutex::new(Vec::new());

// The logger is C-variadic in the standard; a test logger reads the one "%s" argument the
// library always passes, declared as that argument (the same calling convention on x86-64
// System V for this call).
unsafe extern "C" fn logger(
    _env: *mut c_void,
    _name: *const c_char,
    _status: Fmi2Status,
    _category: *const c_char,
    _format: *const c_char,
    message: *const c_char,
) {
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    LOG.lock().unwrap().push(text);
}

fn callbacks() -> Fmi2CallbackFunctions {
    Fmi2CallbackFunctions {
        // SAFETY: see `logger`
        logger: Some(unsafe {
            std::mem::transmute::<
                unsafe extern "C" fn(
                    *mut c_void,
                    *const c_char,
                    Fmi2Status,
                    *const c_char,
                    *const c_char,
                    *const c_char,
                ),
                Fmi2Logger,
            >(logger)
        }),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    }
}

/// A resources folder with the mmg3 example's model.json; its GUID.
fn resources() -> (tempfile::TempDir, CString, CString) {
    let spec = example(ModelName::Mmg3).unwrap();
    let json = hydroid::io::output::to_json(&spec).unwrap();
    // a space in the path, percent-encoded in the URI
    let dir = tempfile::Builder::new()
        .prefix("fmu res")
        .tempdir()
        .unwrap();
    std::fs::write(dir.path().join("model.json"), &json).unwrap();
    let uri = format!(
        "file://{}",
        dir.path().display().to_string().replace(' ', "%20")
    );
    let guid = CString::new(description::guid(&json)).unwrap();
    (dir, CString::new(uri).unwrap(), guid)
}

fn instantiate(uri: &CString, guid: &CString, cb: &Fmi2CallbackFunctions) -> Fmi2Component {
    unsafe {
        fmi2Instantiate(
            c"ship".as_ptr(),
            FMI2_COSIMULATION,
            guid.as_ptr(),
            uri.as_ptr(),
            cb,
            0,
            0,
        )
    }
}

#[test]
fn steps_through_the_c_api_match_one_simulation_with_held_inputs() {
    let (_dir, uri, guid) = resources();
    let cb = callbacks();
    let c = instantiate(&uri, &guid, &cb);
    assert!(!c.is_null(), "{:?}", LOG.lock().unwrap());
    // inputs rudder (0), rpm (1); outputs 2..8; initial states 8..14
    let x0 = [1.2, 0.0, 0.0, 0.0, 0.0, 0.0];
    let starts: Vec<u32> = (8..14).collect();
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), FMI2_OK);
        assert_eq!(fmi2EnterInitializationMode(c), FMI2_OK);
        assert_eq!(fmi2SetReal(c, starts.as_ptr(), 6, x0.as_ptr()), FMI2_OK);
        assert_eq!(fmi2ExitInitializationMode(c), FMI2_OK);
    }
    let h = 0.25;
    let n = 120;
    let rudder = |k: usize| {
        if (k / 20).is_multiple_of(2) {
            0.35
        } else {
            -0.35
        }
    };
    let rps = 11.85;
    let mut got = vec![x0.to_vec()];
    for k in 0..n {
        let u = [rudder(k), rps];
        let mut x = [0.0; 6];
        let outs: Vec<u32> = (2..8).collect();
        unsafe {
            assert_eq!(fmi2SetReal(c, [0u32, 1].as_ptr(), 2, u.as_ptr()), FMI2_OK);
            assert_eq!(fmi2DoStep(c, k as f64 * h, h, 1), FMI2_OK);
            assert_eq!(fmi2GetReal(c, outs.as_ptr(), 6, x.as_mut_ptr()), FMI2_OK);
        }
        got.push(x.to_vec());
    }
    unsafe {
        assert_eq!(fmi2Terminate(c), FMI2_OK);
        fmi2FreeInstance(c);
    }
    // the reference: the model built here, every input a held series over the grid
    let m = Mmg3::build(&ModelName::Mmg3.example_vehicle()).unwrap();
    let cv = m.coefficient_vector(m.example().coefficients);
    let times: Vec<f64> = (0..=n).map(|k| k as f64 * h).collect();
    let inputs = InputSeries {
        t: times.clone(),
        inputs: vec![
            Input::Held((0..=n).map(rudder).collect()),
            Input::Held(vec![rps; n + 1]),
        ],
    };
    // 0.25 s in steps of at most 10 ms: 25 RK4 steps per interval
    let want = simulate(&m, &cv, &x0, &inputs, &times, 25).unwrap();
    let turned = want.last().unwrap()[5].abs();
    assert!(turned > 0.1, "the rudder turned the ship: psi {turned}");
    for (k, (a, b)) in got.iter().zip(&want).enumerate() {
        for i in 0..6 {
            let scale = b[i].abs().max(1.0);
            assert!(
                (a[i] - b[i]).abs() <= 1e-12 * scale,
                "t = {} s, state {i}: {} from the FMU, {} from simulate",
                k as f64 * h,
                a[i],
                b[i]
            );
        }
    }
}

#[test]
fn misuse_is_an_error_logged_not_a_crash() {
    let (_dir, uri, guid) = resources();
    let cb = callbacks();
    // a wrong GUID: no instance, the reason logged
    let bad = CString::new("{00000000-0000-0000-0000-000000000000}").unwrap();
    assert!(instantiate(&uri, &bad, &cb).is_null());
    assert!(LOG.lock().unwrap().iter().any(|m| m.contains("GUID")));
    // a folder without model.json
    let empty = tempfile::tempdir().unwrap();
    let other = CString::new(format!("file://{}", empty.path().display())).unwrap();
    assert!(instantiate(&other, &guid, &cb).is_null());
    // model exchange is not offered
    let me = unsafe { fmi2Instantiate(c"me".as_ptr(), 0, guid.as_ptr(), uri.as_ptr(), &cb, 0, 0) };
    assert!(me.is_null());
    let c = instantiate(&uri, &guid, &cb);
    assert!(!c.is_null());
    let mut state: *mut c_void = std::ptr::null_mut();
    let mut v = 0.0;
    unsafe {
        // stepping before initialization, an unknown reference, an output set, FMU states
        assert_eq!(fmi2DoStep(c, 0.0, 0.1, 1), FMI2_ERROR);
        assert_eq!(fmi2GetReal(c, [99u32].as_ptr(), 1, &mut v), FMI2_ERROR);
        assert_eq!(fmi2SetReal(c, [2u32].as_ptr(), 1, &1.0), FMI2_ERROR);
        assert_eq!(fmi2GetFMUstate(c, &mut state), FMI2_ERROR);
        assert_eq!(
            fmi2SetRealInputDerivatives(c, std::ptr::null(), 0, std::ptr::null(), std::ptr::null()),
            FMI2_ERROR
        );
        assert_eq!(
            fmi2GetInteger(c, std::ptr::null(), 0, std::ptr::null_mut()),
            FMI2_OK
        );
        assert_eq!(fmi2GetInteger(c, [0u32].as_ptr(), 1, &mut 0), FMI2_ERROR);
        assert_eq!(fmi2EnterInitializationMode(c), FMI2_OK);
        assert_eq!(fmi2ExitInitializationMode(c), FMI2_OK);
        // the initial-state parameters are fixed once initialized; a step off the FMU's
        // time and a non-positive step are refused
        assert_eq!(fmi2SetReal(c, [8u32].as_ptr(), 1, &1.0), FMI2_ERROR);
        assert_eq!(fmi2DoStep(c, 1.0, 0.1, 1), FMI2_ERROR);
        assert_eq!(fmi2DoStep(c, 0.0, 0.0, 1), FMI2_ERROR);
        let mut t = -1.0;
        assert_eq!(
            fmi2GetRealStatus(c, FMI2_LAST_SUCCESSFUL_TIME, &mut t),
            FMI2_OK
        );
        assert_eq!(t, 0.0);
        // null component
        assert_eq!(fmi2DoStep(std::ptr::null_mut(), 0.0, 0.1, 1), FMI2_ERROR);
        fmi2FreeInstance(c);
    }
    let log = LOG.lock().unwrap();
    assert!(
        log.iter().any(|m| m.contains("canGetAndSetFMUstate")),
        "{log:?}"
    );
    assert!(log.iter().any(|m| m.contains("fixed parameter")), "{log:?}");
    assert_eq!(
        unsafe { CStr::from_ptr(fmi2GetVersion()) }
            .to_str()
            .unwrap(),
        "2.0"
    );
}

#[test]
fn file_uris_are_decoded() {
    use hydroid_fmu::instance::uri_to_path;
    let p = |s: &str| uri_to_path(s).map(|p| p.display().to_string());
    assert_eq!(p("file:///tmp/a%20b/res").unwrap(), "/tmp/a b/res");
    assert_eq!(p("file://localhost/tmp/x").unwrap(), "/tmp/x");
    assert_eq!(p("file:/tmp/x").unwrap(), "/tmp/x");
    assert!(p("http://example.com/x").is_err());
    assert!(p("file://server/x").is_err());
    assert!(p("file:///tmp/%zz").is_err());
}

/// The library as cargo built it (the cdylib beside this test's executable) defines exactly
/// the FMI functions `hydroid export fmu` checks a library for, and passes that check: the
/// list of app::export::fmu::library and fmu/src/api.rs cannot drift apart.
#[test]
fn the_built_library_defines_the_functions_the_export_checks_for() {
    use hydroid::app::export::fmu::library;
    let deps = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .to_path_buf();
    let built = [
        deps.join("libhydroid_fmu.so"),
        deps.join("../libhydroid_fmu.so"),
    ];
    let Some(path) = built.iter().find(|p| p.is_file()) else {
        // cargo builds the cdylib with the rlib the tests link; say so if it ever does not
        panic!("no libhydroid_fmu.so beside {}", deps.display());
    };
    let bytes = std::fs::read(path).unwrap();
    library::check(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut fmi: Vec<String> = library::defined_functions(&bytes)
        .unwrap()
        .into_iter()
        .filter(|n| n.starts_with("fmi2"))
        .collect();
    fmi.sort();
    let mut want = library::FMI2_CO_SIMULATION_FUNCTIONS.to_vec();
    want.sort();
    assert_eq!(fmi, want);
}
