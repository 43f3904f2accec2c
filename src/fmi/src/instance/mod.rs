//! One FMU instance: the FMI 2.0 co-simulation state machine (standard, section 4.2.4),
//! with FMI 3.0's Event Mode and early return for FMI 3.0 instances (`EventOptions`,
//! `Mode::EventMode`, `do_step3`), logging, and FMU state, over a `Model`. Plain Rust,
//! so that every rule can be tested without a C importer; the C interfaces (`ffi2`,
//! `ffi3`) only convert arguments. It knows which FMI version instantiated it only to
//! name that version's functions in its log (`FmiVersion::names`).
//!
//! Rooms (as rust-fmi's `fmi-export/src/fmi3/instance/`):
//! - here: the type, its construction, logging and debug-logging categories;
//! - `modes`: the calls, the state table, mode changes and FMI 3.0's events;
//! - `values`: getting and setting variables;
//! - `step`: the step, early return and the status functions;
//! - `state`: the saved FMU state, its format and versions.
//!
//! Decisions where the standard leaves room:
//! - Any call in a mode that does not allow it returns Error with the logged reason
//!   "illegal call sequence" and puts the instance in the Error mode.
//! - In the Error mode an instance accepts what the standard's state table allows
//!   there and nothing else: fmi2Reset, fmi2FreeInstance, fmi2SetDebugLogging, the
//!   reads (fmi2Get*, which then report the values as they were, without computing
//!   anything) and the FMU-state functions, so that a state kept as bytes can be
//!   deserialized and set: the standard's way back from an error. Stepping, setting
//!   and the mode changes are refused.
//! - Functions whose capability flag is false (directional derivatives, input and
//!   output derivatives, asynchronous steps) return Error and log why.
//! - Errors are logged in category logStatusError, which is on even when the importer
//!   instantiates with loggingOn = false; fmi2SetDebugLogging(false, 0, NULL) turns it
//!   off too. The other categories are on only when asked for.

mod modes;
mod state;
mod step;
mod values;

pub use modes::{Call, DiscreteUpdate, Mode};
pub use state::{SavedState, StateError, OLDEST_STATE_VERSION, STATE_FORMAT, STATE_VERSION};
pub use step::{EventOptions, StatusKind, StepOutcome};

use crate::model::Model;
use crate::model_description::{guid, LOG_CATEGORIES};
pub use crate::version::FmiVersion;
use crate::version::Names;
use std::path::Path;

const ERROR: usize = 0;
const WARNING: usize = 1;
const EVENTS: usize = 2;
const CALLS: usize = 3;

/// fmi2Status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
}

/// Receives log messages: (status, category, message).
pub type Logger = Box<dyn FnMut(Status, &str, &str) + Send>;

/// An FMU instance of model `M`.
pub struct Instance<M: Model> {
    name: String,
    version: FmiVersion,
    events: EventOptions,
    event_pending: bool,
    guid: String,
    model: M,
    mode: Mode,
    logger: Logger,
    categories: [bool; LOG_CATEGORIES.len()],
    start_time: f64,
    stop_time: Option<f64>,
    time: f64,
}

/// The result of a call that failed: already logged, the instance is in Error mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Failed;

pub type CallResult<T> = Result<T, Failed>;

impl<M: Model> Instance<M> {
    /// fmi2Instantiate: loads the resources (network weights) or fails with a logged
    /// reason. An FMI 2.0 instance; `instantiate` makes one of either version.
    pub fn new(
        name: &str,
        resources: Option<&Path>,
        logging_on: bool,
        logger: Logger,
    ) -> Result<Self, String> {
        Self::instantiate(FmiVersion::V2, name, resources, logging_on, logger)
    }

    /// fmi2Instantiate or fmi3InstantiateCoSimulation: loads the resources (network
    /// weights) or fails with a reason, logged under the name of `version`'s function.
    pub fn instantiate(
        version: FmiVersion,
        name: &str,
        resources: Option<&Path>,
        logging_on: bool,
        mut logger: Logger,
    ) -> Result<Self, String> {
        let names = version.names();
        let mut model = M::with_defaults();
        let loaded = match resources {
            Some(dir) => model.load_resources(dir),
            None => Err(format!("{} is NULL: no resource location was given; the FMU reads its network weights from its resources/ folder", names.resource_argument)),
        };
        if let Err(reason) = loaded {
            let message = format!("{}: {reason}", names.instantiate);
            logger(Status::Error, LOG_CATEGORIES[ERROR].0, &message);
            return Err(message);
        }
        let mut categories = [logging_on; LOG_CATEGORIES.len()];
        categories[ERROR] = true;
        Ok(Self {
            name: name.to_owned(),
            version,
            events: EventOptions::default(),
            event_pending: false,
            guid: guid::<M>(),
            model,
            mode: Mode::Instantiated,
            logger,
            categories,
            start_time: 0.0,
            stop_time: None,
            time: 0.0,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn version(&self) -> FmiVersion {
        self.version
    }

    /// The names of this instance's FMI functions in its log.
    pub fn names(&self) -> &'static Names {
        self.version.names()
    }

    /// The same instance with FMI 3.0's event options (fmi3InstantiateCoSimulation).
    pub fn with_events(mut self, events: EventOptions) -> Self {
        self.events = events;
        self
    }

    /// Sets FMI 3.0's event options right after instantiation (the ffi layer).
    pub fn set_events(&mut self, events: EventOptions) {
        self.events = events;
    }

    pub fn events(&self) -> EventOptions {
        self.events
    }

    /// A step ended at an event that has not been handled in Event Mode yet.
    pub fn event_pending(&self) -> bool {
        self.event_pending
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn model(&self) -> &M {
        &self.model
    }

    fn log(&mut self, category: usize, status: Status, message: &str) {
        if self.categories[category] {
            (self.logger)(status, LOG_CATEGORIES[category].0, message);
        }
    }

    /// Logs a call in the logCalls category (the ffi layer formats the arguments).
    pub fn log_call(&mut self, message: impl FnOnce() -> String) {
        if self.categories[CALLS] {
            self.log(CALLS, Status::Ok, &message());
        }
    }

    /// Logs `reason`, enters the Error mode and returns the failure.
    pub fn fail(&mut self, call: &str, reason: &str) -> Failed {
        self.log(ERROR, Status::Error, &format!("{call}: {reason}"));
        self.mode = Mode::Error;
        Failed
    }

    fn warn(&mut self, message: &str) {
        self.log(WARNING, Status::Warning, message);
    }

    /// fmi2SetDebugLogging. Unknown categories are ignored with a warning.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Status {
        if categories.is_empty() {
            self.categories = [on; LOG_CATEGORIES.len()];
            return Status::Ok;
        }
        let mut status = Status::Ok;
        for name in categories {
            match LOG_CATEGORIES.iter().position(|(c, _)| c == name) {
                Some(k) => self.categories[k] = on,
                None => {
                    let known: Vec<&str> = LOG_CATEGORIES.iter().map(|(c, _)| *c).collect();
                    self.warn(&format!(
                        "{}: unknown log category \"{name}\" ignored; the categories are {}",
                        self.names().set_debug_logging,
                        known.join(", ")
                    ));
                    status = Status::Warning;
                }
            }
        }
        status
    }
}
