//! fmi3Get* and fmi3Set*: Float64 through `values3` (time and arrays besides scalars),
//! Int32, Boolean and String as scalars with FMI 3.0's `nValues` checked, and the value
//! types these FMUs have no variables of.

use super::types::*;
use super::values3;
use crate::boundary::{
    component_at, each, fail, null_argument, slice, slice_mut, status, values, with_component,
    Component,
};
use crate::instance::{Call, Status};
use libc::size_t;

/// The NULL-argument message's names of the array arguments.
const ARGUMENTS: &str = "valueReferences or values";

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

/// Runs `body` on the instance's component after checking that nValues is what scalar
/// variables need.
fn with_values(
    component: Option<&mut Component>,
    call: &'static str,
    nvr: size_t,
    n_values: size_t,
    body: impl FnOnce(&mut Component) -> Status,
) -> fmi3Status {
    with_component(component, call, |component| {
        if !values_match(component, call, nvr, n_values) {
            return Status::Error;
        }
        body(component)
    })
}

/// fmi3GetFloat64: besides scalars, `time` and array variables, whose values take more
/// than one slot of `values` (`values3`), so nValues is checked there.
///
/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; `valueReferences` is NULL or `nValueReferences` elements, `values` NULL or
/// `nValues` writable elements that nothing else uses during the call.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *mut fmi3Float64,
    nValues: size_t,
) -> fmi3Status {
    const CALL: &str = "fmi3GetFloat64";
    // SAFETY: the importer's obligation on `instance` above.
    let component = unsafe { component_at(instance) };
    with_component(component, CALL, |component| {
        // SAFETY: NULL with a non-zero length is refused below; otherwise the lengths
        // given, by the importer's obligation.
        let arrays = unsafe {
            (
                slice(valueReferences, nValueReferences),
                slice_mut(values, nValues),
            )
        };
        let (Some(vrs), Some(out)) = arrays else {
            return null_argument(component, CALL, "valueReferences or values");
        };
        status(each!(&mut component.instance, i => values3::get(i, vrs, out)))
    })
}

/// fmi3SetFloat64: as [`fmi3GetFloat64`]; `time` cannot be set.
///
/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; `valueReferences` is NULL or `nValueReferences` elements, `values` NULL or
/// `nValues` elements.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *const fmi3Float64,
    nValues: size_t,
) -> fmi3Status {
    const CALL: &str = "fmi3SetFloat64";
    // SAFETY: the importer's obligation on `instance` above.
    let component = unsafe { component_at(instance) };
    with_component(component, CALL, |component| {
        // SAFETY: NULL with a non-zero length is refused below; otherwise the lengths
        // given, by the importer's obligation.
        let arrays = unsafe {
            (
                slice(valueReferences, nValueReferences),
                slice(values, nValues),
            )
        };
        let (Some(vrs), Some(values)) = arrays else {
            return null_argument(component, CALL, "valueReferences or values");
        };
        status(each!(&mut component.instance, i => values3::set(i, vrs, values)))
    })
}

/// fmi3GetInt32, fmi3SetInt32, fmi3GetBoolean and fmi3SetBoolean: nValues checked, then
/// as FMI 2.0's scalar gets and sets (`boundary::values`). FMI 3.0's Boolean is a C99
/// `bool`, read as a byte so that a value other than 0 or 1 is no undefined behaviour.
macro_rules! scalars {
    ($get:ident, $set:ident, $c_type:ty, $read:ident, $write:ident, $in:ty, $to_c:expr, $from_c:expr) => {
        /// # Safety
        ///
        /// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no
        /// other call uses meanwhile; `valueReferences` is NULL or `nValueReferences`
        /// elements, `values` NULL or `nValues` writable elements that nothing else
        /// uses during the call.
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            values: *mut $c_type,
            nValues: size_t,
        ) -> fmi3Status {
            const CALL: &str = stringify!($get);
            // SAFETY: the importer's obligation on `instance` above.
            let component = unsafe { component_at(instance) };
            with_values(component, CALL, nValueReferences, nValues, |component| {
                // SAFETY: the importer's obligations on the arrays above.
                unsafe {
                    values::get(
                        component,
                        CALL,
                        ARGUMENTS,
                        valueReferences,
                        nValueReferences,
                        values,
                        |any, vrs, out| each!(any, i => i.$read(vrs, out)),
                        $to_c,
                    )
                }
            })
        }

        /// # Safety
        ///
        /// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no
        /// other call uses meanwhile; `valueReferences` is NULL or `nValueReferences`
        /// elements, `values` NULL or `nValues` elements.
        #[no_mangle]
        pub unsafe extern "C" fn $set(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            values: *const $c_type,
            nValues: size_t,
        ) -> fmi3Status {
            const CALL: &str = stringify!($set);
            // SAFETY: the importer's obligation on `instance` above.
            let component = unsafe { component_at(instance) };
            with_values(component, CALL, nValueReferences, nValues, |component| {
                // SAFETY: the importer's obligations on the arrays above.
                unsafe {
                    values::set(
                        component,
                        CALL,
                        ARGUMENTS,
                        valueReferences,
                        nValueReferences,
                        values as *const $in,
                        |any, vrs, values| each!(any, i => i.$write(vrs, values)),
                        $from_c,
                    )
                }
            })
        }
    };
}

