//! The FMI 3.0 C interface of the same two FMUs (fmi3Functions.h, FMI 3.0 standard
//! sections 2.3 and 4): every function a co-simulation FMU exports, next to the FMI 2.0
//! ones in `ffi2` (the names differ, so one library serves both versions).
//!
//! Nothing model-specific is here. An FMI 3.0 instance is the same `Instance` over the
//! same `Model`, instantiated as `FmiVersion::V3` so that its log names the FMI 3.0
//! functions that were called. Where an FMI 3.0 function does what an FMI 2.0 one does
//! (fmi3GetInt32 and fmi2GetInteger, the FMU-state functions, ...) it checks what FMI
//! 3.0 adds (`nValues`) and calls the same `Instance` method, through the same
//! version-neutral `boundary` as `ffi2`, never an FMI 2.0 function, so both versions
//! share one state machine and one set of checks. fmi3GetFloat64 and fmi3SetFloat64
//! also serve `time` and array variables, whose values `values3` maps onto the
//! instance's scalar accessors.
//!
//! Rooms: here instantiation, the mode changes and Event Mode; `values` the gets and
//! sets (`values3` what a Float64 request stands for); `state` the FMU-state functions;
//! `step` fmi3DoStep and the functions of capabilities these FMUs do not have.
//!
//! Events (FMI 3.0 section 4.2): both FMUs have Event Mode (`hasEventMode = true`):
//! with eventModeUsed, fmi3ExitInitializationMode enters it, and fmi3EnterEventMode,
//! fmi3UpdateDiscreteStates and fmi3EnterStepMode drive it (`Instance`, `Mode::EventMode`).
//! StickSlipBeam also returns early (`mightReturnEarlyFromDoStep = true`): with
//! earlyReturnAllowed, fmi3DoStep ends at the end of the internal step in which the
//! contact switched between stick and slip.
//!
//! What FMI 3.0 co-simulation offers beyond FMI 2.0 and these FMUs do not
//! (modelDescription.xml says so with its capability flags), returns fmi3Error with
//! the reason logged: intermediate update, clocks, configuration mode, adjoint derivatives
//! (and StickSlipBeam's directional derivatives; NeuralFriction's are in `derivatives`), output derivatives,
//! per-element dependencies, and the Model Exchange and Scheduled Execution interfaces.
//! Value types without variables (Float32, Int8, ..., Binary, Clock) accept empty
//! requests and refuse any value reference.

#![allow(non_snake_case, non_camel_case_types)]

mod derivatives;
mod state;
mod step;
mod types;
mod values;
pub mod values3;

pub use derivatives::*;
pub use state::*;
pub use step::*;
pub use types::*;
pub use values::*;

use crate::boundary::logger::{Callback, ImporterLogger, Message};
use crate::boundary::{
    self, component_at, each, exported_model, into_pointer, mode_change, new_component,
    new_exported_component, null_argument, status, text, unknown_guid, with_component,
};
use crate::instance::{EventOptions, FmiVersion, Status};
use crate::FmuKind;
use libc::size_t;
use std::ffi::{c_char, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

impl Callback for fmi3LogMessageCallback {
    /// FMI 3.0's callback takes the message as a plain string (no format, no instance
    /// name).
    unsafe fn deliver(self, environment: *mut c_void, message: &Message) {
        // SAFETY: the caller's obligation: the importer's callback of this signature for
        // this environment; the strings are NUL-terminated.
        unsafe {
            self(
                environment,
                message.status as fmi3Status,
                message.category.as_ptr(),
                message.text.as_ptr(),
            )
        }
    }
}

/// The folder named by resourcePath, or why it cannot be used. FMI 3.0 (section 2.3.1,
/// fmi3InstantiateXXX) passes "the absolute file path (with a trailing file separator)
/// of the resources directory", a path, not FMI 2.0's URI. A `file:` URI is refused
/// with that reason rather than read as a relative path named "file:".
pub fn resource_path(path: &str) -> Result<PathBuf, String> {
    let refuse = |why: &str| format!("resourcePath \"{path}\" {why}");
    if path.starts_with("file:") {
        return Err(refuse(
            "is a URI; FMI 3.0 passes the resources directory as an absolute file path",
        ));
    }
    let folder = PathBuf::from(path);
    if !folder.is_absolute() {
        return Err(refuse("is not an absolute path"));
    }
    Ok(folder)
}

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; `categories` is NULL or `nCategories` pointers, each NULL or
/// NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: size_t,
    categories: *const fmi3String,
) -> fmi3Status {
    // SAFETY: the importer's obligations above.
    unsafe {
        boundary::set_debug_logging(
            instance,
            "fmi3SetDebugLogging",
            is_true(loggingOn),
            nCategories,
            categories,
        )
    }
}

