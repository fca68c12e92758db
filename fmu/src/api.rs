//! The exported FMI 2.0 functions (FMI 2.0.x standard, sections 2.1.4 to 2.1.8 and 4.2).
//! Each is `unsafe extern "C"`: its pointer arguments must be as the standard describes
//! them (valid for the call, arrays of the given lengths), the standard's contract with the
//! importer, which is why no function repeats it in a `# Safety` section.
#![allow(clippy::missing_safety_doc)]

use super::*;
use std::ffi::c_double;

/// fmi2GetTypesPlatform: the standard's default types.
#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

/// fmi2GetVersion: "2.0".
#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// fmi2SetDebugLogging: the categories are ignored; logging on logs every call's notes.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    _n_categories: usize,
    _categories: *const *const c_char,
) -> Fmi2Status {
    with(c, "fmi2SetDebugLogging", |comp| {
        comp.logging_on = logging_on != 0;
        Ok(FMI2_OK)
    })
}

/// The instance of fmi2Instantiate's arguments.
unsafe fn instantiate(
    kind: c_int,
    guid: *const c_char,
    resources: *const c_char,
) -> Result<Instance, String> {
    if kind != FMI2_COSIMULATION {
        return Err("this FMU offers co-simulation only (fmuType must be fmi2CoSimulation)".into());
    }
    // SAFETY: the importer passes C strings (FMI 2.0 section 2.1.5)
    let guid = unsafe { text(guid, "fmuGUID") }?;
    let uri = unsafe { text(resources, "fmuResourceLocation") }?;
    let dir = instance::uri_to_path(uri)?;
    Instance::new(&dir, guid)
}

/// fmi2Instantiate: reads resources/model.json; null on any problem (logged).
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: *const c_char,
    fmu_type: c_int,
    fmu_guid: *const c_char,
    fmu_resource_location: *const c_char,
    functions: *const Fmi2CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    let (logger, environment) = if functions.is_null() {
        (None, std::ptr::null_mut())
    } else {
        // SAFETY: a non-null callback structure is valid for the call
        let f = unsafe { &*functions };
        (f.logger, f.component_environment)
    };
    let name = if instance_name.is_null() {
        CString::default()
    } else {
        // SAFETY: the importer passes a C string
        unsafe { CStr::from_ptr(instance_name) }.to_owned()
    };
    let made = catch_unwind(AssertUnwindSafe(|| unsafe {
        instantiate(fmu_type, fmu_guid, fmu_resource_location)
    }));
    let message = match made {
        Ok(Ok(inner)) => {
            let comp = Component {
                name,
                logger,
                environment,
                logging_on: logging_on != 0,
                inner,
            };
            comp.log(FMI2_OK, "instantiated");
            return Box::into_raw(Box::new(comp)) as Fmi2Component;
        }
        Ok(Err(m)) => m,
        Err(_) => "internal error (a panic) in hydroid".to_string(),
    };
    log_to(
        logger,
        environment,
        &name,
        FMI2_ERROR,
        &format!("fmi2Instantiate: {message}"),
    );
    std::ptr::null_mut()
}

/// fmi2FreeInstance.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    if !c.is_null() {
        // SAFETY: made by Box::into_raw in fmi2Instantiate, freed once (the importer's
        // obligation)
        let _ = catch_unwind(|| drop(unsafe { Box::from_raw(c as *mut Component) }));
    }
}

/// fmi2SetupExperiment: the start time; tolerance and stop time are not used (fixed-step
/// RK4).
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Fmi2Component,
    _tolerance_defined: Fmi2Boolean,
    _tolerance: c_double,
    start_time: c_double,
    _stop_time_defined: Fmi2Boolean,
    _stop_time: c_double,
) -> Fmi2Status {
    with(c, "fmi2SetupExperiment", |comp| {
        if comp.inner.phase != Phase::Instantiated {
            return Err("only allowed right after fmi2Instantiate or fmi2Reset".into());
        }
        if !start_time.is_finite() {
            return Err(format!("start time {start_time} is not finite"));
        }
        comp.inner.time = start_time;
        Ok(FMI2_OK)
    })
}

/// fmi2EnterInitializationMode.
#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2Status {
    with(c, "fmi2EnterInitializationMode", |comp| {
        if comp.inner.phase != Phase::Instantiated {
            return Err("only allowed after fmi2Instantiate or fmi2SetupExperiment".into());
        }
        comp.inner.phase = Phase::Initialization;
        Ok(FMI2_OK)
    })
}

