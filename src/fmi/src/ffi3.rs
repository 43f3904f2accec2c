//! The FMI 3.0 C interface of the same two FMUs (fmi3Functions.h, FMI 3.0 standard
//! sections 2.3 and 4): every function a co-simulation FMU exports, next to the FMI 2.0
//! ones in `ffi` (the names differ, so one library serves both versions).
//!
//! Nothing model-specific is here. An FMI 3.0 instance is the same `Instance` over the
//! same `Model`, marked `FmiVersion::V3` so that its log names FMI 3.0 functions; where
//! an FMI 3.0 function does what an FMI 2.0 one does (fmi3GetInt32 and fmi2GetInteger,
//! the FMU-state functions, ...) it checks what FMI 3.0 adds (`nValues`) and calls the
//! FMI 2.0 function, so both versions share one state machine and one set of checks.
//! fmi3GetFloat64 and fmi3SetFloat64 also serve `time` and array variables, whose
//! values `values3` maps onto the same instance's FMI 2.0 accessors.
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
//! the reason logged: intermediate update, clocks, configuration mode, directional and adjoint derivatives, output derivatives,
//! per-element dependencies, and the Model Exchange and Scheduled Execution interfaces.
//! Value types without variables (Float32, Int8, ..., Binary, Clock) accept empty
//! requests and refuse any value reference.

#![allow(non_snake_case, non_camel_case_types, clippy::missing_safety_doc)]

use crate::ffi::{
    self, each, fail, new_component, null_argument, slice, slice_mut, status, text, unknown_guid,
    unsupported, with_component, Component,
};
use crate::instance::{Call, EventOptions, FmiVersion, Logger, Status};
use crate::values3;
use crate::FmuKind;
use libc::size_t;
use std::ffi::{c_char, c_int, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

pub type fmi3Instance = *mut c_void;
pub type fmi3InstanceEnvironment = *mut c_void;
pub type fmi3FMUState = *mut c_void;
pub type fmi3ValueReference = u32;
pub type fmi3Float32 = f32;
pub type fmi3Float64 = f64;
pub type fmi3Int8 = i8;
pub type fmi3UInt8 = u8;
pub type fmi3Int16 = i16;
pub type fmi3UInt16 = u16;
pub type fmi3Int32 = i32;
pub type fmi3UInt32 = u32;
pub type fmi3Int64 = i64;
pub type fmi3UInt64 = u64;
/// C99 `bool` (fmi3PlatformTypes.h): one byte. Read from the importer as a byte, so
/// that a value other than 0 or 1 is not undefined behaviour here.
pub type fmi3Boolean = bool;
pub type fmi3Char = c_char;
pub type fmi3String = *const fmi3Char;
pub type fmi3Byte = u8;
pub type fmi3Binary = *const fmi3Byte;
pub type fmi3Clock = bool;
pub type fmi3Status = c_int;
pub type fmi3DependencyKind = c_int;
pub type fmi3IntervalQualifier = c_int;

pub type fmi3LogMessageCallback =
    unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String);
pub type fmi3IntermediateUpdateCallback = unsafe extern "C" fn(
    fmi3InstanceEnvironment,
    fmi3Float64,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Float64,
);
pub type fmi3ClockUpdateCallback = unsafe extern "C" fn(fmi3InstanceEnvironment);
pub type fmi3LockPreemptionCallback = unsafe extern "C" fn();
pub type fmi3UnlockPreemptionCallback = unsafe extern "C" fn();

/// The importer's fmi3LogMessageCallback with its environment. FMI 3.0 passes the
/// message as a plain string (no format, no instance name).
struct Logger3 {
    callback: Option<fmi3LogMessageCallback>,
    environment: fmi3InstanceEnvironment,
}

// The raw environment pointer is only handed back to the importer's own callback.
unsafe impl Send for Logger3 {}

