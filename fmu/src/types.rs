//! The C types of the FMI 2.0 interface (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`),
//! declared from the standard's text: the status and kind enumerations, the callbacks an
//! importer passes to `fmi2Instantiate`, and the scalar types.

use std::ffi::{c_char, c_int, c_uint, c_void};

/// `fmi2Component`: the instance, as the importer holds it.
pub type Component = *mut c_void;
/// `fmi2ComponentEnvironment`: the importer's pointer, passed back to its logger.
pub type ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate`: a snapshot, as the importer holds it.
pub type FmuState = *mut c_void;
/// `fmi2ValueReference`.
pub type ValueReference = c_uint;
/// `fmi2Real`.
pub type Real = f64;
/// `fmi2Integer`.
pub type Integer = c_int;
/// `fmi2Boolean` (`fmi2True` 1, `fmi2False` 0).
pub type Boolean = c_int;
/// `fmi2String`.
pub type FmiString = *const c_char;

/// `fmi2Status`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// `fmi2OK`.
    Ok = 0,
    /// `fmi2Warning`.
    Warning = 1,
    /// `fmi2Discard`.
    Discard = 2,
    /// `fmi2Error`.
    Error = 3,
    /// `fmi2Fatal`.
    Fatal = 4,
    /// `fmi2Pending`.
    Pending = 5,
}

/// `fmi2Type` as an integer (an importer may pass any value: checked, not trusted).
pub const CO_SIMULATION: c_int = 1;

/// `fmi2StatusKind` values.
pub mod status_kind {
    use std::ffi::c_int;
    /// `fmi2DoStepStatus`.
    pub const DO_STEP_STATUS: c_int = 0;
    /// `fmi2PendingStatus`.
    pub const PENDING_STATUS: c_int = 1;
    /// `fmi2LastSuccessfulTime`.
    pub const LAST_SUCCESSFUL_TIME: c_int = 2;
    /// `fmi2Terminated`.
    pub const TERMINATED: c_int = 3;
}

/// `fmi2CallbackLogger`: variadic, with a printf format; mbfx passes the message as the
/// format with every `%` doubled, and no further argument.
pub type Logger =
    unsafe extern "C" fn(ComponentEnvironment, FmiString, Status, FmiString, FmiString, ...);

/// `fmi2CallbackFunctions`.
#[repr(C)]
pub struct CallbackFunctions {
    /// `logger` (may be NULL: then nothing is logged).
    pub logger: Option<Logger>,
    /// `allocateMemory` (unused: the library allocates with Rust's allocator, as
    /// `canNotUseMemoryManagementFunctions` says).
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// `freeMemory` (unused).
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// `stepFinished` (unused: `fmi2DoStep` never returns `fmi2Pending`).
    pub step_finished: Option<unsafe extern "C" fn(ComponentEnvironment, Status)>,
    /// `componentEnvironment`.
    pub component_environment: ComponentEnvironment,
}