scalars!(
    fmi3GetInt32,
    fmi3SetInt32,
    fmi3Int32,
    get_integer,
    set_integer,
    fmi3Int32,
    |v: i32| v,
    |v: i32| v
);
scalars!(
    fmi3GetBoolean,
    fmi3SetBoolean,
    fmi3Boolean,
    get_boolean,
    set_boolean,
    u8,
    from_bool,
    is_true
);

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no
/// other call uses meanwhile; `valueReferences` is NULL or `nValueReferences`
/// elements, `values` NULL or `nValues` writable
/// string pointers that nothing else uses during the call.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetString(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *mut fmi3String,
    nValues: size_t,
) -> fmi3Status {
    const CALL: &str = "fmi3GetString";
    // SAFETY: the importer's obligation on `instance` above.
    let component = unsafe { component_at(instance) };
    with_values(component, CALL, nValueReferences, nValues, |component| {
        // SAFETY: the importer's obligations on the arrays above.
        unsafe {
            values::get_strings(
                component,
                CALL,
                ARGUMENTS,
                valueReferences,
                nValueReferences,
                values,
            )
        }
    })
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no
/// other call uses meanwhile; `valueReferences` is NULL or `nValueReferences`
/// elements, `values` NULL or `nValues` pointers, each
/// NULL or NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetString(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *const fmi3String,
    nValues: size_t,
) -> fmi3Status {
    const CALL: &str = "fmi3SetString";
    // SAFETY: the importer's obligation on `instance` above.
    let component = unsafe { component_at(instance) };
    with_values(component, CALL, nValueReferences, nValues, |component| {
        // SAFETY: the importer's obligations on the arrays above.
        unsafe {
            values::set_strings(
                component,
                CALL,
                ARGUMENTS,
                valueReferences,
                nValueReferences,
                values,
            )
        }
    })
}

/// A get or set (`name`, of kind `call`) of a value type that has no variables in
/// these FMUs, on the instance at `instance`: legal in the modes of `call` with no value
/// references, an error naming the first one otherwise.
///
/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; `vrs` is NULL or `nvr` value references.
unsafe fn no_variables_of_type(
    instance: fmi3Instance,
    name: &'static str,
    call: Call,
    vrs: *const fmi3ValueReference,
    nvr: size_t,
    type_name: &str,
) -> fmi3Status {
    // SAFETY: the caller's obligation on `instance`.
    let component = unsafe { component_at(instance) };
    with_component(component, name, |component| {
        if each!(&mut component.instance, i => i.check(call)).is_err() {
            return Status::Error;
        }
        if nvr == 0 {
            return Status::Ok;
        }
        // SAFETY: NULL gives None; otherwise nvr value references by the caller's
        // obligation.
        let first = unsafe { slice(vrs, nvr) }.and_then(|v| v.first().copied());
        let which = first.map_or("NULL".into(), |vr| vr.to_string());
        fail(
            component,
            name,
            &format!("value reference {which} is not a {type_name} variable: this FMU has no {type_name} variables"),
        )
    })
}

macro_rules! no_variables {
    ($get:ident, $set:ident, $c_type:ty, $type_name:literal) => {
        /// # Safety
        ///
        /// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
        /// call uses meanwhile; `valueReferences` is NULL or `nValueReferences` elements;
        /// no other argument is read.
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            _values: *mut $c_type,
            _nValues: size_t,
        ) -> fmi3Status {
            // SAFETY: the importer's obligations on `instance` and `valueReferences` above.
            unsafe {
                no_variables_of_type(
                    instance,
                    stringify!($get),
                    Call::Get,
                    valueReferences,
                    nValueReferences,
                    $type_name,
                )
            }
        }

        /// # Safety
        ///
        /// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
        /// call uses meanwhile; `valueReferences` is NULL or `nValueReferences` elements;
        /// no other argument is read.
        #[no_mangle]
        pub unsafe extern "C" fn $set(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            _values: *const $c_type,
            _nValues: size_t,
        ) -> fmi3Status {
            // SAFETY: the importer's obligations on `instance` and `valueReferences` above.
            unsafe {
                no_variables_of_type(
                    instance,
                    stringify!($set),
                    Call::Set,
                    valueReferences,
                    nValueReferences,
                    $type_name,
                )
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

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; `valueReferences` is NULL or `nValueReferences` elements; no
/// other argument is read.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _valueSizes: *mut size_t,
    _values: *mut fmi3Binary,
    _nValues: size_t,
) -> fmi3Status {
    // SAFETY: the importer's obligations on `instance` and `valueReferences` above.
    unsafe {
        no_variables_of_type(
            instance,
            "fmi3GetBinary",
            Call::Get,
            valueReferences,
            nValueReferences,
            "Binary",
        )
    }
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; `valueReferences` is NULL or `nValueReferences` elements; no
/// other argument is read.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _valueSizes: *const size_t,
    _values: *const fmi3Binary,
    _nValues: size_t,
) -> fmi3Status {
    // SAFETY: the importer's obligations on `instance` and `valueReferences` above.
    unsafe {
        no_variables_of_type(
            instance,
            "fmi3SetBinary",
            Call::Set,
            valueReferences,
            nValueReferences,
            "Binary",
        )
    }
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; `valueReferences` is NULL or `nValueReferences` elements; no
/// other argument is read.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetClock(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _values: *mut fmi3Clock,
) -> fmi3Status {
    // SAFETY: the importer's obligations on `instance` and `valueReferences` above.
    unsafe {
        no_variables_of_type(
            instance,
            "fmi3GetClock",
            Call::Get,
            valueReferences,
            nValueReferences,
            "Clock",
        )
    }
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; `valueReferences` is NULL or `nValueReferences` elements; no
/// other argument is read.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetClock(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _values: *const fmi3Clock,
) -> fmi3Status {
    // SAFETY: the importer's obligations on `instance` and `valueReferences` above.
    unsafe {
        no_variables_of_type(
            instance,
            "fmi3SetClock",
            Call::Set,
            valueReferences,
            nValueReferences,
            "Clock",
        )
    }
}