/// fmi2ExitInitializationMode: the state starts at the initial-state parameters.
#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
    with(c, "fmi2ExitInitializationMode", |comp| {
        if comp.inner.phase != Phase::Initialization {
            return Err("call fmi2EnterInitializationMode first".into());
        }
        comp.inner.x = comp.inner.starts.clone();
        comp.inner.phase = Phase::Stepping;
        Ok(FMI2_OK)
    })
}

/// fmi2Terminate.
#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
    with(c, "fmi2Terminate", |comp| {
        comp.inner.phase = Phase::Terminated;
        Ok(FMI2_OK)
    })
}

/// fmi2Reset: back to the start values.
#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
    with(c, "fmi2Reset", |comp| {
        comp.inner.reset();
        Ok(FMI2_OK)
    })
}

/// fmi2GetReal.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut c_double,
) -> Fmi2Status {
    with(c, "fmi2GetReal", |comp| {
        // SAFETY: arrays of nvr elements (FMI 2.0 section 2.1.7)
        let (vr, value) = unsafe { (slice(vr, nvr)?, slice_mut(value, nvr)?) };
        for (r, v) in vr.iter().zip(value.iter_mut()) {
            *v = comp.inner.get(*r)?;
        }
        Ok(FMI2_OK)
    })
}

/// fmi2SetReal.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const c_double,
) -> Fmi2Status {
    with(c, "fmi2SetReal", |comp| {
        // SAFETY: arrays of nvr elements (FMI 2.0 section 2.1.7)
        let (vr, value) = unsafe { (slice(vr, nvr)?, slice(value, nvr)?) };
        for (r, v) in vr.iter().zip(value) {
            comp.inner.set(*r, *v)?;
        }
        Ok(FMI2_OK)
    })
}

/// The FMU has Real variables only: an Integer, Boolean or String access of no variable is
/// fine, of any is an error.
fn none_of(kind: &str, nvr: usize) -> Result<Fmi2Status, String> {
    if nvr == 0 {
        Ok(FMI2_OK)
    } else {
        Err(format!("this FMU has no {kind} variables"))
    }
}

macro_rules! no_variables {
    ($($name:ident, $kind:literal, $ptr:ty;)+) => {$(
        #[doc = concat!(stringify!($name), ": the FMU has no ", $kind, " variables.")]
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            c: Fmi2Component,
            _vr: *const Fmi2ValueReference,
            nvr: usize,
            _value: $ptr,
        ) -> Fmi2Status {
            with(c, stringify!($name), |_| none_of($kind, nvr))
        }
    )+};
}

no_variables! {
    fmi2GetInteger, "Integer", *mut c_int;
    fmi2SetInteger, "Integer", *const c_int;
    fmi2GetBoolean, "Boolean", *mut Fmi2Boolean;
    fmi2SetBoolean, "Boolean", *const Fmi2Boolean;
    fmi2GetString, "String", *mut *const c_char;
    fmi2SetString, "String", *const *const c_char;
}

/// What an unsupported function logs and returns.
fn unsupported(c: Fmi2Component, what: &str, why: &str) -> Fmi2Status {
    with(c, what, |_| Err(format!("not supported: {why}")))
}

const NO_STATE: &str = "this FMU cannot save and restore its state (canGetAndSetFMUstate = false)";
const NO_DERIVATIVES: &str = "this FMU gives no derivatives (providesDirectionalDerivative = \
                              false, canInterpolateInputs = false, maxOutputDerivativeOrder = 0)";

/// fmi2GetFMUstate: not supported.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Fmi2Component, _s: *mut *mut c_void) -> Fmi2Status {
    unsupported(c, "fmi2GetFMUstate", NO_STATE)
}

/// fmi2SetFMUstate: not supported.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Fmi2Component, _s: *mut c_void) -> Fmi2Status {
    unsupported(c, "fmi2SetFMUstate", NO_STATE)
}

/// fmi2FreeFMUstate: not supported.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Fmi2Component, _s: *mut *mut c_void) -> Fmi2Status {
    unsupported(c, "fmi2FreeFMUstate", NO_STATE)
}

/// fmi2SerializedFMUstateSize: not supported.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Fmi2Component,
    _s: *mut c_void,
    _size: *mut usize,
) -> Fmi2Status {
    unsupported(c, "fmi2SerializedFMUstateSize", NO_STATE)
}

