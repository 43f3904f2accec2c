//! The FMI 2.0 C interface: the 25 common and 9 co-simulation functions.
//!
//! Each function only checks and converts its C arguments and hands over to
//! `Instance`. Every body runs inside `catch_unwind`: a panic becomes fmi2Error with a
//! logged reason and puts the instance in the Error mode; it never unwinds into the
//! importer. The logger is always called with the format "%s", so a '%' in a message
//! is printed, not interpreted.

#![allow(non_snake_case, non_camel_case_types, clippy::missing_safety_doc)]

use crate::beam::StickSlipBeam;
use crate::friction::NeuralFriction;
use crate::instance::{CallResult, FmiVersion, Instance, Logger, SavedState, Status, StatusKind};
use crate::model::Model;
use crate::FmuKind;
use libc::size_t;
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

pub type fmi2Component = *mut c_void;
pub type fmi2ComponentEnvironment = *mut c_void;
pub type fmi2FMUstate = *mut c_void;
pub type fmi2ValueReference = c_uint;
pub type fmi2Real = f64;
pub type fmi2Integer = c_int;
pub type fmi2Boolean = c_int;
pub type fmi2String = *const c_char;
pub type fmi2Byte = c_char;
pub type fmi2Status = c_int;
pub type fmi2Type = c_int;
pub type fmi2StatusKind = c_int;

const FMI2_TRUE: fmi2Boolean = 1;
const FMI2_FALSE: fmi2Boolean = 0;
const CO_SIMULATION: fmi2Type = 1;

pub type fmi2CallbackLogger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);

/// fmi2CallbackFunctions (fmi2FunctionTypes.h).
#[repr(C)]
pub struct fmi2CallbackFunctions {
    pub logger: Option<fmi2CallbackLogger>,
    pub allocateMemory: Option<unsafe extern "C" fn(size_t, size_t) -> *mut c_void>,
    pub freeMemory: Option<unsafe extern "C" fn(*mut c_void)>,
    pub stepFinished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    pub componentEnvironment: fmi2ComponentEnvironment,
}

/// The importer's logger with its environment pointer. The importer guarantees that the
/// callback may be called from the thread that calls the instance (FMI 2.0, 2.1.5); the
/// instance is used from one thread at a time.
pub(crate) struct ImporterLogger {
    callback: Option<fmi2CallbackLogger>,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
}

// The raw environment pointer is only handed back to the importer's own callback.
unsafe impl Send for ImporterLogger {}

impl ImporterLogger {
    fn log(&self, status: Status, category: &str, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        let category = c_string(category);
        let message = c_string(message);
        // SAFETY: the importer supplied the callback for exactly this call signature.
        unsafe {
            callback(
                self.environment,
                self.instance_name.as_ptr(),
                status as fmi2Status,
                category.as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            );
        }
    }
}

pub(crate) fn c_string(text: &str) -> CString {
    CString::new(text.replace('\0', " ")).unwrap_or_default()
}

/// An instance of either FMU.
pub(crate) enum AnyInstance {
    Beam(Box<Instance<StickSlipBeam>>),
    Friction(Box<Instance<NeuralFriction>>),
}

macro_rules! each {
    ($any:expr, $i:ident => $body:expr) => {
        match $any {
            $crate::ffi::AnyInstance::Beam($i) => $body,
            $crate::ffi::AnyInstance::Friction($i) => $body,
        }
    };
}
pub(crate) use each;

/// What fmi2Component points to.
pub(crate) struct Component {
    pub(crate) instance: AnyInstance,
    /// Strings returned by fmi2GetString, valid until the next call.
    pub(crate) strings: Vec<CString>,
    /// FMU states this instance allocated and the importer has not freed yet.
    /// fmi2FreeInstance frees them: it "frees all the allocated memory and other
    /// resources that have been allocated by the functions of the FMU interface"
    /// (FMI 2.0, section 2.1.6).
    pub(crate) states: Vec<*mut SavedState>,
}

