//! The FMU-state handles both versions hand out: a handle is a `SavedState` this
//! component allocated and lists in `Component::states`; only listed handles are read,
//! overwritten or freed, so a dangling, foreign or garbage pointer never is.

use super::{component_at, fail, null_argument, slice, status, with_component, CStatus, Component};
use crate::instance::{SavedState, Status};
use std::ffi::c_void;

impl Component {
    fn owns(&self, state: *mut SavedState) -> bool {
        !state.is_null() && self.states.contains(&state)
    }

    /// A copy of the state behind `handle`, if this instance returned it and it was not
    /// freed; otherwise Error is logged.
    fn state(&mut self, handle: *mut c_void, call: &str) -> Option<SavedState> {
        let state = handle as *mut SavedState;
        if !self.owns(state) {
            let names = self.names();
            let reason = format!(
                "the FMU state was not returned by this instance ({} or {}), or was freed; to move a state between instances, serialize it",
                names.get_fmu_state, names.deserialize_fmu_state
            );
            fail(self, call, &reason);
            return None;
        }
        // SAFETY: in the list, so allocated by Box::into_raw and not freed since.
        Some(unsafe { (*state).clone() })
    }

    /// Hands `saved` out as a new handle.
    fn adopt(&mut self, saved: SavedState) -> *mut c_void {
        let state = Box::into_raw(Box::new(saved));
        self.states.push(state);
        state as *mut c_void
    }

    /// The name of the FMU-state argument in this instance's version.
    fn state_argument(&self) -> &'static str {
        self.names().fmu_state_argument
    }
}

/// fmi2GetFMUstate, fmi3GetFMUState.
///
/// # Safety
///
/// `c` as for `component_at`; `handle` is NULL or points to a readable and writable
/// FMU-state pointer, initialised (to NULL or an earlier state, as the standard asks;
/// any other value is replaced and never written through).
pub(crate) unsafe fn get(c: *mut c_void, call: &'static str, handle: *mut *mut c_void) -> CStatus {
    // SAFETY: the caller's obligation on `c`.
    let component = unsafe { component_at(c) };
    with_component(component, call, |component| {
        if handle.is_null() {
            return null_argument(component, call, component.state_argument());
        }
        match each!(&mut component.instance, i => i.get_state()) {
            Ok(saved) => {
                // SAFETY: not NULL, so a readable pointer by the caller's obligation.
                let existing = unsafe { *handle } as *mut SavedState;
                if component.owns(existing) {
                    // The standard lets the FMU overwrite a state it returned before.
                    // SAFETY: listed, so a live Box of ours that nothing else borrows.
                    unsafe { *existing = saved };
                } else {
                    // NULL, or a pointer this instance never returned (an importer's
                    // uninitialised variable): never written through.
                    let adopted = component.adopt(saved);
                    // SAFETY: not NULL, so writable by the caller's obligation.
                    unsafe { *handle = adopted };
                }
                Status::Ok
            }
            Err(_) => Status::Error,
        }
    })
}

/// fmi2SetFMUstate, fmi3SetFMUState.
///
/// # Safety
///
/// `c` as for `component_at`. `handle` may be anything: only a handle this instance
/// lists is read.
pub(crate) unsafe fn set(c: *mut c_void, call: &'static str, handle: *mut c_void) -> CStatus {
    // SAFETY: the caller's obligation on `c`.
    let component = unsafe { component_at(c) };
    with_component(component, call, |component| {
        if handle.is_null() {
            return null_argument(component, call, component.state_argument());
        }
        let Some(saved) = component.state(handle, call) else {
            return Status::Error;
        };
        status(each!(&mut component.instance, i => i.set_state(&saved)))
    })
}

/// fmi2FreeFMUstate, fmi3FreeFMUState.
///
/// # Safety
///
/// `c` as for `component_at`; `handle` is NULL or points to a readable and writable
/// FMU-state pointer.
pub(crate) unsafe fn free(c: *mut c_void, call: &'static str, handle: *mut *mut c_void) -> CStatus {
    // SAFETY: the caller's obligation on `c`.
    let component = unsafe { component_at(c) };
    with_component(component, call, |component| {
        if handle.is_null() {
            return null_argument(component, call, component.state_argument());
        }
        if each!(&mut component.instance, i => i.free_state()).is_err() {
            return Status::Error;
        }
        // SAFETY: not NULL, so a readable pointer by the caller's obligation.
        let state = unsafe { *handle } as *mut SavedState;
        if !state.is_null() {
            // Only a state of this instance: freeing the instance frees the others'
            // (and a second free would be a double free).
            let Some(k) = component.states.iter().position(|&s| s == state) else {
                return fail(
                    component,
                    call,
                    "the FMU state was not allocated by this instance, or was freed already",
                );
            };
            component.states.swap_remove(k);
            // SAFETY: it was listed, so a live Box::into_raw of `adopt`; unlisted just
            // now, so never freed again.
            drop(unsafe { Box::from_raw(state) });
            // SAFETY: not NULL, so writable by the caller's obligation.
            unsafe { *handle = std::ptr::null_mut() };
        }
        Status::Ok
    })
}

