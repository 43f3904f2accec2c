//! The FMU-state handles both versions hand out: a handle is a `SavedState` this
//! component allocated and lists in `Component::states`; only listed handles are read,
//! overwritten or freed, so a dangling, foreign or garbage pointer never is.

use super::{fail, null_argument, slice, status, with_component, CStatus, Component};
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
pub(crate) unsafe fn get(c: *mut c_void, call: &'static str, handle: *mut *mut c_void) -> CStatus {
    unsafe {
        with_component(c, call, |component| {
            if handle.is_null() {
                return null_argument(component, call, component.state_argument());
            }
            match each!(&mut component.instance, i => i.get_state()) {
                Ok(saved) => {
                    let existing = *handle as *mut SavedState;
                    if component.owns(existing) {
                        // The standard lets the FMU overwrite a state it returned before.
                        *existing = saved;
                    } else {
                        // NULL, or a pointer this instance never returned (an importer's
                        // uninitialised variable): never written through.
                        *handle = component.adopt(saved);
                    }
                    Status::Ok
                }
                Err(_) => Status::Error,
            }
        })
    }
}

/// fmi2SetFMUstate, fmi3SetFMUState.
pub(crate) unsafe fn set(c: *mut c_void, call: &'static str, handle: *mut c_void) -> CStatus {
    unsafe {
        with_component(c, call, |component| {
            if handle.is_null() {
                return null_argument(component, call, component.state_argument());
            }
            let Some(saved) = component.state(handle, call) else {
                return Status::Error;
            };
            status(each!(&mut component.instance, i => i.set_state(&saved)))
        })
    }
}

/// fmi2FreeFMUstate, fmi3FreeFMUState.
pub(crate) unsafe fn free(c: *mut c_void, call: &'static str, handle: *mut *mut c_void) -> CStatus {
    unsafe {
        with_component(c, call, |component| {
            if handle.is_null() {
                return null_argument(component, call, component.state_argument());
            }
            if each!(&mut component.instance, i => i.free_state()).is_err() {
                return Status::Error;
            }
            let state = *handle as *mut SavedState;
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
                drop(Box::from_raw(state));
                *handle = std::ptr::null_mut();
            }
            Status::Ok
        })
    }
}

/// fmi2SerializedFMUstateSize, fmi3SerializedFMUStateSize.
pub(crate) unsafe fn serialized_size(
    c: *mut c_void,
    call: &'static str,
    handle: *mut c_void,
    size: *mut usize,
) -> CStatus {
    unsafe {
        with_component(c, call, |component| {
            if handle.is_null() || size.is_null() {
                let what = format!("{} or size", component.state_argument());
                return null_argument(component, call, &what);
            }
            let Some(saved) = component.state(handle, call) else {
                return Status::Error;
            };
            match each!(&mut component.instance, i => i.serialize_state(&saved)) {
                Ok(bytes) => {
                    *size = bytes.len();
                    Status::Ok
                }
                Err(_) => Status::Error,
            }
        })
    }
}

/// fmi2SerializeFMUstate, fmi3SerializeFMUState.
pub(crate) unsafe fn serialize(
    c: *mut c_void,
    call: &'static str,
    handle: *mut c_void,
    serialized: *mut u8,
    size: usize,
) -> CStatus {
    unsafe {
        with_component(c, call, |component| {
            if handle.is_null() || serialized.is_null() {
                let what = format!("{} or serializedState", component.state_argument());
                return null_argument(component, call, &what);
            }
            let Some(saved) = component.state(handle, call) else {
                return Status::Error;
            };
            match each!(&mut component.instance, i => i.serialize_state(&saved)) {
                Ok(bytes) if bytes.len() == size => {
                    std::ptr::copy_nonoverlapping(bytes.as_ptr(), serialized, size);
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
}

/// fmi2DeSerializeFMUstate, fmi3DeserializeFMUState.
pub(crate) unsafe fn deserialize(
    c: *mut c_void,
    call: &'static str,
    serialized: *const u8,
    size: usize,
    handle: *mut *mut c_void,
) -> CStatus {
    unsafe {
        with_component(c, call, |component| {
            let Some(bytes) = slice(serialized, size) else {
                return null_argument(component, call, "serializedState");
            };
            if handle.is_null() {
                return null_argument(component, call, component.state_argument());
            }
            match each!(&mut component.instance, i => i.deserialize_state(bytes)) {
                Ok(saved) => {
                    // Always a new state: unlike getting a state, the standard does not
                    // promise that a non-NULL *FMUstate is one of ours.
                    *handle = component.adopt(saved);
                    Status::Ok
                }
                Err(_) => Status::Error,
            }
        })
    }
}
