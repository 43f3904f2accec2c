//! fmi2DoStep, the status functions (fmi2Get*Status: steps are synchronous, so only
//! the last successful time and "terminated" are known), directional derivatives, and
//! the functions of capabilities this FMU does not have, which return fmi2Error and log
//! why.

use super::types::{
    fmi2Boolean, fmi2Component, fmi2Integer, fmi2Real, fmi2Status, fmi2StatusKind, fmi2String,
    fmi2ValueReference, FMI2_FALSE, FMI2_TRUE,
};
use crate::boundary::{
    component_at, each, fail, null_argument, slice, slice_mut, status, unsupported, with_component,
    Component,
};
use crate::instance::{Status, StatusKind};
use libc::size_t;

/// NeuralFriction: the outputs' sensitivities along a seed of the inputs; StickSlipBeam:
/// Error (its providesDirectionalDerivative is false). See `Instance::get_directional_derivative`.
///
/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `vUnknown_ref` and `dvUnknown` are NULL or `nUnknown` elements (`dvUnknown` writable
/// and used by nothing else), `vKnown_ref` and `dvKnown` NULL or `nKnown` elements.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    vUnknown_ref: *const fmi2ValueReference,
    nUnknown: size_t,
    vKnown_ref: *const fmi2ValueReference,
    nKnown: size_t,
    dvKnown: *const fmi2Real,
    dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    const CALL: &str = "fmi2GetDirectionalDerivative";
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, CALL, |component| {
        // SAFETY: NULL with a non-zero length is refused below; otherwise the lengths
        // given, by the importer's obligation.
        let arrays = unsafe {
            (
                slice(vUnknown_ref, nUnknown),
                slice(vKnown_ref, nKnown),
                slice(dvKnown, nKnown),
                slice_mut(dvUnknown, nUnknown),
            )
        };
        let (Some(unknowns), Some(knowns), Some(seed), Some(out)) = arrays else {
            return null_argument(
                component,
                CALL,
                "vUnknown_ref, vKnown_ref, dvKnown or dvUnknown",
            );
        };
        status(
            each!(&mut component.instance, i => i.get_directional_derivative(unknowns, knowns, seed, out)),
        )
    })
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: size_t,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, "fmi2SetRealInputDerivatives", |component| {
        unsupported(
            component,
            "fmi2SetRealInputDerivatives",
            "canInterpolateInputs is false",
        )
    })
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: size_t,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, "fmi2GetRealOutputDerivatives", |component| {
        unsupported(
            component,
            "fmi2GetRealOutputDerivatives",
            "maxOutputDerivativeOrder is 0",
        )
    })
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, "fmi2DoStep", |component| {
        status(
            each!(&mut component.instance, i => i.do_step(currentCommunicationPoint, communicationStepSize)),
        )
    })
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile.
#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, "fmi2CancelStep", |component| {
        unsupported(
            component,
            "fmi2CancelStep",
            "steps are synchronous (canRunAsynchronuously is false)",
        )
    })
}

fn status_kind(kind: fmi2StatusKind) -> Option<StatusKind> {
    match kind {
        0 => Some(StatusKind::DoStepStatus),
        1 => Some(StatusKind::PendingStatus),
        2 => Some(StatusKind::LastSuccessfulTime),
        3 => Some(StatusKind::Terminated),
        _ => None,
    }
}

fn bad_status_kind(component: &mut Component, call: &str, kind: fmi2StatusKind) -> Status {
    fail(
        component,
        call,
        &format!("status kind {kind} is not an fmi2StatusKind"),
    )
}

/// fmi2Get*Status for the value types no status kind of this FMU has.
macro_rules! unavailable_status {
    ($fn_name:ident, $c_type:ty) => {
        /// # Safety
        ///
        /// `c` is NULL or a live instance of fmi2Instantiate that no other call uses
        /// meanwhile; `_value` is never touched.
        #[no_mangle]
        pub unsafe extern "C" fn $fn_name(
            c: fmi2Component,
            s: fmi2StatusKind,
            _value: *mut $c_type,
        ) -> fmi2Status {
            // SAFETY: the importer's obligation on `c` above.
            let component = unsafe { component_at(c) };
            with_component(component, stringify!($fn_name), |component| match status_kind(s) {
                Some(kind) => each!(&mut component.instance, i => {
                    i.unavailable_status(stringify!($fn_name), kind)
                }),
                None => bad_status_kind(component, stringify!($fn_name), s),
            })
        }
    };
}

unavailable_status!(fmi2GetStatus, fmi2Status);
unavailable_status!(fmi2GetIntegerStatus, fmi2Integer);
unavailable_status!(fmi2GetStringStatus, fmi2String);

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, "fmi2GetRealStatus", |component| {
        if value.is_null() {
            return null_argument(component, "fmi2GetRealStatus", "value");
        }
        let Some(kind) = status_kind(s) else {
            return bad_status_kind(component, "fmi2GetRealStatus", s);
        };
        match each!(&mut component.instance, i => i.real_status(kind)) {
            Ok(v) => {
                // SAFETY: NULL was refused above; writable by the importer's obligation.
                unsafe { *value = v };
                Status::Ok
            }
            Err(status) => status,
        }
    })
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, "fmi2GetBooleanStatus", |component| {
        if value.is_null() {
            return null_argument(component, "fmi2GetBooleanStatus", "value");
        }
        let Some(kind) = status_kind(s) else {
            return bad_status_kind(component, "fmi2GetBooleanStatus", s);
        };
        match each!(&mut component.instance, i => i.boolean_status(kind)) {
            Ok(v) => {
                // SAFETY: NULL was refused above; writable by the importer's obligation.
                unsafe { *value = if v { FMI2_TRUE } else { FMI2_FALSE } };
                Status::Ok
            }
            Err(status) => status,
        }
    })
}
