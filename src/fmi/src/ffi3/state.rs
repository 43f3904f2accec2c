//! The FMU-state functions of FMI 3.0 (canGetAndSetFMUState, canSerializeFMUState):
//! handles kept by `boundary::states`, as FMI 2.0's.

use super::types::{fmi3Byte, fmi3FMUState, fmi3Instance, fmi3Status};
use crate::boundary::states;
use libc::size_t;

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile;
/// `FMUState` is NULL or points to a readable and writable, initialised
/// fmi3FMUState (only a state this instance returned is overwritten in place).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: the importer's obligations above.
    unsafe { states::get(instance, "fmi3GetFMUState", FMUState) }
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile;
/// `FMUState` may be any value: only one this instance returned and
/// did not free is read.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    // SAFETY: the importer's obligations above.
    unsafe { states::set(instance, "fmi3SetFMUState", FMUState) }
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile;
/// `FMUState` is NULL or points to a readable and writable fmi3FMUState.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: the importer's obligations above.
    unsafe { states::free(instance, "fmi3FreeFMUState", FMUState) }
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile;
/// `size` is NULL or writable; `FMUState` may be any value (only
/// one this instance lists is read).
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut size_t,
) -> fmi3Status {
    // SAFETY: the importer's obligations above.
    unsafe { states::serialized_size(instance, "fmi3SerializedFMUStateSize", FMUState, size) }
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile;
/// `serializedState` is NULL or `size` writable bytes; `FMUState`
/// may be any value (only one this instance lists is read).
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: size_t,
) -> fmi3Status {
    // SAFETY: the importer's obligations above.
    unsafe {
        states::serialize(
            instance,
            "fmi3SerializeFMUState",
            FMUState,
            serializedState,
            size,
        )
    }
}

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile;
/// `serializedState` is NULL or `size` readable bytes; `FMUState`
/// is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: size_t,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: the importer's obligations above.
    unsafe {
        states::deserialize(
            instance,
            "fmi3DeserializeFMUState",
            serializedState,
            size,
            FMUState,
        )
    }
}
