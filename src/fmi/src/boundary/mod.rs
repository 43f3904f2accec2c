//! What both C interfaces (`ffi2`, `ffi3`) need and neither version owns: the component
//! behind an FMI instance pointer (an `Instance` of either FMU, the strings and FMU
//! states it handed out), C strings and arrays from the importer, and the boundary that
//! no panic crosses. The shells of both versions call this and `Instance` directly, and
//! never each other.
//!
//! Rooms:
//! - here: the component, instantiation and freeing, panics, C arguments, failures;
//! - `logger`: the importer's logging callback as an instance's logger;
//! - `values`: the gets and sets whose C types are the same in both versions;
//! - `states`: the FMU-state handles (get, set, free, serialize, deserialize).

use crate::beam::StickSlipBeam;
use crate::friction::NeuralFriction;
use crate::instance::{CallResult, FmiVersion, Instance, Logger, SavedState, Status};
use crate::version::Names;
use crate::FmuKind;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

/// fmi2Status and fmi3Status: the same C `int` values (OK = 0 ... Fatal = 4).
pub(crate) type CStatus = c_int;

/// An instance of either FMU.
pub(crate) enum AnyInstance {
    Beam(Box<Instance<StickSlipBeam>>),
    Friction(Box<Instance<NeuralFriction>>),
}

/// Runs `$body` with `$i` bound to the instance inside an `AnyInstance`, whichever FMU.
macro_rules! each {
    ($any:expr, $i:ident => $body:expr) => {
        match $any {
            $crate::boundary::AnyInstance::Beam($i) => $body,
            $crate::boundary::AnyInstance::Friction($i) => $body,
        }
    };
}
pub(crate) use each;

// Declared after `each!`, which they use by its textual scope.
pub(crate) mod logger;
pub(crate) mod states;
pub(crate) mod values;

/// What fmi2Component and fmi3Instance point to.
pub(crate) struct Component {
    pub(crate) instance: AnyInstance,
    /// Strings returned by fmi2GetString and fmi3GetString, valid until the next call.
    pub(crate) strings: Vec<CString>,
    /// FMU states this instance allocated and the importer has not freed yet.
    /// Freeing the instance frees them: fmi2FreeInstance "frees all the allocated
    /// memory and other resources that have been allocated by the functions of the FMU
    /// interface" (FMI 2.0, section 2.1.6; FMI 3.0 says the same of fmi3FreeInstance).
    pub(crate) states: Vec<*mut SavedState>,
}

impl Drop for Component {
    fn drop(&mut self) {
        for state in self.states.drain(..) {
            // SAFETY: allocated by Box::into_raw in `states` and not freed since (freeing
            // removes it from the list).
            drop(unsafe { Box::from_raw(state) });
        }
    }
}

impl Component {
    /// The names of the instance's FMI functions in its log.
    pub(crate) fn names(&self) -> &'static Names {
        each!(&self.instance, i => i.names())
    }
}

pub(crate) fn c_string(text: &str) -> CString {
    CString::new(text.replace('\0', " ")).unwrap_or_default()
}

/// The importer's NUL-terminated string, or None for NULL.
///
/// # Safety
///
/// `s` is NULL or points to a NUL-terminated string that stays unchanged during the call
/// (FMI passes every string argument so).
pub(crate) unsafe fn text(s: *const c_char) -> Option<String> {
    if s.is_null() {
        None
    } else {
        // SAFETY: not NULL, so a NUL-terminated string by the caller's obligation.
        Some(unsafe { CStr::from_ptr(s) }.to_string_lossy().into_owned())
    }
}

/// A slice from a C array, or None for a NULL pointer with a non-zero length.
///
/// # Safety
///
/// Unless `n` is 0 or `ptr` is NULL, `ptr` points to `n` initialised elements that
/// nothing writes to while the slice lives (FMI passes every array argument with the
/// length beside it).
pub(crate) unsafe fn slice<'a, T>(ptr: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if ptr.is_null() {
        None
    } else {
        // SAFETY: n > 0 and not NULL, so n readable elements by the caller's obligation.
        Some(unsafe { std::slice::from_raw_parts(ptr, n) })
    }
}

/// A mutable slice over a C output array, or None for a NULL pointer with a non-zero
/// length.
///
/// # Safety
///
/// Unless `n` is 0 or `ptr` is NULL, `ptr` points to `n` writable elements that nothing
/// else reads or writes while the slice lives.
pub(crate) unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if ptr.is_null() {
        None
    } else {
        // SAFETY: n > 0 and not NULL, so n writable, unaliased elements by the caller's
        // obligation.
        Some(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
    }
}

