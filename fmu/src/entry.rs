//! The FMI 2.0 functions every FMU exports (`fmi2FunctionTypes.h`, "common functions"):
//! version, logging, instantiation, the experiment, initialization, termination, reset,
//! and the getters and setters. Each checks its pointers through [`crate::guard`] and
//! runs under its panic guard; the FMU has Real variables only, so the Integer, Boolean
//! and String functions accept an empty list and refuse any value reference.

// The standard's names.
#![allow(non_snake_case)]

use crate::guard::{self, call, Handle, Sink};
use crate::instance::Instance;
use crate::types::{
    Boolean, CallbackFunctions, Component, FmiString, Integer, Real, Status, ValueReference,
    CO_SIMULATION,
};
use std::ffi::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// `fmi2GetTypesPlatform`: "default".
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

/// `fmi2GetVersion`: "2.0".
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// `fmi2SetDebugLogging`: debug messages on or off, for the categories named (all when
/// none is).
///
/// # Safety
/// `c` is a live instance; `categories` points to `n` C strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Component,
    logging_on: Boolean,
    n: usize,
    categories: *const FmiString,
) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2SetDebugLogging", |h| {
            if logging_on == 0 {
                h.debug = None;
                return Ok(Status::Ok);
            }
            let mut on = Vec::new();
            for &s in guard::slice(categories, n, "categories")? {
                on.push(guard::string(s, "a category")?.to_string());
            }
            h.debug = Some(on);
            Ok(Status::Ok)
        })
    }
}

/// `fmi2Instantiate`: reads the resources, checks the GUID; NULL on failure (logged).
///
/// # Safety
/// The strings are NUL-terminated or NULL; `functions` points to the importer's
/// callbacks, alive as long as the instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: FmiString,
    fmu_type: std::ffi::c_int,
    guid: FmiString,
    resource_location: FmiString,
    functions: *const CallbackFunctions,
    _visible: Boolean,
    logging_on: Boolean,
) -> Component {
    let made = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: non-NULL callbacks are the importer's struct (the caller's word).
        let callbacks = (!functions.is_null()).then(|| unsafe { &*functions });
        let sink = callbacks.map_or(
            Sink {
                logger: None,
                environment: std::ptr::null_mut(),
            },
            |f| Sink {
                logger: f.logger,
                environment: f.component_environment,
            },
        );
        // SAFETY: a NUL-terminated string or NULL (the caller's word).
        let name = unsafe { guard::string(instance_name, "instanceName") }
            .map(guard::text)
            .unwrap_or_else(|_| c"mbfx".to_owned());
        let fail = |m: String| {
            let message = format!("fmi2Instantiate: {m}");
            sink.log(&name, Status::Error, "logStatusError", &message);
        };
        let made = (|| {
            if fmu_type != CO_SIMULATION {
                return Err(format!(
                    "fmuType {fmu_type}: this FMU is for co-simulation only (fmi2CoSimulation)"
                ));
            }
            // SAFETY: NUL-terminated strings or NULL (the caller's word).
            let guid = unsafe { guard::string(guid, "fmuGUID") }?;
            // SAFETY: as above.
            let location = unsafe { guard::string(resource_location, "fmuResourceLocation") }?;
            let (settings, dataset) = crate::resources::read(location)?;
            Instance::new(settings, dataset, guid)
        })();
        match made {
            Ok(instance) => {
                let handle = Box::new(Handle {
                    name: name.clone(),
                    sink,
                    debug: (logging_on != 0).then(Vec::new),
                    instance,
                });
                Box::into_raw(handle).cast()
            }
            Err(m) => {
                fail(m);
                std::ptr::null_mut()
            }
        }
    }));
    made.unwrap_or(std::ptr::null_mut())
}

