//! The gets and sets whose work is the same in both versions once the C arguments are
//! slices: a buffer per request, filled by the instance and copied out only on success.
//! Each runs inside `with_component`; `arguments` names the array arguments of the
//! calling version for the NULL message (FMI 2.0: "vr or value").

use super::{c_string, null_argument, slice, slice_mut, status, text, AnyInstance, Component};
use crate::instance::{CallResult, Status};
use std::ffi::c_char;

/// Reads `nvr` values of type `T` and writes them converted into `value`.
///
/// # Safety
///
/// `vr` is NULL or `nvr` readable value references; `value` is NULL or `nvr` writable
/// elements that nothing else uses during the call.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn get<T: Copy + Default, C>(
    component: &mut Component,
    call: &str,
    arguments: &str,
    vr: *const u32,
    nvr: usize,
    value: *mut C,
    read: impl FnOnce(&mut AnyInstance, &[u32], &mut [T]) -> CallResult<()>,
    convert: impl Fn(T) -> C,
) -> Status {
    // SAFETY: NULL with nvr > 0 is refused below; otherwise nvr elements each by the
    // caller's obligation.
    let (Some(vrs), Some(out)) = (unsafe { slice(vr, nvr) }, unsafe { slice_mut(value, nvr) })
    else {
        return null_argument(component, call, arguments);
    };
    let mut values = vec![T::default(); nvr];
    let result = read(&mut component.instance, vrs, &mut values);
    if result.is_ok() {
        for (slot, v) in out.iter_mut().zip(values) {
            *slot = convert(v);
        }
    }
    status(result)
}

/// Writes the `nvr` values of `value`, converted to `T`.
///
/// # Safety
///
/// `vr` and `value` are each NULL or `nvr` readable elements.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn set<C: Copy, T>(
    component: &mut Component,
    call: &str,
    arguments: &str,
    vr: *const u32,
    nvr: usize,
    value: *const C,
    write: impl FnOnce(&mut AnyInstance, &[u32], &[T]) -> CallResult<()>,
    convert: impl Fn(C) -> T,
) -> Status {
    // SAFETY: NULL with nvr > 0 is refused below; otherwise nvr elements each by the
    // caller's obligation.
    let (Some(vrs), Some(values)) = (unsafe { slice(vr, nvr) }, unsafe { slice(value, nvr) })
    else {
        return null_argument(component, call, arguments);
    };
    let values: Vec<T> = values.iter().map(|&v| convert(v)).collect();
    status(write(&mut component.instance, vrs, &values))
}

/// Reads `nvr` strings; the pointers written into `value` stay valid until the next
/// call (the component keeps the strings).
///
/// # Safety
///
/// `vr` is NULL or `nvr` readable value references; `value` is NULL or `nvr` writable
/// string pointers.
pub(crate) unsafe fn get_strings(
    component: &mut Component,
    call: &str,
    arguments: &str,
    vr: *const u32,
    nvr: usize,
    value: *mut *const c_char,
) -> Status {
    // SAFETY: NULL with nvr > 0 is refused below; otherwise nvr elements each by the
    // caller's obligation.
    let (Some(vrs), Some(out)) = (unsafe { slice(vr, nvr) }, unsafe { slice_mut(value, nvr) })
    else {
        return null_argument(component, call, arguments);
    };
    let result = each!(&mut component.instance, i => i.get_string(vrs));
    match result {
        Ok(strings) => {
            component.strings = strings.iter().map(|s| c_string(s)).collect();
            for (slot, s) in out.iter_mut().zip(&component.strings) {
                *slot = s.as_ptr();
            }
            Status::Ok
        }
        Err(_) => Status::Error,
    }
}

/// Writes `nvr` strings; a NULL string is refused.
///
/// # Safety
///
/// `vr` is NULL or `nvr` readable value references; `value` is NULL or `nvr` pointers,
/// each NULL or a NUL-terminated string.
pub(crate) unsafe fn set_strings(
    component: &mut Component,
    call: &str,
    arguments: &str,
    vr: *const u32,
    nvr: usize,
    value: *const *const c_char,
) -> Status {
    // SAFETY: NULL with nvr > 0 is refused below; otherwise nvr elements each by the
    // caller's obligation.
    let (Some(vrs), Some(pointers)) = (unsafe { slice(vr, nvr) }, unsafe { slice(value, nvr) })
    else {
        return null_argument(component, call, arguments);
    };
    let mut owned = Vec::with_capacity(nvr);
    for &p in pointers {
        // SAFETY: each pointer is NULL (refused) or a NUL-terminated string.
        match unsafe { text(p) } {
            Some(s) => owned.push(s),
            None => return null_argument(component, call, "a string value"),
        }
    }
    let values: Vec<&str> = owned.iter().map(String::as_str).collect();
    status(each!(&mut component.instance, i => i.set_string(vrs, &values)))
}