pub(crate) fn status(result: CallResult<()>) -> Status {
    match result {
        Ok(()) => Status::Ok,
        Err(_) => Status::Error,
    }
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// The component behind an instance pointer, None for NULL.
///
/// # Safety
///
/// `c` is NULL or a pointer an instantiation function of this library returned and no
/// free function has been given since, and no other call uses the instance meanwhile
/// (the importer calls an instance from one thread at a time).
pub(crate) unsafe fn component_at<'a>(c: *mut c_void) -> Option<&'a mut Component> {
    // SAFETY: non-NULL, it is the live, unshared `Component` that `into_pointer` made.
    (!c.is_null()).then(|| unsafe { &mut *(c as *mut Component) })
}

/// Runs `body` on `component` (logging `call` in logCalls), turning a NULL component
/// (None) and any panic into Error.
pub(crate) fn with_component(
    component: Option<&mut Component>,
    call: &'static str,
    body: impl FnOnce(&mut Component) -> Status,
) -> CStatus {
    let Some(component) = component else {
        return Status::Error as CStatus;
    };
    // The log call runs the importer's logger (and, from Rust, any logger closure), so
    // it is inside the unwind guard too: no panic of either may cross extern "C".
    match catch_unwind(AssertUnwindSafe(|| {
        each!(&mut component.instance, i => i.log_call(|| call.to_string()));
        body(component)
    })) {
        Ok(s) => s as CStatus,
        Err(payload) => {
            let reason = format!("internal error (panic): {}", panic_message(&*payload));
            let _ = catch_unwind(AssertUnwindSafe(|| {
                each!(&mut component.instance, i => {
                    i.fail(call, &reason);
                })
            }));
            Status::Error as CStatus
        }
    }
}

/// Logs `reason`, puts the instance in the Error mode and returns Error.
pub(crate) fn fail(component: &mut Component, call: &str, reason: &str) -> Status {
    each!(&mut component.instance, i => {
        i.fail(call, reason);
    });
    Status::Error
}

pub(crate) fn null_argument(component: &mut Component, call: &str, what: &str) -> Status {
    fail(component, call, &format!("{what} is NULL"))
}

/// A function whose capability flag is false.
pub(crate) fn unsupported(component: &mut Component, call: &str, why: &str) -> Status {
    fail(component, call, &format!("not supported: {why}"))
}

/// Why a GUID or instantiation token (`what`) names neither FMU of this binary.
pub(crate) fn unknown_guid(what: &str, guid: &str) -> String {
    let known: Vec<String> = FmuKind::ALL
        .iter()
        .map(|k| format!("{} {}", k.model_identifier(), k.guid()))
        .collect();
    format!(
        "{what} \"{guid}\" does not match this binary ({})",
        known.join(", ")
    )
}

/// A new instance of `kind` behind a component pointer, or NULL after the instance
/// logged why.
pub(crate) fn new_component(
    version: FmiVersion,
    kind: FmuKind,
    name: &str,
    resources: Option<PathBuf>,
    logging_on: bool,
    logger: Logger,
) -> Option<Component> {
    let resources = resources.as_deref();
    let instance = match kind {
        FmuKind::StickSlipBeam => {
            Instance::instantiate(version, name, resources, logging_on, logger)
                .ok()
                .map(|i| AnyInstance::Beam(Box::new(i)))
        }
        FmuKind::NeuralFriction => {
            Instance::instantiate(version, name, resources, logging_on, logger)
                .ok()
                .map(|i| AnyInstance::Friction(Box::new(i)))
        }
    }?;
    Some(Component {
        instance,
        strings: Vec::new(),
        states: Vec::new(),
    })
}

/// The model of the exported FMU in `resources` (`crate::export`) for `guid`, a GUID
/// neither built-in FMU has, and its resources folder. `Err`: why not, the unknown-GUID
/// message when `resources` holds no export.
pub(crate) fn exported_model(
    what: &str,
    guid: &str,
    resources: Option<PathBuf>,
) -> Result<(PathBuf, StickSlipBeam), String> {
    let Some(dir) = resources.filter(|dir| dir.join(crate::export::EXPORT_RESOURCE).exists())
    else {
        return Err(unknown_guid(what, guid));
    };
    let export = crate::export::Export::read(&dir)
        .map_err(|reason| format!("{} (exported FMU: {reason})", unknown_guid(what, guid)))?;
    let expected = export.guid();
    if expected != guid {
        return Err(format!(
            "{what} \"{guid}\" does not match the exported FMU {} in {}, whose description and resources hash to {expected}: modelDescription.xml and resources/ are not of one export (edited or mixed after export-fmu wrote them); export the scene again",
            export.settings.model_identifier,
            dir.display()
        ));
    }
    Ok((dir, export.described().defaults))
}

/// A new instance of an exported FMU's `model` (`exported_model`) under `guid`, or NULL
/// after the instance logged why.
pub(crate) fn new_exported_component(
    version: FmiVersion,
    name: &str,
    (resources, model): (PathBuf, StickSlipBeam),
    guid: &str,
    logging_on: bool,
    logger: Logger,
) -> Option<Component> {
    let instance = Instance::instantiate_model(
        version,
        name,
        Some(&resources),
        logging_on,
        logger,
        model,
        guid.to_owned(),
    )
    .ok()?;
    Some(Component {
        instance: AnyInstance::Beam(Box::new(instance)),
        strings: Vec::new(),
        states: Vec::new(),
    })
}

/// The pointer an instantiation function returns for `component`.
pub(crate) fn into_pointer(component: Component) -> *mut c_void {
    Box::into_raw(Box::new(component)) as *mut c_void
}

/// fmi2FreeInstance and fmi3FreeInstance: frees the component, its FMU states and
/// strings; NULL is ignored.
///
/// # Safety
///
/// `c` is NULL or a pointer an instantiation function of this library returned that no
/// call uses now and that is freed only this once (no call may use it afterwards).
pub(crate) unsafe fn free_component(c: *mut c_void) {
    if c.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: made by Box::into_raw in `into_pointer`, and freed only here, once, by
        // the caller's obligation.
        drop(unsafe { Box::from_raw(c as *mut Component) });
    }));
}