/// `fmi2FreeInstance` (NULL is accepted).
///
/// # Safety
/// `c` is NULL or a live instance, not used after this call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
    if c.is_null() {
        return;
    }
    // SAFETY: a Box fmi2Instantiate made, freed once (the caller's word).
    let handle = unsafe { Box::from_raw(c.cast::<Handle>()) };
    // Dropping runs mbfx's destructors: no unwind may reach the importer.
    let _ = catch_unwind(AssertUnwindSafe(move || drop(handle)));
}

/// `fmi2SetupExperiment`: the tolerance becomes the run's ERROR; the start time must be 0.
///
/// # Safety
/// `c` is a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Component,
    tolerance_defined: Boolean,
    tolerance: Real,
    start_time: Real,
    stop_time_defined: Boolean,
    stop_time: Real,
) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2SetupExperiment", |h| {
            h.instance.setup_experiment(
                (tolerance_defined != 0).then_some(tolerance),
                start_time,
                (stop_time_defined != 0).then_some(stop_time),
            )?;
            Ok(Status::Ok)
        })
    }
}

/// Declares a function of the instance alone: `fmi2X(c)`.
macro_rules! lifecycle {
    ($($name:ident => $method:ident: $doc:literal;)*) => {$(
        #[doc = $doc]
        ///
        /// # Safety
        /// `c` is a live instance.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(c: Component) -> Status {
            // SAFETY: the caller's word, as the function's.
            unsafe { call(c, stringify!($name), |h| h.instance.$method().map(|()| Status::Ok)) }
        }
    )*};
}

lifecycle! {
    fmi2EnterInitializationMode => enter_initialization:
        "`fmi2EnterInitializationMode`: the dataset is built and the inputs set on it.";
    fmi2ExitInitializationMode => exit_initialization:
        "`fmi2ExitInitializationMode`: stepping may start.";
    fmi2Terminate => terminate:
        "`fmi2Terminate`: the values stay readable.";
}

/// `fmi2Reset`: back to just instantiated, the inputs at their start values.
///
/// # Safety
/// `c` is a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: Component) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2Reset", |h| {
            h.instance.reset();
            Ok(Status::Ok)
        })
    }
}

/// `fmi2GetReal`.
///
/// # Safety
/// `c` is a live instance; `vr` and `value` point to `nvr` values.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut Real,
) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2GetReal", |h| {
            let refs = guard::slice(vr, nvr, "vr")?;
            let out = guard::slice_mut(value, nvr, "value")?;
            h.instance.get_real(refs, out).map(|()| Status::Ok)
        })
    }
}

/// `fmi2SetReal`: inputs only, holding from the current time.
///
/// # Safety
/// `c` is a live instance; `vr` and `value` point to `nvr` values.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *const Real,
) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2SetReal", |h| {
            let refs = guard::slice(vr, nvr, "vr")?;
            let values = guard::slice(value, nvr, "value")?;
            h.instance.set_real(refs, values).map(|()| Status::Ok)
        })
    }
}

/// Refuses every value reference of a type the FMU has no variable of.
fn none_of(kind: &str, n: usize) -> Result<Status, String> {
    match n {
        0 => Ok(Status::Ok),
        _ => Err(format!(
            "this FMU has no {kind} variables (its inputs and outputs are Real)"
        )),
    }
}

/// Declares the getters and setters of a type the FMU has none of.
macro_rules! no_variables {
    ($($name:ident($ty:ty, $kind:literal);)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: the FMU has no ", $kind, " variables.")]
        ///
        /// # Safety
        /// `c` is a live instance.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: Component,
            _vr: *const ValueReference,
            nvr: usize,
            _value: $ty,
        ) -> Status {
            // SAFETY: the caller's word, as the function's.
            unsafe { call(c, stringify!($name), |_| none_of($kind, nvr)) }
        }
    )*};
}

no_variables! {
    fmi2GetInteger(*mut Integer, "Integer");
    fmi2SetInteger(*const Integer, "Integer");
    fmi2GetBoolean(*mut Boolean, "Boolean");
    fmi2SetBoolean(*const Boolean, "Boolean");
    fmi2GetString(*mut FmiString, "String");
    fmi2SetString(*const FmiString, "String");
}
