//! fmi2Get* and fmi2Set*: the C arrays become slices (`boundary::values`) and the
//! instance does the rest.

use super::types::{
    fmi2Boolean, fmi2Component, fmi2Integer, fmi2Real, fmi2Status, fmi2String, fmi2ValueReference,
    FMI2_FALSE, FMI2_TRUE,
};
use crate::boundary::{component_at, each, values, with_component};
use libc::size_t;
use std::ffi::c_int;

/// The NULL-argument message's names of the array arguments.
const ARGUMENTS: &str = "vr or value";

macro_rules! getter {
    ($fn_name:ident, $c_type:ty, $method:ident, $convert:expr) => {
        /// # Safety
        ///
        /// `c` is NULL or a live instance of fmi2Instantiate that no other call uses
        /// meanwhile; `vr` is NULL or `nvr` value references, `value` NULL or `nvr`
        /// writable elements that nothing else uses during the call.
        #[no_mangle]
        pub unsafe extern "C" fn $fn_name(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: size_t,
            value: *mut $c_type,
        ) -> fmi2Status {
            // SAFETY: the importer's obligation on `c` above.
            let component = unsafe { component_at(c) };
            with_component(component, stringify!($fn_name), |component| {
                // SAFETY: the importer's obligation on `vr` and `value` above.
                unsafe {
                    values::get(
                        component,
                        stringify!($fn_name),
                        ARGUMENTS,
                        vr,
                        nvr,
                        value,
                        |any, vrs, out| each!(any, i => i.$method(vrs, out)),
                        $convert,
                    )
                }
            })
        }
    };
}

getter!(fmi2GetReal, fmi2Real, get_real, |v: f64| v);
getter!(fmi2GetInteger, fmi2Integer, get_integer, |v: i32| v);
getter!(fmi2GetBoolean, fmi2Boolean, get_boolean, |v: bool| {
    if v {
        FMI2_TRUE
    } else {
        FMI2_FALSE
    }
});

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `vr` is NULL or `nvr` value references, `value` NULL or `nvr` writable string
/// pointers that nothing else uses during the call.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2String,
) -> fmi2Status {
    const CALL: &str = "fmi2GetString";
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, CALL, |component| {
        // SAFETY: the importer's obligation on `vr` and `value` above.
        unsafe { values::get_strings(component, CALL, ARGUMENTS, vr, nvr, value) }
    })
}

macro_rules! setter {
    ($fn_name:ident, $c_type:ty, $method:ident, $convert:expr) => {
        /// # Safety
        ///
        /// `c` is NULL or a live instance of fmi2Instantiate that no other call uses
        /// meanwhile; `vr` and `value` are each NULL or `nvr` readable elements.
        #[no_mangle]
        pub unsafe extern "C" fn $fn_name(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: size_t,
            value: *const $c_type,
        ) -> fmi2Status {
            // SAFETY: the importer's obligation on `c` above.
            let component = unsafe { component_at(c) };
            with_component(component, stringify!($fn_name), |component| {
                // SAFETY: the importer's obligation on `vr` and `value` above.
                unsafe {
                    values::set(
                        component,
                        stringify!($fn_name),
                        ARGUMENTS,
                        vr,
                        nvr,
                        value,
                        |any, vrs, values| each!(any, i => i.$method(vrs, values)),
                        $convert,
                    )
                }
            })
        }
    };
}

setter!(fmi2SetReal, fmi2Real, set_real, |v: f64| v);
setter!(fmi2SetInteger, fmi2Integer, set_integer, |v: i32| v);
setter!(fmi2SetBoolean, fmi2Boolean, set_boolean, |v: c_int| v
    != FMI2_FALSE);

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `vr` and `value` are each NULL or `nvr` readable elements, each string NULL or NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2String,
) -> fmi2Status {
    const CALL: &str = "fmi2SetString";
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, CALL, |component| {
        // SAFETY: the importer's obligation on `vr` and `value` above.
        unsafe { values::set_strings(component, CALL, ARGUMENTS, vr, nvr, value) }
    })
}