/// Logs why an instantiation failed, through the importer's callback; a panic while
/// logging is caught (no panic crosses extern "C"), and the answer is NULL either way.
///
/// # Safety
///
/// `logMessage` is None or a callback with fmi3LogMessageCallback's signature that may
/// be called with `environment`.
unsafe fn refuse_instantiation(
    logMessage: Option<fmi3LogMessageCallback>,
    environment: fmi3InstanceEnvironment,
    call: &str,
    reason: &str,
) -> fmi3Instance {
    // SAFETY: the caller's obligation on `logMessage` and `environment`.
    let logger = unsafe { ImporterLogger::new(logMessage, environment, "") };
    let _ = catch_unwind(AssertUnwindSafe(|| {
        logger.log(
            Status::Error,
            "logStatusError",
            &format!("{call}: {reason}"),
        )
    }));
    std::ptr::null_mut()
}

/// # Safety
///
/// `logMessage` is NULL or a callback with fmi3LogMessageCallback's signature that may
/// be called with `instanceEnvironment`; no other argument is read.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
) -> fmi3Instance {
    // SAFETY: the importer's obligation on `logMessage` above.
    unsafe {
        refuse_instantiation(
            logMessage,
            instanceEnvironment,
            "fmi3InstantiateModelExchange",
            "this FMU supports co-simulation only (no <ModelExchange> in modelDescription.xml)",
        )
    }
}

/// # Safety
///
/// `logMessage` is NULL or a callback with fmi3LogMessageCallback's signature that may
/// be called with `instanceEnvironment`; no other argument is read.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _clockUpdate: Option<fmi3ClockUpdateCallback>,
    _lockPreemption: Option<fmi3LockPreemptionCallback>,
    _unlockPreemption: Option<fmi3UnlockPreemptionCallback>,
) -> fmi3Instance {
    // SAFETY: the importer's obligation on `logMessage` above.
    unsafe {
        refuse_instantiation(
            logMessage,
            instanceEnvironment,
            "fmi3InstantiateScheduledExecution",
            "this FMU supports co-simulation only (no <ScheduledExecution> in modelDescription.xml)",
        )
    }
}

