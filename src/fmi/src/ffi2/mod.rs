//! The FMI 2.0 C interface: the 25 common and 9 co-simulation functions.
//!
//! Each function only checks and converts its C arguments and hands over to
//! `Instance` (through the version-neutral `boundary`, which also keeps every body
//! inside `catch_unwind`: a panic becomes fmi2Error with a logged reason and puts the
//! instance in the Error mode; it never unwinds into the importer). The logger is
//! always called with the format "%s", so a '%' in a message is printed, not
//! interpreted.
//!
//! Rooms: here instantiation and the mode changes; `values` the gets and sets; `state`
//! the FMU-state functions; `step` fmi2DoStep, the status functions and the functions
//! of capabilities this FMU does not have.

#![allow(non_snake_case, non_camel_case_types)]

mod state;
mod step;
mod types;
mod values;

pub use state::*;
pub use step::*;
pub use types::*;
pub use values::*;

use crate::boundary::logger::{Callback, ImporterLogger, Message};
use crate::boundary::{
    self, component_at, each, exported_model, into_pointer, mode_change, new_component,
    new_exported_component, text, unknown_guid, with_component,
};
use crate::instance::{FmiVersion, Status};
use crate::FmuKind;
use libc::size_t;
use std::ffi::{c_char, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

impl Callback for fmi2CallbackLogger {
    /// FMI 2.0's logger takes the instance's name and a printf format: "%s" with the
    /// message, so that a '%' in it is printed as it is.
    unsafe fn deliver(self, environment: *mut c_void, message: &Message) {
        // SAFETY: the caller's obligation: the importer's callback of this signature for
        // this environment; the strings are NUL-terminated.
        unsafe {
            self(
                environment,
                message.instance_name.as_ptr(),
                message.status as fmi2Status,
                message.category.as_ptr(),
                c"%s".as_ptr(),
                message.text.as_ptr(),
            )
        }
    }
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

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// # Safety
///
/// Every string argument is NULL or NUL-terminated; `functions` is NULL or points to an
/// fmi2CallbackFunctions whose logger (if any) has fmi2CallbackLogger's signature and
/// may be called, with `componentEnvironment`, as long as the instance lives.
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
        // SAFETY: NULL was refused above; otherwise a valid struct by the importer's
        // obligation.
        let callbacks = unsafe { &*functions };
        // SAFETY: NULL or NUL-terminated, the importer's obligation.
        let name = unsafe { text(instanceName) }.unwrap_or_default();
        // SAFETY: the importer's obligation: its logger may be called with its
        // environment.
        let logger =
            unsafe { ImporterLogger::new(callbacks.logger, callbacks.componentEnvironment, &name) };
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
        // SAFETY: NULL or NUL-terminated, the importer's obligation.
        let guid = unsafe { text(fmuGUID) }.unwrap_or_default();
        let kind = FmuKind::from_guid(&guid);
        // SAFETY: NULL or NUL-terminated, the importer's obligation.
        let location = unsafe { text(fmuResourceLocation) };
        let resources = match location.as_deref().map(resource_folder) {
            None => None,
            Some(Ok(dir)) => Some(dir),
            Some(Err(reason)) if kind.is_some() => return fail(reason),
            Some(Err(_)) => return fail(unknown_guid("GUID", &guid)),
        };
        let logging_on = loggingOn != FMI2_FALSE;
        let Some(kind) = kind else {
            // Not a built-in FMU: an exported one, if resources/ holds its export.
            let exported = match exported_model("GUID", &guid, resources) {
                Ok(exported) => exported,
                Err(reason) => return fail(reason),
            };
            return new_exported_component(
                FmiVersion::V2,
                &name,
                exported,
                &guid,
                logging_on,
                logger.into_logger(),
            )
            .map_or(std::ptr::null_mut(), into_pointer);
        };
        new_component(
            FmiVersion::V2,
            kind,
            &name,
            resources,
            logging_on,
            logger.into_logger(),
        )
        .map_or(std::ptr::null_mut(), into_pointer)
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// # Safety
///
/// `c` is NULL or an instance fmi2Instantiate returned, not freed before, and not used
/// by any call during or after this one.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    // SAFETY: the importer's obligation on `c` above.
    unsafe { boundary::free_component(c) }
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile;
/// `categories` is NULL or `nCategories` pointers, each NULL or NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: size_t,
    categories: *const fmi2String,
) -> fmi2Status {
    // SAFETY: the importer's obligations above.
    unsafe {
        boundary::set_debug_logging(
            c,
            "fmi2SetDebugLogging",
            loggingOn != FMI2_FALSE,
            nCategories,
            categories,
        )
    }
}

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    // SAFETY: the importer's obligation on `c` above.
    let component = unsafe { component_at(c) };
    with_component(component, "fmi2SetupExperiment", |component| {
        let stop = (stopTimeDefined != FMI2_FALSE).then_some(stopTime);
        each!(&mut component.instance, i => boundary::status(i.setup_experiment(startTime, stop)))
    })
}

mode_change!(fmi2EnterInitializationMode => enter_initialization_mode);
mode_change!(fmi2ExitInitializationMode => exit_initialization_mode);
mode_change!(fmi2Terminate => terminate);

/// # Safety
///
/// `c` is NULL or a live instance of fmi2Instantiate that no other call uses meanwhile.
#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    // SAFETY: the importer's obligation on `c` above.
    boundary::reset(unsafe { component_at(c) }, "fmi2Reset")
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
