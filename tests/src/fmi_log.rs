//! The importer side shared by the C-ABI tests: a logger that records every message.

use std::ffi::{c_char, CStr};
use std::sync::Mutex;

use stickslip_fmi::ffi2::{fmi2ComponentEnvironment, fmi2Status, fmi2String};

#[derive(Debug)]
pub struct Entry {
    pub status: fmi2Status,
    pub category: String,
    pub format: String,
    pub message: String,
}

pub type Log = Mutex<Vec<Entry>>;

/// The C string at `p`, or "<NULL>".
///
/// # Safety
/// `p` is NULL or points to a NUL-terminated string that lives through the call.
pub unsafe fn owned(p: *const c_char) -> String {
    if p.is_null() {
        "<NULL>".into()
    } else {
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

/// The logger's six fixed arguments. The FMU always passes exactly one variadic argument
/// (the message, with format "%s"); a non-variadic function called through the variadic
/// pointer type receives it in the same register on x86-64 System V and AArch64 Linux.
// A C callback: the FMU, not Rust, guarantees its pointer arguments, so it cannot be
// an `unsafe fn` (the logger type is a safe `extern "C" fn`).
#[allow(clippy::not_unsafe_ptr_arg_deref)]
pub extern "C" fn record(
    environment: fmi2ComponentEnvironment,
    _instance: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    format: fmi2String,
    message: *const c_char,
) {
    let log = unsafe { &*(environment as *const Log) };
    let entry = Entry {
        status,
        // SAFETY: the FMU passes NUL-terminated strings (or NULL) that live through the call.
        category: unsafe { owned(category) },
        format: unsafe { owned(format) },
        message: unsafe { owned(message) },
    };
    if let Ok(mut entries) = log.lock() {
        entries.push(entry);
    }
}