impl Drop for Component {
    fn drop(&mut self) {
        for state in self.states.drain(..) {
            // SAFETY: allocated by Box::into_raw below and not freed since (freeing
            // removes it from the list).
            drop(unsafe { Box::from_raw(state) });
        }
    }
}

impl Component {
    fn owns(&self, state: *mut SavedState) -> bool {
        !state.is_null() && self.states.contains(&state)
    }

    /// A copy of the state behind `handle`, if this instance returned it and it was not
    /// freed; otherwise fmi2Error is logged. Checking the list keeps a dangling, foreign
    /// or garbage pointer from being read.
    fn state(&mut self, handle: fmi2FMUstate, call: &str) -> Option<SavedState> {
        let state = handle as *mut SavedState;
        if !self.owns(state) {
            fail(
                self,
                call,
                "the FMU state was not returned by this instance (fmi2GetFMUstate or fmi2DeSerializeFMUstate), or was freed; to move a state between instances, serialize it",
            );
            return None;
        }
        // SAFETY: in the list, so allocated by Box::into_raw and not freed since.
        Some(unsafe { (*state).clone() })
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

/// Runs `body` on the component behind `c`, turning a NULL component and any panic into
/// fmi2Error.
pub(crate) unsafe fn with_component(
    c: fmi2Component,
    call: &'static str,
    body: impl FnOnce(&mut Component) -> Status,
) -> fmi2Status {
    if c.is_null() {
        return Status::Error as fmi2Status;
    }
    // SAFETY: a non-NULL fmi2Component is the pointer fmi2Instantiate returned.
    let component = unsafe { &mut *(c as *mut Component) };
    each!(&mut component.instance, i => i.log_call(|| call.to_string()));
    match catch_unwind(AssertUnwindSafe(|| body(component))) {
        Ok(s) => s as fmi2Status,
        Err(payload) => {
            let reason = format!("internal error (panic): {}", panic_message(&*payload));
            let _ = catch_unwind(AssertUnwindSafe(|| {
                each!(&mut component.instance, i => {
                    i.fail(call, &reason);
                })
            }));
            Status::Error as fmi2Status
        }
    }
}

/// A slice from a C array, or None for a NULL pointer with a non-zero length.
pub(crate) unsafe fn slice<'a, T>(ptr: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if ptr.is_null() {
        None
    } else {
        // SAFETY: the importer passes arrays of length n.
        Some(unsafe { std::slice::from_raw_parts(ptr, n) })
    }
}

pub(crate) unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if ptr.is_null() {
        None
    } else {
        // SAFETY: the importer passes arrays of length n.
        Some(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
    }
}

/// Logs `reason`, puts the instance in the Error mode and returns fmi2Error.
pub(crate) fn fail(component: &mut Component, call: &str, reason: &str) -> Status {
    each!(&mut component.instance, i => {
        i.fail(call, reason);
    });
    Status::Error
}

pub(crate) fn null_argument(component: &mut Component, call: &str, what: &str) -> Status {
    fail(component, call, &format!("{what} is NULL"))
}

