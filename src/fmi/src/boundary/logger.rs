//! The importer's logging callback as an instance's [`Logger`], for both versions: the
//! strings made C strings, the callback skipped when the importer gave none. What
//! differs between the versions is only how the callback is called ([`Callback`]).

use super::c_string;
use crate::instance::{Logger, Status};
use std::ffi::{c_void, CStr, CString};

/// One message for the importer, its strings NUL-terminated.
pub(crate) struct Message<'a> {
    /// The instance's name (FMI 2.0 passes it; FMI 3.0 does not).
    pub(crate) instance_name: &'a CStr,
    pub(crate) status: Status,
    /// The log category.
    pub(crate) category: &'a CStr,
    pub(crate) text: &'a CStr,
}

/// A version's logging callback type: how a message reaches it.
pub(crate) trait Callback: Copy + 'static {
    /// Calls the callback with the importer's `environment` and `message`.
    ///
    /// # Safety
    ///
    /// `self` is the importer's callback of this signature, which may be called with
    /// `environment` from the thread that calls the instance.
    unsafe fn deliver(self, environment: *mut c_void, message: &Message);
}

/// The importer's callback with its environment pointer and the instance's name. The
/// importer guarantees that the callback may be called from the thread that calls the
/// instance (FMI 2.0, 2.1.5; FMI 3.0, 2.3.1); the instance is used from one thread at a
/// time.
pub(crate) struct ImporterLogger<F> {
    callback: Option<F>,
    environment: *mut c_void,
    instance_name: CString,
}

// SAFETY: the environment pointer is only handed back to the importer's own callback,
// which the importer lets the FMU call from the thread that calls the instance.
unsafe impl<F> Send for ImporterLogger<F> {}

impl<F: Callback> ImporterLogger<F> {
    /// # Safety
    ///
    /// `callback` is None or the importer's callback, which may be called with
    /// `environment` from the thread that calls the instance.
    pub(crate) unsafe fn new(
        callback: Option<F>,
        environment: *mut c_void,
        instance_name: &str,
    ) -> Self {
        ImporterLogger {
            callback,
            environment,
            instance_name: c_string(instance_name),
        }
    }

    /// Hands `message` in `category` to the importer's callback, if it gave one.
    pub(crate) fn log(&self, status: Status, category: &str, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        let category = c_string(category);
        let message = c_string(message);
        // SAFETY: `new`'s obligation: the importer's callback for this environment, called
        // from the thread that calls the instance; every string is a NUL-terminated
        // CString that outlives the call.
        unsafe {
            callback.deliver(
                self.environment,
                &Message {
                    instance_name: &self.instance_name,
                    status,
                    category: &category,
                    text: &message,
                },
            )
        };
    }

    /// The instance's logger: every message through [`ImporterLogger::log`].
    pub(crate) fn into_logger(self) -> Logger {
        Box::new(move |status, category, message| self.log(status, category, message))
    }
}
