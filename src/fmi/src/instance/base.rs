//! An instance's type, its construction (the instantiation functions), and its log:
//! the categories and how messages reach the importer.

use super::machine::{EventOptions, Mode};
use crate::model::Model;
use crate::model_description::{guid, LOG_CATEGORIES};
use crate::version::{FmiVersion, Names};
use std::path::Path;

pub(super) const ERROR: usize = 0;
pub(super) const WARNING: usize = 1;
pub(super) const EVENTS: usize = 2;
pub(super) const CALLS: usize = 3;

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
    pub(super) name: String,
    pub(super) version: FmiVersion,
    pub(super) events: EventOptions,
    pub(super) event_pending: bool,
    pub(super) guid: String,
    pub(super) model: M,
    pub(super) mode: Mode,
    pub(super) logger: Logger,
    pub(super) categories: [bool; LOG_CATEGORIES.len()],
    pub(super) start_time: f64,
    pub(super) stop_time: Option<f64>,
    pub(super) time: f64,
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
        logger: Logger,
    ) -> Result<Self, String> {
        Self::instantiate_model(
            version,
            name,
            resources,
            logging_on,
            logger,
            M::with_defaults(),
            guid::<M>(),
        )
    }

    /// [`Self::instantiate`] of `model` (at its start values) for the FMU of `guid`: an
    /// exported FMU (`crate::export`) is StickSlipBeam at a scene's values, under its own
    /// GUID, which its FMU states carry.
    pub fn instantiate_model(
        version: FmiVersion,
        name: &str,
        resources: Option<&Path>,
        logging_on: bool,
        mut logger: Logger,
        mut model: M,
        guid: String,
    ) -> Result<Self, String> {
        let names = version.names();
        let loaded = match resources {
            Some(dir) => model.load_resources(dir),
            None => Err(format!("{} is NULL: no resource location was given; the FMU reads its network weights from its resources/ folder", names.resource_argument)),
        };
        if let Err(reason) = loaded {
            let message = format!("{}: {reason}", names.instantiate);
            logger(Status::Error, LOG_CATEGORIES[ERROR].name, &message);
            return Err(message);
        }
        let mut categories = [logging_on; LOG_CATEGORIES.len()];
        categories[ERROR] = true;
        Ok(Self {
            name: name.to_owned(),
            version,
            events: EventOptions::default(),
            event_pending: false,
            guid,
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

    pub(super) fn log(&mut self, category: usize, status: Status, message: &str) {
        if self.categories[category] {
            (self.logger)(status, LOG_CATEGORIES[category].name, message);
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

    pub(super) fn warn(&mut self, message: &str) {
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
            match LOG_CATEGORIES.iter().position(|c| c.name == *name) {
                Some(k) => self.categories[k] = on,
                None => {
                    let known: Vec<&str> = LOG_CATEGORIES.iter().map(|c| c.name).collect();
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
