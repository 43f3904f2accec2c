//! fmi3DoStep, and the functions of the capabilities these FMUs do not have (each
//! returns fmi3Error and logs which capability flag says so).

use super::types::*;
use crate::boundary::{component_at, each, null_argument, status, unsupported, with_component};
use libc::size_t;

/// fmi3DoStep: without earlyReturnAllowed the step ends at currentCommunicationPoint +
/// communicationStepSize, exactly as fmi2DoStep's does; with it StickSlipBeam ends at a
/// stick/slip switch inside the step (earlyReturn, lastSuccessfulTime = the switch), and
/// with eventModeUsed a step ending at a switch sets eventHandlingNeeded
/// (`Instance::do_step3`).
///
/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; each output pointer is NULL or writable.
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
    // SAFETY: the importer's obligation on `instance` above.
    let component = unsafe { component_at(instance) };
    with_component(component, CALL, |component| {
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
        // SAFETY: NULL was refused above; each writable by the importer's obligation.
        unsafe {
            *eventHandlingNeeded = from_bool(outcome.is_some_and(|o| o.event_handling_needed));
            *terminateSimulation = from_bool(false);
            *earlyReturn = from_bool(outcome.is_some_and(|o| o.early_return));
            *lastSuccessfulTime = outcome.map_or(time, |o| o.last_successful_time);
        }
        status(result.map(|_| ()))
    })
}

/// The functions of capabilities these FMUs do not have: each returns fmi3Error and logs
/// which capability flag says so.
macro_rules! not_supported {
    ($name:ident ( $($ty:ty),* $(,)? ), $why:literal) => {
        /// # Safety
        ///
        /// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no
        /// other call uses meanwhile; no other argument is read.
        #[no_mangle]
        pub unsafe extern "C" fn $name(instance: fmi3Instance $(, _: $ty)*) -> fmi3Status {
            // SAFETY: the importer's obligation on `instance` above.
            let component = unsafe { component_at(instance) };
            with_component(component, stringify!($name), |component| {
                unsupported(component, stringify!($name), $why)
            })
        }
    };
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