/// The folder named by fmuResourceLocation, or why it cannot be used.
///
/// FMI 2.0 (sec. 2.1.6, fmi2Instantiate) passes the unpacked `resources/` folder as a
/// URI (RFC 3986) and requires only the file scheme. Accepted: `file:///p`,
/// `file://localhost/p` and `file:/p`, with or without a trailing slash, percent-encoded
/// or raw (importers send spaces and non-ASCII characters unencoded too). The `url`
/// crate parses it (the WHATWG URL Standard, which encodes a raw path as a browser
/// would) and decodes the path (`Url::to_file_path`); on top of it this refuses what
/// would silently name another folder: a malformed percent escape (the standard keeps
/// `%zz` as text), a query or fragment (a raw `?` or `#` in a path would cut it there),
/// a path that decodes to bytes that are not UTF-8, and a host other than localhost.
pub fn resource_folder(uri: &str) -> Result<PathBuf, String> {
    let refuse = |why: String| {
        format!("fmuResourceLocation \"{uri}\" is not a file URI of a local folder: {why}")
    };
    let url = url::Url::parse(uri).map_err(|e| refuse(e.to_string()))?;
    if url.scheme() != "file" {
        return Err(refuse(format!(
            "the scheme is {}:, and only file: is supported",
            url.scheme()
        )));
    }
    // file://localhost/p parses with an empty host.
    if let Some(host) = url.host_str().filter(|h| !h.is_empty()) {
        return Err(refuse(format!(
            "host \"{host}\" is not this machine (use file:///path or file://localhost/path)"
        )));
    }
    if url.query().is_some() || url.fragment().is_some() {
        return Err(refuse(
            "it has a query or fragment; write '?' as %3F and '#' as %23 in a path".into(),
        ));
    }
    if let Some(bad) = bad_percent_escape(url.path()) {
        return Err(refuse(format!(
            "\"{bad}\" is not a percent escape (%XX, two hex digits)"
        )));
    }
    let path = url
        .to_file_path()
        .map_err(|()| refuse("its path is not an absolute local path".into()))?;
    if path.to_str().is_none() {
        return Err(refuse(
            "its path decodes to bytes that are not UTF-8".into(),
        ));
    }
    Ok(path)
}

/// The first `%` in `path` (a URL's serialised path, which is ASCII) that is not
/// followed by two hex digits, with what follows it (at most two characters).
fn bad_percent_escape(path: &str) -> Option<&str> {
    path.match_indices('%').find_map(|(k, _)| {
        let escape = &path[k..(k + 3).min(path.len())];
        let hex_digits = escape.bytes().skip(1).filter(u8::is_ascii_hexdigit).count();
        (hex_digits != 2).then_some(escape)
    })
}

pub(crate) unsafe fn text(s: fmi2String) -> Option<String> {
    if s.is_null() {
        None
    } else {
        // SAFETY: the importer passes NUL-terminated strings.
        Some(unsafe { CStr::from_ptr(s) }.to_string_lossy().into_owned())
    }
}

pub(crate) fn instantiate<M: Model>(
    name: &str,
    resources: Option<PathBuf>,
    logging_on: bool,
    logger: Logger,
) -> Option<Instance<M>> {
    Instance::<M>::new(name, resources.as_deref(), logging_on, logger).ok()
}

/// Why a GUID or instantiation token names neither FMU of this binary.
pub(crate) fn unknown_guid(guid: &str) -> String {
    let known: Vec<String> = FmuKind::ALL
        .iter()
        .map(|k| format!("{} {}", k.model_identifier(), k.guid()))
        .collect();
    format!(
        "GUID \"{guid}\" does not match this binary ({})",
        known.join(", ")
    )
}

