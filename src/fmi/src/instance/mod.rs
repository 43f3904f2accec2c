//! One FMU instance: the FMI 2.0 co-simulation state machine (standard, section 4.2.4),
//! with FMI 3.0's Event Mode and early return for FMI 3.0 instances (`EventOptions`,
//! `Mode::EventMode`, `do_step3`), logging, and FMU state, over a `Model`. Plain Rust,
//! so that every rule can be tested without a C importer; the C interfaces (`ffi2`,
//! `ffi3`) only convert arguments. It knows which FMI version instantiated it only to
//! name that version's functions in its log (`FmiVersion::names`).
//!
//! Rooms (as rust-fmi's `fmi-export/src/fmi3/instance/`):
//! - `base`: the type, its construction, logging and debug-logging categories;
//! - `machine`: the modes, the calls and the state table;
//! - `modes`: the mode changes and FMI 3.0's events;
//! - `values`: getting and setting variables;
//! - `derivatives`: directional derivatives of outputs with respect to inputs;
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
//! - Functions whose capability flag is false (directional derivatives of
//!   StickSlipBeam, input and output derivatives, asynchronous steps) return Error and
//!   log why.
//! - Errors are logged in category logStatusError, which is on even when the importer
//!   instantiates with loggingOn = false; fmi2SetDebugLogging(false, 0, NULL) turns it
//!   off too. The other categories are on only when asked for.

mod base;
mod derivatives;
mod machine;
mod modes;
mod state;
mod step;
mod values;

pub use crate::version::FmiVersion;
pub use base::{CallResult, Failed, Instance, Logger, Status};
pub use machine::{Call, EventOptions, Mode};
pub use modes::DiscreteUpdate;
pub use state::{
    check_as_set, first_difference, parse_saved, with_checksum, SavedState, StateError,
    CHECKSUM_MARK, CHECKSUM_VERSION, OLDEST_STATE_VERSION, STATE_FORMAT, STATE_VERSION,
};
pub use step::{StatusKind, StepOutcome};