/// # Safety
///
/// Every string argument is NULL or NUL-terminated; `logMessage` is NULL or a callback
/// with fmi3LogMessageCallback's signature that may be called with
/// `instanceEnvironment` as long as the instance lives. `_requiredIntermediateVariables`
/// is never read.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    nRequiredIntermediateVariables: size_t,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _intermediateUpdate: Option<fmi3IntermediateUpdateCallback>,
) -> fmi3Instance {
    const CALL: &str = "fmi3InstantiateCoSimulation";
    let result = catch_unwind(AssertUnwindSafe(|| {
        let refuse = |reason: String| {
            // SAFETY: the importer's obligation on `logMessage` above.
            unsafe { refuse_instantiation(logMessage, instanceEnvironment, CALL, &reason) }
        };
        // SAFETY: NULL or NUL-terminated, the importer's obligation.
        let name = unsafe { text(instanceName) }.unwrap_or_default();
        if name.is_empty() {
            return refuse("instanceName must be a non-empty string".into());
        }
        // Both FMUs have Event Mode, and an FMU that never returns early (NeuralFriction)
        // honours earlyReturnAllowed trivially.
        let events = EventOptions {
            event_mode_used: is_true(eventModeUsed),
            early_return_allowed: is_true(earlyReturnAllowed),
        };
        if nRequiredIntermediateVariables != 0 {
            return refuse(format!(
                "{nRequiredIntermediateVariables} intermediate variables requested, but this FMU provides no intermediate update (providesIntermediateUpdate = false)"
            ));
        }
        // SAFETY: NULL or NUL-terminated, the importer's obligation.
        let token = unsafe { text(instantiationToken) }.unwrap_or_default();
        let kind = FmuKind::from_guid(&token);
        // SAFETY: NULL or NUL-terminated, the importer's obligation.
        let resources = match unsafe { text(resourcePath) }.as_deref().map(resource_path) {
            None => None,
            Some(Ok(dir)) => Some(dir),
            Some(Err(reason)) if kind.is_some() => return refuse(reason),
            Some(Err(_)) => return refuse(unknown_guid("instantiationToken", &token)),
        };
        // SAFETY: the importer's obligation: its callback may be called with its
        // environment.
        let logger = unsafe { ImporterLogger::new(logMessage, instanceEnvironment, &name) };
        let Some(kind) = kind else {
            // Not a built-in FMU: an exported one, if resources/ holds its export.
            let exported = match exported_model("instantiationToken", &token, resources) {
                Ok(exported) => exported,
                Err(reason) => return refuse(reason),
            };
            return new_exported_component(
                FmiVersion::V3,
                &name,
                exported,
                &token,
                is_true(loggingOn),
                logger.into_logger(),
            )
            .map_or(std::ptr::null_mut(), |mut c| {
                each!(&mut c.instance, i => i.set_events(events));
                into_pointer(c)
            });
        };
        new_component(
            FmiVersion::V3,
            kind,
            &name,
            resources,
            is_true(loggingOn),
            logger.into_logger(),
        )
        .map_or(std::ptr::null_mut(), |mut c| {
            each!(&mut c.instance, i => i.set_events(events));
            into_pointer(c)
        })
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// # Safety
///
/// `instance` is NULL or an instance fmi3InstantiateCoSimulation returned, not freed
/// before, and not used by any call during or after this one.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    // SAFETY: the importer's obligation on `instance` above.
    unsafe { boundary::free_component(instance) }
}

/// fmi3EnterInitializationMode: FMI 2.0's fmi2SetupExperiment and
/// fmi2EnterInitializationMode in one call. The tolerance is not used: the step size is
/// a parameter.
///
/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    // SAFETY: the importer's obligation on `instance` above.
    let component = unsafe { component_at(instance) };
    with_component(component, "fmi3EnterInitializationMode", |component| {
        let stop = is_true(stopTimeDefined).then_some(stopTime);
        each!(&mut component.instance, i => status(
            i.setup_experiment(startTime, stop)
                .and_then(|()| i.enter_initialization_mode())
        ))
    })
}

mode_change!(
    /// With eventModeUsed into Event Mode, otherwise straight to Step Mode (FMI 3.0, 4.2).
    fmi3ExitInitializationMode => exit_initialization_mode
);
mode_change!(fmi3Terminate => terminate);

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile.
#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
    // SAFETY: the importer's obligation on `instance` above.
    boundary::reset(unsafe { component_at(instance) }, "fmi3Reset")
}

mode_change!(
    /// fmi3EnterEventMode: from Step Mode into Event Mode (only with eventModeUsed).
    fmi3EnterEventMode => enter_event_mode
);
mode_change!(
    /// fmi3EnterStepMode: from Event Mode back into Step Mode.
    fmi3EnterStepMode => enter_step_mode
);

/// fmi3UpdateDiscreteStates: settles at once (no discrete state of these models depends
/// on the inputs set in Event Mode), with no next time event.
///
/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; each output pointer is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
    instance: fmi3Instance,
    discreteStatesNeedUpdate: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
    valuesOfContinuousStatesChanged: *mut fmi3Boolean,
    nextEventTimeDefined: *mut fmi3Boolean,
    nextEventTime: *mut fmi3Float64,
) -> fmi3Status {
    const CALL: &str = "fmi3UpdateDiscreteStates";
    // SAFETY: the importer's obligation on `instance` above.
    let component = unsafe { component_at(instance) };
    with_component(component, CALL, |component| {
        if discreteStatesNeedUpdate.is_null()
            || terminateSimulation.is_null()
            || nominalsOfContinuousStatesChanged.is_null()
            || valuesOfContinuousStatesChanged.is_null()
            || nextEventTimeDefined.is_null()
            || nextEventTime.is_null()
        {
            return null_argument(component, CALL, "an output argument");
        }
        let result = each!(&mut component.instance, i => i.update_discrete_states());
        let update = result.unwrap_or_default();
        // SAFETY: NULL was refused above; each writable by the importer's obligation.
        unsafe {
            *discreteStatesNeedUpdate = from_bool(update.discrete_states_need_update);
            *terminateSimulation = from_bool(update.terminate_simulation);
            *nominalsOfContinuousStatesChanged =
                from_bool(update.nominals_of_continuous_states_changed);
            *valuesOfContinuousStatesChanged =
                from_bool(update.values_of_continuous_states_changed);
            *nextEventTimeDefined = from_bool(update.next_event_time.is_some());
            *nextEventTime = update.next_event_time.unwrap_or(0.0);
        }
        status(result.map(|_| ()))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resource_paths_are_paths() {
        assert_eq!(
            resource_path("/tmp/a b/Größe/").ok(),
            Some(PathBuf::from("/tmp/a b/Größe/"))
        );
        // FMI 2.0's URI is refused with the reason, not read as a relative path.
        let uri = resource_path("file:///tmp/x/resources/").unwrap_err();
        assert!(uri.contains("is a URI"), "{uri}");
        let relative = resource_path("resources/").unwrap_err();
        assert!(relative.contains("not an absolute path"), "{relative}");
    }
}
