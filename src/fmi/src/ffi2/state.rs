//! The FMU-state functions of FMI 2.0 (canGetAndSetFMUstate, canSerializeFMUstate):
//! handles kept by `boundary::states`.

use super::types::{fmi2Byte, fmi2Component, fmi2FMUstate, fmi2Status};
use crate::boundary::states;
use libc::size_t;

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe { states::get(c, "fmi2GetFMUstate", FMUstate) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    unsafe { states::set(c, "fmi2SetFMUstate", FMUstate) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe { states::free(c, "fmi2FreeFMUstate", FMUstate) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut size_t,
) -> fmi2Status {
    unsafe { states::serialized_size(c, "fmi2SerializedFMUstateSize", FMUstate, size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: size_t,
) -> fmi2Status {
    unsafe {
        states::serialize(
            c,
            "fmi2SerializeFMUstate",
            FMUstate,
            serializedState as *mut u8,
            size,
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: size_t,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        states::deserialize(
            c,
            "fmi2DeSerializeFMUstate",
            serializedState as *const u8,
            size,
            FMUstate,
        )
    }
}
