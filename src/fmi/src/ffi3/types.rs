//! The C types of FMI 3.0 (fmi3PlatformTypes.h, fmi3FunctionTypes.h).

#![allow(non_camel_case_types)]

use std::ffi::{c_char, c_int, c_void};

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
/// C99 `bool` (fmi3PlatformTypes.h): one byte. Held as `u8`, not Rust's `bool`, so that
/// a byte other than 0 or 1 from an importer (by value or behind a pointer) is not
/// undefined behaviour here: it is read with [`is_true`] (any non-zero byte is true, as
/// C converts it) and written as 0 or 1 with [`from_bool`].
pub type fmi3Boolean = u8;
pub type fmi3Char = c_char;
pub type fmi3String = *const fmi3Char;
pub type fmi3Byte = u8;
pub type fmi3Binary = *const fmi3Byte;
/// A clock's tick flag, a C99 `bool` like [`fmi3Boolean`].
pub type fmi3Clock = u8;
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

/// An `fmi3Boolean` from the importer as a Rust `bool`: non-zero is true.
pub(crate) fn is_true(value: fmi3Boolean) -> bool {
    value != 0
}

/// A Rust `bool` as the `fmi3Boolean` the standard allows: `fmi3True` (1) or
/// `fmi3False` (0).
pub(crate) fn from_bool(value: bool) -> fmi3Boolean {
    fmi3Boolean::from(value)
}
