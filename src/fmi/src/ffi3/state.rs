//! The FMU-state functions of FMI 3.0 (canGetAndSetFMUState, canSerializeFMUState):
//! handles kept by `boundary::states`, as FMI 2.0's.

use super::types::{fmi3Byte, fmi3FMUState, fmi3Instance, fmi3Status};
use crate::boundary::states;
use libc::size_t;

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe { states::get(instance, "fmi3GetFMUState", FMUState) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    unsafe { states::set(instance, "fmi3SetFMUState", FMUState) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe { states::free(instance, "fmi3FreeFMUState", FMUState) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut size_t,
) -> fmi3Status {
    unsafe { states::serialized_size(instance, "fmi3SerializedFMUStateSize", FMUState, size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: size_t,
) -> fmi3Status {
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

#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: size_t,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
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