/// A new instance of `kind` behind a component, or None after the instance logged why.
pub(crate) fn new_component(
    kind: FmuKind,
    name: &str,
    resources: Option<PathBuf>,
    logging_on: bool,
    logger: Logger,
    version: FmiVersion,
) -> Option<Component> {
    let instance = match kind {
        FmuKind::StickSlipBeam => instantiate::<StickSlipBeam>(name, resources, logging_on, logger)
            .map(|i| AnyInstance::Beam(Box::new(i.with_version(version)))),
        FmuKind::NeuralFriction => {
            instantiate::<NeuralFriction>(name, resources, logging_on, logger)
                .map(|i| AnyInstance::Friction(Box::new(i.with_version(version))))
        }
    }?;
    Some(Component {
        instance,
        strings: Vec::new(),
        states: Vec::new(),
    })
}

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    if functions.is_null() {
        return std::ptr::null_mut();
    }
    let result = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: checked non-NULL; the importer passes a valid struct.
        let callbacks = unsafe { &*functions };
        let name = unsafe { text(instanceName) }.unwrap_or_default();
        let logger = ImporterLogger {
            callback: callbacks.logger,
            environment: callbacks.componentEnvironment,
            instance_name: c_string(&name),
        };
        let fail = |reason: String| {
            logger.log(
                Status::Error,
                "logStatusError",
                &format!("fmi2Instantiate: {reason}"),
            );
            std::ptr::null_mut()
        };
        if instanceName.is_null() || name.is_empty() {
            return fail("instanceName must be a non-empty string".into());
        }
        if fmuType != CO_SIMULATION {
            return fail(format!(
                "fmuType = {fmuType}: this FMU supports co-simulation (fmi2CoSimulation = 1) only"
            ));
        }
        let guid = unsafe { text(fmuGUID) }.unwrap_or_default();
        let Some(kind) = FmuKind::from_guid(&guid) else {
            return fail(unknown_guid(&guid));
        };
        let location = unsafe { text(fmuResourceLocation) };
        let resources = match location.as_deref().map(resource_folder) {
            None => None,
            Some(Ok(dir)) => Some(dir),
            Some(Err(reason)) => return fail(reason),
        };
        let logging_on = loggingOn != FMI2_FALSE;
        let boxed_logger: Logger =
            Box::new(move |status, category, message| logger.log(status, category, message));
        new_component(
            kind,
            &name,
            resources,
            logging_on,
            boxed_logger,
            FmiVersion::V2,
        )
        .map_or(std::ptr::null_mut(), |c| {
            Box::into_raw(Box::new(c)) as fmi2Component
        })
    }));
    result.unwrap_or(std::ptr::null_mut())
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    if c.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the pointer fmi2Instantiate returned; the importer frees it once.
        drop(unsafe { Box::from_raw(c as *mut Component) });
    }));
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: size_t,
    categories: *const fmi2String,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2SetDebugLogging", |component| {
            let Some(pointers) = slice(categories, nCategories) else {
                return null_argument(component, "fmi2SetDebugLogging", "categories");
            };
            let names: Vec<String> = pointers
                .iter()
                .map(|&p| text(p).unwrap_or_default())
                .collect();
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            each!(&mut component.instance, i => i.set_debug_logging(loggingOn != FMI2_FALSE, &names))
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2SetupExperiment", |component| {
            let stop = (stopTimeDefined != FMI2_FALSE).then_some(stopTime);
            each!(&mut component.instance, i => status(i.setup_experiment(startTime, stop)))
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_component(
            c,
            "fmi2EnterInitializationMode",
            |component| each!(&mut component.instance, i => status(i.enter_initialization_mode())),
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_component(
            c,
            "fmi2ExitInitializationMode",
            |component| each!(&mut component.instance, i => status(i.exit_initialization_mode())),
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_component(
            c,
            "fmi2Terminate",
            |component| each!(&mut component.instance, i => status(i.terminate())),
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2Reset", |component| {
            each!(&mut component.instance, i => i.reset());
            Status::Ok
        })
    }
}

macro_rules! getter {
    ($fn_name:ident, $c_type:ty, $method:ident, $convert:expr) => {
        #[no_mangle]
        pub unsafe extern "C" fn $fn_name(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: size_t,
            value: *mut $c_type,
        ) -> fmi2Status {
            unsafe {
                with_component(c, stringify!($fn_name), |component| {
                    let (Some(vrs), Some(out)) = (slice(vr, nvr), slice_mut(value, nvr)) else {
                        return null_argument(component, stringify!($fn_name), "vr or value");
                    };
                    let mut values = vec![Default::default(); nvr];
                    let result =
                        each!(&mut component.instance, i => i.$method(vrs, &mut values));
                    if result.is_ok() {
                        for (slot, v) in out.iter_mut().zip(values) {
                            *slot = $convert(v);
                        }
                    }
                    status(result)
                })
            }
        }
    };
}

getter!(fmi2GetReal, fmi2Real, get_real, |v: f64| v);
getter!(fmi2GetInteger, fmi2Integer, get_integer, |v: i32| v);
getter!(fmi2GetBoolean, fmi2Boolean, get_boolean, |v: bool| {
    if v {
        FMI2_TRUE
    } else {
        FMI2_FALSE
    }
});