impl Logger3 {
    fn log(&self, status: Status, category: &str, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        // Messages written before the instance knows its version (Instance::new) name
        // FMI 2.0 functions.
        let category = ffi::c_string(category);
        let message = ffi::c_string(&FmiVersion::V3.rename(message));
        // SAFETY: the importer supplied the callback for exactly this signature.
        unsafe {
            callback(
                self.environment,
                status as fmi3Status,
                category.as_ptr(),
                message.as_ptr(),
            )
        };
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

#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: size_t,
    categories: *const fmi3String,
) -> fmi3Status {
    unsafe { ffi::fmi2SetDebugLogging(instance, c_int::from(loggingOn), nCategories, categories) }
}

/// Logs why an instantiation failed, through the importer's callback.
unsafe fn refuse_instantiation(
    logMessage: Option<fmi3LogMessageCallback>,
    environment: fmi3InstanceEnvironment,
    call: &str,
    reason: &str,
) -> fmi3Instance {
    let logger = Logger3 {
        callback: logMessage,
        environment,
    };
    logger.log(
        Status::Error,
        "logStatusError",
        &format!("{call}: {reason}"),
    );
    std::ptr::null_mut()
}

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
    unsafe {
        refuse_instantiation(
            logMessage,
            instanceEnvironment,
            "fmi3InstantiateModelExchange",
            "this FMU supports co-simulation only (no <ModelExchange> in modelDescription.xml)",
        )
    }
}

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
    unsafe {
        refuse_instantiation(
            logMessage,
            instanceEnvironment,
            "fmi3InstantiateScheduledExecution",
            "this FMU supports co-simulation only (no <ScheduledExecution> in modelDescription.xml)",
        )
    }
}

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
        let refuse = |reason: String| unsafe {
            refuse_instantiation(logMessage, instanceEnvironment, CALL, &reason)
        };
        let name = unsafe { text(instanceName) }.unwrap_or_default();
        if name.is_empty() {
            return refuse("instanceName must be a non-empty string".into());
        }
        // Both FMUs have Event Mode, and an FMU that never returns early (NeuralFriction)
        // honours earlyReturnAllowed trivially.
        let events = EventOptions {
            event_mode_used: eventModeUsed,
            early_return_allowed: earlyReturnAllowed,
        };
        if nRequiredIntermediateVariables != 0 {
            return refuse(format!(
                "{nRequiredIntermediateVariables} intermediate variables requested, but this FMU provides no intermediate update (providesIntermediateUpdate = false)"
            ));
        }
        let token = unsafe { text(instantiationToken) }.unwrap_or_default();
        let Some(kind) = FmuKind::from_guid(&token) else {
            return refuse(unknown_guid(&token).replacen("GUID", "instantiationToken", 1));
        };
        let resources = match unsafe { text(resourcePath) }.as_deref().map(resource_path) {
            None => None,
            Some(Ok(dir)) => Some(dir),
            Some(Err(reason)) => return refuse(reason),
        };
        let logger = Logger3 {
            callback: logMessage,
            environment: instanceEnvironment,
        };
        let boxed_logger: Logger =
            Box::new(move |status, category, message| logger.log(status, category, message));
        new_component(
            kind,
            &name,
            resources,
            loggingOn,
            boxed_logger,
            FmiVersion::V3,
        )
        .map_or(std::ptr::null_mut(), |mut c| {
            each!(&mut c.instance, i => i.set_events(events));
            Box::into_raw(Box::new(c)) as fmi3Instance
        })
    }));
    result.unwrap_or(std::ptr::null_mut())
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    unsafe { ffi::fmi2FreeInstance(instance) }
}