/// fmi2SerializedFMUstateSize, fmi3SerializedFMUStateSize.
///
/// # Safety
///
/// `c` as for `component_at`; `size` is NULL or writable. `handle` may be anything:
/// only a handle this instance lists is read.
pub(crate) unsafe fn serialized_size(
    c: *mut c_void,
    call: &'static str,
    handle: *mut c_void,
    size: *mut usize,
) -> CStatus {
    // SAFETY: the caller's obligation on `c`.
    let component = unsafe { component_at(c) };
    with_component(component, call, |component| {
        if handle.is_null() || size.is_null() {
            let what = format!("{} or size", component.state_argument());
            return null_argument(component, call, &what);
        }
        let Some(saved) = component.state(handle, call) else {
            return Status::Error;
        };
        match each!(&mut component.instance, i => i.serialize_state(&saved)) {
            Ok(bytes) => {
                // SAFETY: NULL was refused above; writable by the caller's obligation.
                unsafe { *size = bytes.len() };
                Status::Ok
            }
            Err(_) => Status::Error,
        }
    })
}

/// fmi2SerializeFMUstate, fmi3SerializeFMUState.
///
/// # Safety
///
/// `c` as for `component_at`; `serialized` is NULL or `size` writable bytes that
/// nothing else uses during the call. `handle` may be anything: only a handle this
/// instance lists is read.
pub(crate) unsafe fn serialize(
    c: *mut c_void,
    call: &'static str,
    handle: *mut c_void,
    serialized: *mut u8,
    size: usize,
) -> CStatus {
    // SAFETY: the caller's obligation on `c`.
    let component = unsafe { component_at(c) };
    with_component(component, call, |component| {
        if handle.is_null() || serialized.is_null() {
            let what = format!("{} or serializedState", component.state_argument());
            return null_argument(component, call, &what);
        }
        let Some(saved) = component.state(handle, call) else {
            return Status::Error;
        };
        match each!(&mut component.instance, i => i.serialize_state(&saved)) {
            Ok(bytes) if bytes.len() == size => {
                // SAFETY: NULL was refused above; `size` writable bytes by the caller's
                // obligation, and `bytes` is ours, so they do not overlap.
                unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), serialized, size) };
                Status::Ok
            }
            Ok(bytes) => {
                let reason = format!(
                    "size = {size}, but the state needs {} bytes (see {})",
                    bytes.len(),
                    component.names().serialized_fmu_state_size
                );
                fail(component, call, &reason)
            }
            Err(_) => Status::Error,
        }
    })
}

/// fmi2DeSerializeFMUstate, fmi3DeserializeFMUState.
///
/// # Safety
///
/// `c` as for `component_at`; `serialized` is NULL or `size` readable bytes; `handle` is
/// NULL or writable (its old value is never read).
pub(crate) unsafe fn deserialize(
    c: *mut c_void,
    call: &'static str,
    serialized: *const u8,
    size: usize,
    handle: *mut *mut c_void,
) -> CStatus {
    // SAFETY: the caller's obligation on `c`.
    let component = unsafe { component_at(c) };
    with_component(component, call, |component| {
        // SAFETY: NULL with size > 0 is refused below; otherwise `size` readable bytes by
        // the caller's obligation.
        let Some(bytes) = (unsafe { slice(serialized, size) }) else {
            return null_argument(component, call, "serializedState");
        };
        if handle.is_null() {
            return null_argument(component, call, component.state_argument());
        }
        match each!(&mut component.instance, i => i.deserialize_state(bytes)) {
            Ok(saved) => {
                // Always a new state: unlike getting a state, the standard does not
                // promise that a non-NULL *FMUstate is one of ours.
                let adopted = component.adopt(saved);
                // SAFETY: NULL was refused above; writable by the caller's obligation.
                unsafe { *handle = adopted };
                Status::Ok
            }
            Err(_) => Status::Error,
        }
    })
}