#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2GetString", |component| {
            let (Some(vrs), Some(out)) = (slice(vr, nvr), slice_mut(value, nvr)) else {
                return null_argument(component, "fmi2GetString", "vr or value");
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
        })
    }
}

macro_rules! setter {
    ($fn_name:ident, $c_type:ty, $method:ident, $convert:expr) => {
        #[no_mangle]
        pub unsafe extern "C" fn $fn_name(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: size_t,
            value: *const $c_type,
        ) -> fmi2Status {
            unsafe {
                with_component(c, stringify!($fn_name), |component| {
                    let (Some(vrs), Some(values)) = (slice(vr, nvr), slice(value, nvr)) else {
                        return null_argument(component, stringify!($fn_name), "vr or value");
                    };
                    let values: Vec<_> = values.iter().map(|&v| $convert(v)).collect();
                    status(each!(&mut component.instance, i => i.$method(vrs, &values)))
                })
            }
        }
    };
}

setter!(fmi2SetReal, fmi2Real, set_real, |v: f64| v);
setter!(fmi2SetInteger, fmi2Integer, set_integer, |v: i32| v);
setter!(fmi2SetBoolean, fmi2Boolean, set_boolean, |v: c_int| v
    != FMI2_FALSE);

#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2String,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2SetString", |component| {
            let (Some(vrs), Some(pointers)) = (slice(vr, nvr), slice(value, nvr)) else {
                return null_argument(component, "fmi2SetString", "vr or value");
            };
            let mut owned = Vec::with_capacity(nvr);
            for &p in pointers {
                match text(p) {
                    Some(s) => owned.push(s),
                    None => return null_argument(component, "fmi2SetString", "a string value"),
                }
            }
            let values: Vec<&str> = owned.iter().map(String::as_str).collect();
            status(each!(&mut component.instance, i => i.set_string(vrs, &values)))
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2GetFMUstate", |component| {
            if FMUstate.is_null() {
                return null_argument(component, "fmi2GetFMUstate", "FMUstate");
            }
            match each!(&mut component.instance, i => i.get_state()) {
                Ok(saved) => {
                    let existing = *FMUstate as *mut SavedState;
                    if component.owns(existing) {
                        // The standard lets the FMU overwrite a state it returned before.
                        *existing = saved;
                    } else {
                        // NULL, or a pointer this instance never returned (an importer's
                        // uninitialised variable): never written through.
                        let state = Box::into_raw(Box::new(saved));
                        component.states.push(state);
                        *FMUstate = state as fmi2FMUstate;
                    }
                    Status::Ok
                }
                Err(_) => Status::Error,
            }
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2SetFMUstate", |component| {
            if FMUstate.is_null() {
                return null_argument(component, "fmi2SetFMUstate", "FMUstate");
            }
            let Some(saved) = component.state(FMUstate, "fmi2SetFMUstate") else {
                return Status::Error;
            };
            status(each!(&mut component.instance, i => i.set_state(&saved)))
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2FreeFMUstate", |component| {
            if FMUstate.is_null() {
                return null_argument(component, "fmi2FreeFMUstate", "FMUstate");
            }
            if each!(&mut component.instance, i => i.free_state()).is_err() {
                return Status::Error;
            }
            let state = *FMUstate as *mut SavedState;
            if !state.is_null() {
                // Only a state of this instance: fmi2FreeInstance frees the others' (and
                // a second free would be a double free).
                let Some(k) = component.states.iter().position(|&s| s == state) else {
                    return fail(
                        component,
                        "fmi2FreeFMUstate",
                        "the FMU state was not allocated by this instance, or was freed already",
                    );
                };
                component.states.swap_remove(k);
                drop(Box::from_raw(state));
                *FMUstate = std::ptr::null_mut();
            }
            Status::Ok
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut size_t,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2SerializedFMUstateSize", |component| {
            if FMUstate.is_null() || size.is_null() {
                return null_argument(component, "fmi2SerializedFMUstateSize", "FMUstate or size");
            }
            let Some(saved) = component.state(FMUstate, "fmi2SerializedFMUstateSize") else {
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

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: size_t,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2SerializeFMUstate", |component| {
            if FMUstate.is_null() || serializedState.is_null() {
                return null_argument(
                    component,
                    "fmi2SerializeFMUstate",
                    "FMUstate or serializedState",
                );
            }
            let Some(saved) = component.state(FMUstate, "fmi2SerializeFMUstate") else {
                return Status::Error;
            };
            match each!(&mut component.instance, i => i.serialize_state(&saved)) {
                Ok(bytes) if bytes.len() == size => {
                    std::ptr::copy_nonoverlapping(bytes.as_ptr(), serializedState as *mut u8, size);
                    Status::Ok
                }
                Ok(bytes) => fail(
                    component,
                    "fmi2SerializeFMUstate",
                    &format!(
                        "size = {size}, but the state needs {} bytes (see fmi2SerializedFMUstateSize)",
                        bytes.len()
                    ),
                ),
                Err(_) => Status::Error,
            }
        })
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
        with_component(c, "fmi2DeSerializeFMUstate", |component| {
            let Some(bytes) = slice(serializedState as *const u8, size) else {
                return null_argument(component, "fmi2DeSerializeFMUstate", "serializedState");
            };
            if FMUstate.is_null() {
                return null_argument(component, "fmi2DeSerializeFMUstate", "FMUstate");
            }
            match each!(&mut component.instance, i => i.deserialize_state(bytes)) {
                Ok(saved) => {
                    // Always a new state: unlike fmi2GetFMUstate, the standard does not
                    // promise that a non-NULL *FMUstate is one of ours.
                    let state = Box::into_raw(Box::new(saved));
                    component.states.push(state);
                    *FMUstate = state as fmi2FMUstate;
                    Status::Ok
                }
                Err(_) => Status::Error,
            }
        })
    }
}