/// fmi2SerializeFMUstate: not supported.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Fmi2Component,
    _s: *mut c_void,
    _bytes: *mut c_char,
    _size: usize,
) -> Fmi2Status {
    unsupported(c, "fmi2SerializeFMUstate", NO_STATE)
}

/// fmi2DeSerializeFMUstate: not supported.
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Fmi2Component,
    _bytes: *const c_char,
    _size: usize,
    _s: *mut *mut c_void,
) -> Fmi2Status {
    unsupported(c, "fmi2DeSerializeFMUstate", NO_STATE)
}

/// fmi2GetDirectionalDerivative: not supported.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Fmi2Component,
    _unknown: *const Fmi2ValueReference,
    _n_unknown: usize,
    _known: *const Fmi2ValueReference,
    _n_known: usize,
    _dv_known: *const c_double,
    _dv_unknown: *mut c_double,
) -> Fmi2Status {
    unsupported(c, "fmi2GetDirectionalDerivative", NO_DERIVATIVES)
}

/// fmi2SetRealInputDerivatives: not supported.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Fmi2Component,
    _vr: *const Fmi2ValueReference,
    _nvr: usize,
    _order: *const c_int,
    _value: *const c_double,
) -> Fmi2Status {
    unsupported(c, "fmi2SetRealInputDerivatives", NO_DERIVATIVES)
}

/// fmi2GetRealOutputDerivatives: not supported.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Fmi2Component,
    _vr: *const Fmi2ValueReference,
    _nvr: usize,
    _order: *const c_int,
    _value: *mut c_double,
) -> Fmi2Status {
    unsupported(c, "fmi2GetRealOutputDerivatives", NO_DERIVATIVES)
}

/// fmi2DoStep: integrates the communication step with the inputs held; never pending.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: Fmi2Component,
    current_communication_point: c_double,
    communication_step_size: c_double,
    _no_set_fmu_state_prior: Fmi2Boolean,
) -> Fmi2Status {
    with(c, "fmi2DoStep", |comp| {
        comp.inner
            .do_step(current_communication_point, communication_step_size)?;
        Ok(FMI2_OK)
    })
}

/// fmi2CancelStep: there is never a step to cancel (fmi2DoStep does not return
/// fmi2Pending).
#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
    unsupported(c, "fmi2CancelStep", "fmi2DoStep never returns fmi2Pending")
}

/// fmi2GetStatus: no asynchronous step, no status to ask for (fmi2Discard, section 4.2.3).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: Fmi2Component,
    _kind: c_int,
    _value: *mut Fmi2Status,
) -> Fmi2Status {
    with(c, "fmi2GetStatus", |_| Ok(FMI2_DISCARD))
}

/// fmi2GetRealStatus: fmi2LastSuccessfulTime, the time of the state.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut c_double,
) -> Fmi2Status {
    with(c, "fmi2GetRealStatus", |comp| {
        if kind != FMI2_LAST_SUCCESSFUL_TIME || value.is_null() {
            return Ok(FMI2_DISCARD);
        }
        // SAFETY: a non-null pointer to a double (FMI 2.0 section 4.2.3)
        unsafe { *value = comp.inner.time };
        Ok(FMI2_OK)
    })
}

/// fmi2GetIntegerStatus: none (fmi2Discard).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Fmi2Component,
    _kind: c_int,
    _value: *mut c_int,
) -> Fmi2Status {
    with(c, "fmi2GetIntegerStatus", |_| Ok(FMI2_DISCARD))
}

/// fmi2GetBooleanStatus: fmi2Terminated, always false (the FMU never asks to stop).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    with(c, "fmi2GetBooleanStatus", |_| {
        if kind != FMI2_TERMINATED || value.is_null() {
            return Ok(FMI2_DISCARD);
        }
        // SAFETY: a non-null pointer to an fmi2Boolean (FMI 2.0 section 4.2.3)
        unsafe { *value = 0 };
        Ok(FMI2_OK)
    })
}

/// fmi2GetStringStatus: none (fmi2Discard).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: Fmi2Component,
    _kind: c_int,
    _value: *mut *const c_char,
) -> Fmi2Status {
    with(c, "fmi2GetStringStatus", |_| Ok(FMI2_DISCARD))
}
