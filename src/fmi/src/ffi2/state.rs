//! The FMU-state functions of FMI 2.0 (canGetAndSetFMUstate, canSerializeFMUstate):
//! handles kept by `boundary::states`.

use super::types::{fmi2Byte, fmi2Component, fmi2FMUstate, fmi2Status};
use crate::boundary::states;
use libc::size_t;

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `FMUstate` is NULL or points to a readable and writable, initialised fmi2FMUstate
/// (only a state this instance returned is overwritten in place).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the importer's obligations above.
    unsafe { states::get(c, "fmi2GetFMUstate", FMUstate) }
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `FMUstate` may be any value: only one this instance returned and
/// did not free is read.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    // SAFETY: the importer's obligations above.
    unsafe { states::set(c, "fmi2SetFMUstate", FMUstate) }
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `FMUstate` is NULL or points to a readable and writable fmi2FMUstate.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the importer's obligations above.
    unsafe { states::free(c, "fmi2FreeFMUstate", FMUstate) }
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `size` is NULL or writable; `FMUstate` may be any value (only one
/// this instance lists is read).
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut size_t,
) -> fmi2Status {
    // SAFETY: the importer's obligations above.
    unsafe { states::serialized_size(c, "fmi2SerializedFMUstateSize", FMUstate, size) }
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `serializedState` is NULL or `size` writable bytes; `FMUstate`
/// may be any value (only one this instance lists is read).
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: size_t,
) -> fmi2Status {
    // SAFETY: the importer's obligations above.
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

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `serializedState` is NULL or `size` readable bytes; `FMUstate`
/// is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: size_t,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the importer's obligations above.
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