/// A function whose capability flag is false.
pub(crate) fn unsupported(component: &mut Component, call: &str, why: &str) -> Status {
    fail(component, call, &format!("not supported: {why}"))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    _vUnknown_ref: *const fmi2ValueReference,
    _nUnknown: size_t,
    _vKnown_ref: *const fmi2ValueReference,
    _nKnown: size_t,
    _dvKnown: *const fmi2Real,
    _dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2GetDirectionalDerivative", |component| {
            unsupported(
                component,
                "fmi2GetDirectionalDerivative",
                "providesDirectionalDerivative is false",
            )
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: size_t,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2SetRealInputDerivatives", |component| {
            unsupported(
                component,
                "fmi2SetRealInputDerivatives",
                "canInterpolateInputs is false",
            )
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: size_t,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2GetRealOutputDerivatives", |component| {
            unsupported(
                component,
                "fmi2GetRealOutputDerivatives",
                "maxOutputDerivativeOrder is 0",
            )
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2DoStep", |component| {
            status(
                each!(&mut component.instance, i => i.do_step(currentCommunicationPoint, communicationStepSize)),
            )
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2CancelStep", |component| {
            unsupported(
                component,
                "fmi2CancelStep",
                "steps are synchronous (canRunAsynchronuously is false)",
            )
        })
    }
}

fn status_kind(kind: fmi2StatusKind) -> Option<StatusKind> {
    match kind {
        0 => Some(StatusKind::DoStepStatus),
        1 => Some(StatusKind::PendingStatus),
        2 => Some(StatusKind::LastSuccessfulTime),
        3 => Some(StatusKind::Terminated),
        _ => None,
    }
}

fn bad_status_kind(component: &mut Component, call: &str, kind: fmi2StatusKind) -> Status {
    fail(
        component,
        call,
        &format!("status kind {kind} is not an fmi2StatusKind"),
    )
}

