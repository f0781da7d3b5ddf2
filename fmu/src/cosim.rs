//! The FMI 2.0 co-simulation functions (`fmi2DoStep` and the status queries), the
//! FMU-state functions (snapshots kept in memory, not serialized) and the optional ones
//! this FMU declares it lacks (directional derivatives, input and output derivatives),
//! which refuse with a message.

// The standard's names.
#![allow(non_snake_case)]

use crate::guard::{self, call};
use crate::instance::{Phase, State};
use crate::types::{
    status_kind, Boolean, Component, FmiString, FmuState, Integer, Real, Status, ValueReference,
};
use std::ffi::c_int;

/// `fmi2DoStep`: integrates from `t` to `t + h` with the inputs as set.
///
/// # Safety
/// `c` is a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: Component,
    t: Real,
    h: Real,
    _no_set_fmu_state_prior: Boolean,
) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2DoStep", |i| {
            i.instance.do_step(t, h).map(|()| Status::Ok)
        })
    }
}

/// `fmi2CancelStep`: `fmi2DoStep` never returns `fmi2Pending`, so there is nothing to
/// cancel.
///
/// # Safety
/// `c` is a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: Component) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2CancelStep", |_| {
            Err("no step is pending: fmi2DoStep finishes before it returns".into())
        })
    }
}

/// Writes `value` through `out`, or an error when it is NULL.
///
/// # Safety
/// A non-NULL `out` is writable.
unsafe fn put<T>(out: *mut T, value: T) -> Result<Status, String> {
    // SAFETY: one writable value, or NULL (the caller's word).
    let out = unsafe { guard::slice_mut(out, 1, "value")? };
    out[0] = value;
    Ok(Status::Ok)
}

/// `fmi2GetStatus`: only `fmi2DoStepStatus` after `fmi2Pending` is defined, which never
/// happens here.
///
/// # Safety
/// `c` is a live instance; `value` is writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(c: Component, kind: c_int, _value: *mut Status) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2GetStatus", |_| {
            Err(format!(
                "status kind {kind}: fmi2DoStep never returns fmi2Pending, so no step status is pending"
            ))
        })
    }
}

/// `fmi2GetRealStatus`: `fmi2LastSuccessfulTime` is the model's time.
///
/// # Safety
/// `c` is a live instance; `value` is writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(c: Component, kind: c_int, value: *mut Real) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2GetRealStatus", |h| match kind {
            status_kind::LAST_SUCCESSFUL_TIME => put(value, h.instance.time()),
            _ => Err(format!("status kind {kind} is not a Real status")),
        })
    }
}

/// `fmi2GetIntegerStatus`: there is no Integer status.
///
/// # Safety
/// `c` is a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Component,
    kind: c_int,
    _value: *mut Integer,
) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2GetIntegerStatus", |_| {
            Err(format!(
                "status kind {kind}: FMI 2.0 defines no Integer status"
            ))
        })
    }
}

/// `fmi2GetBooleanStatus`: `fmi2Terminated` is false (the FMU never asks to stop).
///
/// # Safety
/// `c` is a live instance; `value` is writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Component,
    kind: c_int,
    value: *mut Boolean,
) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2GetBooleanStatus", |_| match kind {
            status_kind::TERMINATED => put(value, 0),
            _ => Err(format!("status kind {kind} is not a Boolean status")),
        })
    }
}

/// `fmi2GetStringStatus`: `fmi2PendingStatus` is only defined after `fmi2Pending`.
///
/// # Safety
/// `c` is a live instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: Component,
    kind: c_int,
    _value: *mut FmiString,
) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2GetStringStatus", |_| match kind {
            status_kind::PENDING_STATUS => {
                Err("no step is pending: fmi2DoStep finishes before it returns".into())
            }
            _ => Err(format!("status kind {kind} is not a String status")),
        })
    }
}

/// `fmi2GetFMUstate`: a snapshot in memory; `*state`, when not NULL, is one this
/// instance made, replaced.
///
/// # Safety
/// `c` is a live instance; `state` is writable and `*state` NULL or a live snapshot.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, state: *mut FmuState) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2GetFMUstate", |h| {
            let slot = guard::slice_mut(state, 1, "FMUstate")?;
            let snapshot = Box::new(h.instance.state()?);
            if !slot[0].is_null() {
                // SAFETY: a snapshot this function made (the caller's word).
                drop(Box::from_raw(slot[0].cast::<State>()));
            }
            slot[0] = Box::into_raw(snapshot).cast();
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SetFMUstate`: back to a snapshot.
///
/// # Safety
/// `c` is a live instance; `state` a live snapshot of it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, state: FmuState) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2SetFMUstate", |h| {
            if state.is_null() {
                return Err("FMUstate is NULL".into());
            }
            if h.instance.phase == Phase::Instantiated {
                return Err(
                    "the model is not initialized: call fmi2EnterInitializationMode".into(),
                );
            }
            // SAFETY: a live snapshot fmi2GetFMUstate made (the caller's word).
            let snapshot = &*state.cast::<State>();
            h.instance.restore(snapshot).map(|()| Status::Ok)
        })
    }
}

/// `fmi2FreeFMUstate` (`*state` NULL is accepted); sets `*state` to NULL.
///
/// # Safety
/// `c` is a live instance; `state` is writable and `*state` NULL or a live snapshot.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, state: *mut FmuState) -> Status {
    // SAFETY: the caller's word, as the function's.
    unsafe {
        call(c, "fmi2FreeFMUstate", |_| {
            let slot = guard::slice_mut(state, 1, "FMUstate")?;
            if !slot[0].is_null() {
                // SAFETY: a snapshot fmi2GetFMUstate made, freed once (the caller's word).
                drop(Box::from_raw(slot[0].cast::<State>()));
                slot[0] = std::ptr::null_mut();
            }
            Ok(Status::Ok)
        })
    }
}

/// Declares a function the FMU says it lacks (`canSerializeFMUstate`,
/// `providesDirectionalDerivative`, `canInterpolateInputs`, `maxOutputDerivativeOrder`
/// are false or 0): it refuses with the capability's name.
macro_rules! lacking {
    ($($name:ident($($arg:ident: $ty:ty),*) => $why:literal;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: refused (", $why, ").")]
        ///
        /// # Safety
        /// `c` is a live instance.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(c: Component, $(_: $ty),*) -> Status {
            // SAFETY: the caller's word, as the function's.
            unsafe { call(c, stringify!($name), |_| Err(concat!("this FMU has ", $why).into())) }
        }
    )*};
}

lacking! {
    fmi2SerializedFMUstateSize(s: FmuState, size: *mut usize) =>
        "canSerializeFMUstate = false";
    fmi2SerializeFMUstate(s: FmuState, bytes: *mut std::ffi::c_char, size: usize) =>
        "canSerializeFMUstate = false";
    fmi2DeSerializeFMUstate(bytes: *const std::ffi::c_char, size: usize, s: *mut FmuState) =>
        "canSerializeFMUstate = false";
    fmi2GetDirectionalDerivative(
        unknown: *const ValueReference, n_unknown: usize, known: *const ValueReference,
        n_known: usize, dv_known: *const Real, dv_unknown: *mut Real
    ) => "providesDirectionalDerivative = false";
    fmi2SetRealInputDerivatives(
        vr: *const ValueReference, nvr: usize, order: *const Integer, value: *const Real
    ) => "canInterpolateInputs = false";
    fmi2GetRealOutputDerivatives(
        vr: *const ValueReference, nvr: usize, order: *const Integer, value: *mut Real
    ) => "maxOutputDerivativeOrder = 0";
}