/// fmi2SetDebugLogging and fmi3SetDebugLogging.
///
/// # Safety
///
/// `c` as for `component_at`; `categories` is NULL or holds `n_categories` pointers,
/// each NULL or a NUL-terminated string.
pub(crate) unsafe fn set_debug_logging(
    c: *mut c_void,
    call: &'static str,
    on: bool,
    n_categories: usize,
    categories: *const *const c_char,
) -> CStatus {
    // SAFETY: the caller's obligation on `c`.
    let component = unsafe { component_at(c) };
    with_component(component, call, |component| {
        // SAFETY: NULL is refused below; otherwise n_categories pointers by the caller's
        // obligation.
        let Some(pointers) = (unsafe { slice(categories, n_categories) }) else {
            return null_argument(component, call, "categories");
        };
        let names: Vec<String> = pointers
            .iter()
            // SAFETY: each category is NULL (read as "") or a NUL-terminated string.
            .map(|&p| unsafe { text(p) }.unwrap_or_default())
            .collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        each!(&mut component.instance, i => i.set_debug_logging(on, &names))
    })
}

/// Exports `$name(instance)`, an FMI function with no argument but the instance whose
/// work is the instance's method `$method`, a change of mode.
macro_rules! mode_change {
    ($(#[$doc:meta])* $name:ident => $method:ident) => {
        $(#[$doc])*
        ///
        /// # Safety
        ///
        /// `instance` is NULL or an instance this library's instantiation function
        /// returned, not freed, and not used by another call meanwhile.
        #[no_mangle]
        pub unsafe extern "C" fn $name(instance: *mut std::ffi::c_void) -> std::ffi::c_int {
            // SAFETY: the importer's obligation on `instance` above.
            let component = unsafe { $crate::boundary::component_at(instance) };
            $crate::boundary::change_mode(component, stringify!($name), |any| {
                $crate::boundary::each!(any, i => i.$method())
            })
        }
    };
}
pub(crate) use mode_change;

/// A call that only changes the mode (and has no arguments besides the instance).
pub(crate) fn change_mode(
    component: Option<&mut Component>,
    call: &'static str,
    change: fn(&mut AnyInstance) -> CallResult<()>,
) -> CStatus {
    with_component(component, call, |component| {
        status(change(&mut component.instance))
    })
}

/// fmi2Reset and fmi3Reset.
pub(crate) fn reset(component: Option<&mut Component>, call: &'static str) -> CStatus {
    with_component(component, call, |component| {
        each!(&mut component.instance, i => i.reset());
        Status::Ok
    })
}
