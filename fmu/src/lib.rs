//! The shared library of hydroid's exported FMUs (docs/fmu.md): the FMI 2.0 co-simulation C
//! API, written from the FMI 2.0.x standard (chapter 2.1: types, status, callbacks, common
//! functions; chapter 4.2: co-simulation functions). An instance reads the FMU's
//! resources/model.json at fmi2Instantiate and steps the model with hydroid's RK4, the
//! inputs held over each communication step ([`instance`]).
//!
//! Nothing panics across the C boundary: every function runs its body under
//! `catch_unwind`, and an error or a panic is reported through the importer's logger and
//! returned as fmi2Error (a null component from fmi2Instantiate). Model exchange, FMU
//! states (canGetAndSetFMUstate = false), directional derivatives and input or output
//! derivatives are not offered and return fmi2Error.

// the FMI names its functions in camel case
#![allow(non_snake_case)]

pub mod instance;

use instance::{Instance, Phase};
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// fmi2Status (FMI 2.0 section 2.1.3).
pub type Fmi2Status = c_int;
/// fmi2OK.
pub const FMI2_OK: Fmi2Status = 0;
/// fmi2Warning.
pub const FMI2_WARNING: Fmi2Status = 1;
/// fmi2Discard.
pub const FMI2_DISCARD: Fmi2Status = 2;
/// fmi2Error.
pub const FMI2_ERROR: Fmi2Status = 3;
/// fmi2Fatal.
pub const FMI2_FATAL: Fmi2Status = 4;

/// fmi2Boolean (an int: fmi2True = 1, fmi2False = 0).
pub type Fmi2Boolean = c_int;
/// fmi2ValueReference.
pub type Fmi2ValueReference = c_uint;
/// fmi2Component: the instance, an opaque pointer for the importer.
pub type Fmi2Component = *mut c_void;
/// fmi2Type: fmi2ModelExchange = 0, fmi2CoSimulation = 1.
pub const FMI2_COSIMULATION: c_int = 1;
/// fmi2StatusKind fmi2LastSuccessfulTime.
pub const FMI2_LAST_SUCCESSFUL_TIME: c_int = 2;
/// fmi2StatusKind fmi2Terminated.
pub const FMI2_TERMINATED: c_int = 3;

/// fmi2CallbackLogger: (componentEnvironment, instanceName, status, category, message, ...),
/// the message a printf format.
pub type Fmi2Logger =
    unsafe extern "C" fn(*mut c_void, *const c_char, Fmi2Status, *const c_char, *const c_char, ...);

/// fmi2CallbackFunctions (FMI 2.0 section 2.1.5).
#[repr(C)]
pub struct Fmi2CallbackFunctions {
    /// The logger.
    pub logger: Option<Fmi2Logger>,
    /// allocateMemory (not used: canNotUseMemoryManagementFunctions = true).
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// freeMemory (not used).
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// stepFinished (not used: fmi2DoStep never returns fmi2Pending).
    pub step_finished: Option<unsafe extern "C" fn(*mut c_void, Fmi2Status)>,
    /// The importer's pointer handed back to the logger.
    pub component_environment: *mut c_void,
}

/// An instance with what it needs to talk to its importer.
pub struct Component {
    name: CString,
    logger: Option<Fmi2Logger>,
    environment: *mut c_void,
    logging_on: bool,
    /// The model and its state.
    pub inner: Instance,
}

/// Sends `message` to a logger (as the argument of a "%s" format, so that a '%' in it is
/// text).
fn log_to(
    logger: Option<Fmi2Logger>,
    env: *mut c_void,
    name: &CStr,
    status: Fmi2Status,
    message: &str,
) {
    let Some(logger) = logger else { return };
    let category = if status >= FMI2_ERROR {
        c"logStatusError"
    } else {
        c"logAll"
    };
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    // SAFETY: the importer gave the logger for this use; every pointer is a valid C string
    // for the call's duration.
    unsafe {
        logger(
            env,
            name.as_ptr(),
            status,
            category.as_ptr(),
            c"%s".as_ptr(),
            text.as_ptr(),
        )
    };
}

impl Component {
    fn log(&self, status: Fmi2Status, message: &str) {
        if status >= FMI2_WARNING || self.logging_on {
            log_to(self.logger, self.environment, &self.name, status, message);
        }
    }
}

/// Runs `body` on the component `c`, catching a panic; an error is logged and returned as
/// fmi2Error.
fn with(
    c: Fmi2Component,
    what: &str,
    body: impl FnOnce(&mut Component) -> Result<Fmi2Status, String>,
) -> Fmi2Status {
    if c.is_null() {
        return FMI2_ERROR;
    }
    // SAFETY: a non-null component is one fmi2Instantiate returned and fmi2FreeInstance has
    // not freed (the importer's obligation, FMI 2.0 section 2.1.5).
    let comp = unsafe { &mut *(c as *mut Component) };
    match catch_unwind(AssertUnwindSafe(|| body(comp))) {
        Ok(Ok(status)) => status,
        Ok(Err(message)) => {
            comp.log(FMI2_ERROR, &format!("{what}: {message}"));
            FMI2_ERROR
        }
        Err(_) => {
            comp.log(
                FMI2_FATAL,
                &format!("{what}: internal error (a panic) in hydroid"),
            );
            comp.inner.phase = Phase::Failed;
            FMI2_ERROR
        }
    }
}

/// A C string argument, or an error naming it.
///
/// # Safety
/// `p` is null or a valid C string.
unsafe fn text<'a>(p: *const c_char, what: &str) -> Result<&'a str, String> {
    if p.is_null() {
        return Err(format!("{what} is null"));
    }
    // SAFETY: the caller's promise
    unsafe { CStr::from_ptr(p) }
        .to_str()
        .map_err(|_| format!("{what} is not UTF-8"))
}

/// A slice from a C array of `n` elements (empty for n = 0, whatever the pointer).
///
/// # Safety
/// `p` points to `n` valid elements when `n > 0`.
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err("a null array with a positive length".into());
    }
    // SAFETY: the caller's promise
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// A mutable slice from a C array of `n` elements.
///
/// # Safety
/// `p` points to `n` valid, writable elements when `n > 0`.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err("a null array with a positive length".into());
    }
    // SAFETY: the caller's promise
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

mod api;
pub use api::*;