/// fmi2Get*Status for the value types no status kind of this FMU has.
macro_rules! unavailable_status {
    ($fn_name:ident, $c_type:ty) => {
        #[no_mangle]
        pub unsafe extern "C" fn $fn_name(
            c: fmi2Component,
            s: fmi2StatusKind,
            _value: *mut $c_type,
        ) -> fmi2Status {
            unsafe {
                with_component(c, stringify!($fn_name), |component| match status_kind(s) {
                    Some(kind) => each!(&mut component.instance, i => {
                        i.unavailable_status(stringify!($fn_name), kind)
                    }),
                    None => bad_status_kind(component, stringify!($fn_name), s),
                })
            }
        }
    };
}

unavailable_status!(fmi2GetStatus, fmi2Status);
unavailable_status!(fmi2GetIntegerStatus, fmi2Integer);
unavailable_status!(fmi2GetStringStatus, fmi2String);

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2GetRealStatus", |component| {
            if value.is_null() {
                return null_argument(component, "fmi2GetRealStatus", "value");
            }
            let Some(kind) = status_kind(s) else {
                return bad_status_kind(component, "fmi2GetRealStatus", s);
            };
            match each!(&mut component.instance, i => i.real_status(kind)) {
                Ok(v) => {
                    *value = v;
                    Status::Ok
                }
                Err(status) => status,
            }
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        with_component(c, "fmi2GetBooleanStatus", |component| {
            if value.is_null() {
                return null_argument(component, "fmi2GetBooleanStatus", "value");
            }
            let Some(kind) = status_kind(s) else {
                return bad_status_kind(component, "fmi2GetBooleanStatus", s);
            };
            match each!(&mut component.instance, i => i.boolean_status(kind)) {
                Ok(v) => {
                    *value = if v { FMI2_TRUE } else { FMI2_FALSE };
                    Status::Ok
                }
                Err(status) => status,
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resource_uris() {
        let p = |s: &str| resource_folder(s).ok().map(|p| p.display().to_string());
        assert_eq!(
            p("file:///tmp/a%20b/resources"),
            Some("/tmp/a b/resources".into())
        );
        assert_eq!(
            p("file:/tmp/x/resources/"),
            Some("/tmp/x/resources/".into())
        );
        assert_eq!(p("file://localhost/tmp/x"), Some("/tmp/x".into()));
        assert_eq!(p("file://LOCALHOST/tmp/x"), Some("/tmp/x".into()));
        // Raw (unencoded) spaces and non-ASCII characters, and their encoded form.
        assert_eq!(p("file:///tmp/a b/Größe/"), Some("/tmp/a b/Größe/".into()));
        assert_eq!(
            p("file:///tmp/a%20b/Gr%C3%B6%C3%9Fe/"),
            Some("/tmp/a b/Größe/".into())
        );
        // Encoded '?', '#' and '%' are path characters.
        assert_eq!(p("file:///tmp/a%3Fb%23c%25d"), Some("/tmp/a?b#c%d".into()));
        assert_eq!(p("file://server/tmp/x"), None);
        assert_eq!(p("http://x/y"), None);
        assert_eq!(p("file:///bad%zz"), None);
        assert_eq!(p("file:///cut%2"), None);
        assert_eq!(p("file:///cut%"), None);
        assert_eq!(p("file:///not-utf8%C3"), None);
        assert_eq!(p("file:///tmp/a?b"), None);
        assert_eq!(p("file:///tmp/a#b"), None);
        assert_eq!(p("/tmp/x"), None);
        assert_eq!(p(""), None);
    }

    #[test]
    fn refused_resource_uris_say_why() {
        let why = |s: &str| resource_folder(s).unwrap_err();
        for (uri, reason) in [
            ("http://x/y", "scheme is http:"),
            ("file://server/tmp/x", "host \"server\""),
            ("file:///bad%zzz", "\"%zz\" is not a percent escape"),
            ("file:///cut%2", "\"%2\" is not a percent escape"),
            ("file:///tmp/a#b", "query or fragment"),
            ("file:///x%C3", "not UTF-8"),
            ("resources", "relative URL without a base"),
        ] {
            let message = why(uri);
            assert!(
                message.starts_with(&format!("fmuResourceLocation \"{uri}\" is not a file URI"))
                    && message.contains(reason),
                "{uri}: {message}"
            );
        }
    }
}