/// fmi3EnterInitializationMode: fmi2SetupExperiment and fmi2EnterInitializationMode in
/// one call. The tolerance is not used: the step size is a parameter.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    unsafe {
        with_component(instance, "fmi3EnterInitializationMode", |component| {
            let stop = stopTimeDefined.then_some(stopTime);
            each!(&mut component.instance, i => status(
                i.setup_experiment(startTime, stop)
                    .and_then(|()| i.enter_initialization_mode())
            ))
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
    // With eventModeUsed into Event Mode, otherwise straight to Step Mode (FMI 3.0, 4.2).
    unsafe { ffi::fmi2ExitInitializationMode(instance) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
    unsafe { ffi::fmi2Terminate(instance) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
    unsafe { ffi::fmi2Reset(instance) }
}

/// FMI 3.0 passes the number of values besides the number of value references; for
/// scalar variables they must be equal.
fn values_match(component: &mut Component, call: &str, nvr: size_t, nValues: size_t) -> bool {
    if nvr == nValues {
        return true;
    }
    fail(
        component,
        call,
        &format!(
            "nValues = {nValues}, but {nvr} value references of scalar variables need {nvr} values"
        ),
    );
    false
}

/// Runs an FMI 2.0 function after checking `nValues` (the value types are the same C
/// types in both versions).
macro_rules! via_fmi2 {
    ($name:ident, $fmi2:path, $ptr:ty) => {
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            values: $ptr,
            nValues: size_t,
        ) -> fmi3Status {
            unsafe {
                if nValueReferences != nValues {
                    return with_component(instance, stringify!($name), |component| {
                        values_match(component, stringify!($name), nValueReferences, nValues);
                        Status::Error
                    });
                }
                $fmi2(instance, valueReferences, nValueReferences, values)
            }
        }
    };
}

/// fmi3GetFloat64: besides scalars, `time` and array variables, whose values take more
/// than one slot of `values` (`values3`), so nValues is checked there.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *mut fmi3Float64,
    nValues: size_t,
) -> fmi3Status {
    const CALL: &str = "fmi3GetFloat64";
    unsafe {
        with_component(instance, CALL, |component| {
            let (Some(vrs), Some(out)) = (
                slice(valueReferences, nValueReferences),
                slice_mut(values, nValues),
            ) else {
                return null_argument(component, CALL, "valueReferences or values");
            };
            status(each!(&mut component.instance, i => values3::get(i, vrs, out)))
        })
    }
}

/// fmi3SetFloat64: as [`fmi3GetFloat64`]; `time` cannot be set.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *const fmi3Float64,
    nValues: size_t,
) -> fmi3Status {
    const CALL: &str = "fmi3SetFloat64";
    unsafe {
        with_component(instance, CALL, |component| {
            let (Some(vrs), Some(values)) = (
                slice(valueReferences, nValueReferences),
                slice(values, nValues),
            ) else {
                return null_argument(component, CALL, "valueReferences or values");
            };
            status(each!(&mut component.instance, i => values3::set(i, vrs, values)))
        })
    }
}
via_fmi2!(fmi3GetInt32, ffi::fmi2GetInteger, *mut fmi3Int32);
via_fmi2!(fmi3SetInt32, ffi::fmi2SetInteger, *const fmi3Int32);
via_fmi2!(fmi3GetString, ffi::fmi2GetString, *mut fmi3String);
via_fmi2!(fmi3SetString, ffi::fmi2SetString, *const fmi3String);

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBoolean(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *mut fmi3Boolean,
    nValues: size_t,
) -> fmi3Status {
    const CALL: &str = "fmi3GetBoolean";
    unsafe {
        with_component(instance, CALL, |component| {
            if !values_match(component, CALL, nValueReferences, nValues) {
                return Status::Error;
            }
            let (Some(vrs), Some(out)) = (
                slice(valueReferences, nValueReferences),
                slice_mut(values, nValues),
            ) else {
                return null_argument(component, CALL, "valueReferences or values");
            };
            let mut read = vec![false; nValues];
            let result = each!(&mut component.instance, i => i.get_boolean(vrs, &mut read));
            if result.is_ok() {
                out.copy_from_slice(&read);
            }
            status(result)
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBoolean(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *const fmi3Boolean,
    nValues: size_t,
) -> fmi3Status {
    const CALL: &str = "fmi3SetBoolean";
    unsafe {
        with_component(instance, CALL, |component| {
            if !values_match(component, CALL, nValueReferences, nValues) {
                return Status::Error;
            }
            let (Some(vrs), Some(bytes)) = (
                slice(valueReferences, nValueReferences),
                slice(values as *const u8, nValues),
            ) else {
                return null_argument(component, CALL, "valueReferences or values");
            };
            let booleans: Vec<bool> = bytes.iter().map(|&b| b != 0).collect();
            status(each!(&mut component.instance, i => i.set_boolean(vrs, &booleans)))
        })
    }
}

/// A get or set of a value type that has no variables in these FMUs: legal in the
/// modes of `call` with no value references, an error naming the first one otherwise.
fn no_variables_of_type(
    component: &mut Component,
    name: &str,
    call: Call,
    vrs: *const fmi3ValueReference,
    nvr: size_t,
    type_name: &str,
) -> Status {
    if each!(&mut component.instance, i => i.check(call)).is_err() {
        return Status::Error;
    }
    if nvr == 0 {
        return Status::Ok;
    }
    // SAFETY: the importer passes nvr value references.
    let first = unsafe { slice(vrs, nvr) }.and_then(|v| v.first().copied());
    let which = first.map_or("NULL".into(), |vr| vr.to_string());
    fail(
        component,
        name,
        &format!("value reference {which} is not a {type_name} variable: this FMU has no {type_name} variables"),
    )
}

macro_rules! no_variables {
    ($get:ident, $set:ident, $c_type:ty, $type_name:literal) => {
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            _values: *mut $c_type,
            _nValues: size_t,
        ) -> fmi3Status {
            unsafe {
                with_component(instance, stringify!($get), |component| {
                    no_variables_of_type(
                        component,
                        stringify!($get),
                        Call::Get,
                        valueReferences,
                        nValueReferences,
                        $type_name,
                    )
                })
            }
        }

        #[no_mangle]
        pub unsafe extern "C" fn $set(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            _values: *const $c_type,
            _nValues: size_t,
        ) -> fmi3Status {
            unsafe {
                with_component(instance, stringify!($set), |component| {
                    no_variables_of_type(
                        component,
                        stringify!($set),
                        Call::Set,
                        valueReferences,
                        nValueReferences,
                        $type_name,
                    )
                })
            }
        }
    };
}

no_variables!(fmi3GetFloat32, fmi3SetFloat32, fmi3Float32, "Float32");
no_variables!(fmi3GetInt8, fmi3SetInt8, fmi3Int8, "Int8");
no_variables!(fmi3GetUInt8, fmi3SetUInt8, fmi3UInt8, "UInt8");
no_variables!(fmi3GetInt16, fmi3SetInt16, fmi3Int16, "Int16");
no_variables!(fmi3GetUInt16, fmi3SetUInt16, fmi3UInt16, "UInt16");
no_variables!(fmi3GetUInt32, fmi3SetUInt32, fmi3UInt32, "UInt32");
no_variables!(fmi3GetInt64, fmi3SetInt64, fmi3Int64, "Int64");
no_variables!(fmi3GetUInt64, fmi3SetUInt64, fmi3UInt64, "UInt64");

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _valueSizes: *mut size_t,
    _values: *mut fmi3Binary,
    _nValues: size_t,
) -> fmi3Status {
    unsafe {
        with_component(instance, "fmi3GetBinary", |component| {
            no_variables_of_type(
                component,
                "fmi3GetBinary",
                Call::Get,
                valueReferences,
                nValueReferences,
                "Binary",
            )
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _valueSizes: *const size_t,
    _values: *const fmi3Binary,
    _nValues: size_t,
) -> fmi3Status {
    unsafe {
        with_component(instance, "fmi3SetBinary", |component| {
            no_variables_of_type(
                component,
                "fmi3SetBinary",
                Call::Set,
                valueReferences,
                nValueReferences,
                "Binary",
            )
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetClock(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _values: *mut fmi3Clock,
) -> fmi3Status {
    unsafe {
        with_component(instance, "fmi3GetClock", |component| {
            no_variables_of_type(
                component,
                "fmi3GetClock",
                Call::Get,
                valueReferences,
                nValueReferences,
                "Clock",
            )
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetClock(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _values: *const fmi3Clock,
) -> fmi3Status {
    unsafe {
        with_component(instance, "fmi3SetClock", |component| {
            no_variables_of_type(
                component,
                "fmi3SetClock",
                Call::Set,
                valueReferences,
                nValueReferences,
                "Clock",
            )
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe { ffi::fmi2GetFMUstate(instance, FMUState) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    unsafe { ffi::fmi2SetFMUstate(instance, FMUState) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe { ffi::fmi2FreeFMUstate(instance, FMUState) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut size_t,
) -> fmi3Status {
    unsafe { ffi::fmi2SerializedFMUstateSize(instance, FMUState, size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: size_t,
) -> fmi3Status {
    unsafe { ffi::fmi2SerializeFMUstate(instance, FMUState, serializedState as *mut c_char, size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: size_t,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe {
        ffi::fmi2DeSerializeFMUstate(instance, serializedState as *const c_char, size, FMUState)
    }
}

/// fmi3DoStep: without earlyReturnAllowed the step ends at currentCommunicationPoint +
/// communicationStepSize, exactly as fmi2DoStep's does; with it StickSlipBeam ends at a
/// stick/slip switch inside the step (earlyReturn, lastSuccessfulTime = the switch), and
/// with eventModeUsed a step ending at a switch sets eventHandlingNeeded
/// (`Instance::do_step3`).
#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    instance: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    const CALL: &str = "fmi3DoStep";
    unsafe {
        with_component(instance, CALL, |component| {
            if eventHandlingNeeded.is_null()
                || terminateSimulation.is_null()
                || earlyReturn.is_null()
                || lastSuccessfulTime.is_null()
            {
                return null_argument(
                    component,
                    CALL,
                    "eventHandlingNeeded, terminateSimulation, earlyReturn or lastSuccessfulTime",
                );
            }
            let (result, time) = each!(&mut component.instance, i => {
                let result = i.do_step3(currentCommunicationPoint, communicationStepSize);
                (result, i.time())
            });
            let outcome = result.ok();
            *eventHandlingNeeded = outcome.is_some_and(|o| o.event_handling_needed);
            *terminateSimulation = false;
            *earlyReturn = outcome.is_some_and(|o| o.early_return);
            *lastSuccessfulTime = outcome.map_or(time, |o| o.last_successful_time);
            status(result.map(|_| ()))
        })
    }
}

/// The functions of capabilities these FMUs do not have: each returns fmi3Error and logs
/// which capability flag says so.
macro_rules! not_supported {
    ($name:ident ( $($ty:ty),* $(,)? ), $why:literal) => {
        #[no_mangle]
        pub unsafe extern "C" fn $name(instance: fmi3Instance $(, _: $ty)*) -> fmi3Status {
            unsafe {
                with_component(instance, stringify!($name), |component| {
                    unsupported(component, stringify!($name), $why)
                })
            }
        }
    };
}

/// fmi3EnterEventMode: from Step Mode into Event Mode (only with eventModeUsed).
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterEventMode(instance: fmi3Instance) -> fmi3Status {
    unsafe {
        with_component(
            instance,
            "fmi3EnterEventMode",
            |component| each!(&mut component.instance, i => status(i.enter_event_mode())),
        )
    }
}

/// fmi3EnterStepMode: from Event Mode back into Step Mode.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterStepMode(instance: fmi3Instance) -> fmi3Status {
    unsafe {
        with_component(
            instance,
            "fmi3EnterStepMode",
            |component| each!(&mut component.instance, i => status(i.enter_step_mode())),
        )
    }
}

/// fmi3UpdateDiscreteStates: settles at once (no discrete state of these models depends
/// on the inputs set in Event Mode), with no next time event.
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
    unsafe {
        with_component(instance, CALL, |component| {
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
            *discreteStatesNeedUpdate = update.discrete_states_need_update;
            *terminateSimulation = update.terminate_simulation;
            *nominalsOfContinuousStatesChanged = update.nominals_of_continuous_states_changed;
            *valuesOfContinuousStatesChanged = update.values_of_continuous_states_changed;
            *nextEventTimeDefined = update.next_event_time.is_some();
            *nextEventTime = update.next_event_time.unwrap_or(0.0);
            status(result.map(|_| ()))
        })
    }
}
not_supported!(
    fmi3EvaluateDiscreteStates(),
    "providesEvaluateDiscreteStates is false"
);
not_supported!(
    fmi3GetNumberOfVariableDependencies(fmi3ValueReference, *mut size_t),
    "providesPerElementDependencies is false; the dependencies are in modelDescription.xml"
);
not_supported!(
    fmi3GetVariableDependencies(
        fmi3ValueReference,
        *mut size_t,
        *mut fmi3ValueReference,
        *mut size_t,
        *mut fmi3DependencyKind,
        size_t,
    ),
    "providesPerElementDependencies is false; the dependencies are in modelDescription.xml"
);
not_supported!(
    fmi3GetDirectionalDerivative(
        *const fmi3ValueReference,
        size_t,
        *const fmi3ValueReference,
        size_t,
        *const fmi3Float64,
        size_t,
        *mut fmi3Float64,
        size_t,
    ),
    "providesDirectionalDerivatives is false"
);
not_supported!(
    fmi3GetAdjointDerivative(
        *const fmi3ValueReference,
        size_t,
        *const fmi3ValueReference,
        size_t,
        *const fmi3Float64,
        size_t,
        *mut fmi3Float64,
        size_t,
    ),
    "providesAdjointDerivatives is false"
);
not_supported!(
    fmi3EnterConfigurationMode(),
    "the FMU has no structural parameters"
);
not_supported!(
    fmi3ExitConfigurationMode(),
    "the FMU has no structural parameters"
);
not_supported!(
    fmi3GetIntervalDecimal(
        *const fmi3ValueReference,
        size_t,
        *mut fmi3Float64,
        *mut fmi3IntervalQualifier,
    ),
    "the FMU has no clocks"
);
not_supported!(
    fmi3GetIntervalFraction(
        *const fmi3ValueReference,
        size_t,
        *mut fmi3UInt64,
        *mut fmi3UInt64,
        *mut fmi3IntervalQualifier,
    ),
    "the FMU has no clocks"
);
not_supported!(
    fmi3GetShiftDecimal(*const fmi3ValueReference, size_t, *mut fmi3Float64),
    "the FMU has no clocks"
);
not_supported!(
    fmi3GetShiftFraction(*const fmi3ValueReference, size_t, *mut fmi3UInt64, *mut fmi3UInt64),
    "the FMU has no clocks"
);
not_supported!(
    fmi3SetIntervalDecimal(*const fmi3ValueReference, size_t, *const fmi3Float64),
    "the FMU has no clocks"
);
not_supported!(
    fmi3SetIntervalFraction(
        *const fmi3ValueReference,
        size_t,
        *const fmi3UInt64,
        *const fmi3UInt64,
    ),
    "the FMU has no clocks"
);
not_supported!(
    fmi3SetShiftDecimal(*const fmi3ValueReference, size_t, *const fmi3Float64),
    "the FMU has no clocks"
);
not_supported!(
    fmi3SetShiftFraction(*const fmi3ValueReference, size_t, *const fmi3UInt64, *const fmi3UInt64),
    "the FMU has no clocks"
);
not_supported!(
    fmi3GetOutputDerivatives(
        *const fmi3ValueReference,
        size_t,
        *const fmi3Int32,
        *mut fmi3Float64,
        size_t,
    ),
    "maxOutputDerivativeOrder is 0"
);
// Model Exchange and Scheduled Execution: not offered (no <ModelExchange> or
// <ScheduledExecution> element), so no instance of ours can be in their modes.
not_supported!(fmi3EnterContinuousTimeMode(), "co-simulation only");
not_supported!(
    fmi3CompletedIntegratorStep(fmi3Boolean, *mut fmi3Boolean, *mut fmi3Boolean),
    "co-simulation only"
);
not_supported!(fmi3SetTime(fmi3Float64), "co-simulation only");
not_supported!(
    fmi3SetContinuousStates(*const fmi3Float64, size_t),
    "co-simulation only"
);
not_supported!(
    fmi3GetContinuousStateDerivatives(*mut fmi3Float64, size_t),
    "co-simulation only"
);
not_supported!(
    fmi3GetEventIndicators(*mut fmi3Float64, size_t),
    "co-simulation only"
);
not_supported!(
    fmi3GetContinuousStates(*mut fmi3Float64, size_t),
    "co-simulation only"
);
not_supported!(
    fmi3GetNominalsOfContinuousStates(*mut fmi3Float64, size_t),
    "co-simulation only"
);
not_supported!(
    fmi3GetNumberOfEventIndicators(*mut size_t),
    "co-simulation only"
);
not_supported!(
    fmi3GetNumberOfContinuousStates(*mut size_t),
    "co-simulation only"
);
not_supported!(
    fmi3ActivateModelPartition(fmi3ValueReference, fmi3Float64),
    "co-simulation only"
);

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

    #[test]
    fn fmi3_names_in_messages() {
        let v3 = FmiVersion::V3;
        assert_eq!(v3.rename("fmi2GetReal: x"), "fmi3GetFloat64: x");
        assert_eq!(v3.rename("fmi2SetInteger"), "fmi3SetInt32");
        assert_eq!(
            v3.rename("fmi2DeSerializeFMUstate"),
            "fmi3DeserializeFMUState"
        );
        assert_eq!(
            v3.rename("fmi2SetupExperiment"),
            "fmi3EnterInitializationMode"
        );
        assert_eq!(
            v3.rename("set only before fmi2ExitInitializationMode"),
            "set only before fmi3ExitInitializationMode"
        );
        assert_eq!(FmiVersion::V2.rename("fmi2GetReal"), "fmi2GetReal");
    }
}
