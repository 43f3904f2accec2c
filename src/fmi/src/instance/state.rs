//! The saved FMU state: plain, versioned data that the FMU-state functions get, set and
//! (de)serialize, with the checks that keep a restored clock one the instance could
//! have reached.

use super::base::{CallResult, Instance};
use super::machine::{Call, Mode};
use crate::model::Model;
use serde::{Deserialize, Serialize};

/// A saved FMU state: plain, versioned data (serialised as JSON), restorable in a fresh
/// instance or another process.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SavedState {
    pub format: String,
    pub version: u32,
    pub guid: String,
    pub mode: Mode,
    pub time: f64,
    pub start_time: f64,
    pub stop_time: Option<f64>,
    pub model: serde_json::Value,
    /// FMI 3.0 with event mode: a step ended at an event that the importer has not yet
    /// handled in Event Mode. Written only when true, so FMI 2.0 states are unchanged.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub event_pending: bool,
}

pub const STATE_FORMAT: &str = "stickslip-fmu-state";
/// The version this FMU writes.
/// - 2: StickSlipBeam's friction model, `auto` flag and tolerance moved into its scene
///   (`friction.law`, `fidelity.level = auto`, `fidelity.tolerance`), so an FMU that
///   reads only version 1 refuses these states by their version rather than as
///   malformed.
/// - 3: StickSlipBeam no longer lists every stick/slip transition made so far (a list
///   that grew with simulated time); the simulation state's count replaces it, so the
///   state's size no longer depends on how long the run has gone.
/// - 4: the simulation state carries the friction law's internal state
///   (`SimulationState::law_state`, for `friction.law = lugre | rate-and-state`); a
///   version-3 state reads as one with an empty law state (its laws had none).
///   NeuralFriction's state becomes `{settings, law_state}` (the learned law with
///   memory's state); its version-1 to -3 states, the settings alone, still read.
pub const STATE_VERSION: u32 = 4;
/// The oldest version this FMU still reads (version-1 and version-2 beam states are
/// converted; their transition lists are checked against the count, then dropped).
pub const OLDEST_STATE_VERSION: u32 = 1;

impl SavedState {
    pub fn to_bytes(&self) -> Vec<u8> {
        // A SavedState holds only strings, numbers and JSON values: it always serialises.
        serde_json::to_vec(self).unwrap_or_default()
    }

    /// Reads bytes written by `to_bytes`, refusing anything else with a reason.
    pub fn from_bytes(bytes: &[u8]) -> Result<SavedState, StateError> {
        let state: SavedState = serde_json::from_slice(bytes).map_err(StateError::Malformed)?;
        if state.format != STATE_FORMAT {
            return Err(StateError::Format {
                found: state.format,
            });
        }
        if !(OLDEST_STATE_VERSION..=STATE_VERSION).contains(&state.version) {
            return Err(StateError::Version {
                found: state.version,
            });
        }
        if !state.time.is_finite() || !state.start_time.is_finite() {
            return Err(StateError::NonFiniteTime);
        }
        state.check_clock()?;
        Ok(state)
    }

    /// The instance clock of a state must be one the instance could have reached: no
    /// time before the start, none past the stop, and no time but the start before
    /// initialisation ends.
    fn check_clock(&self) -> Result<(), StateError> {
        let (start, time) = (self.start_time, self.time);
        if !(start.is_finite() && time.is_finite()) {
            return Err(StateError::ClockNotFinite { time, start });
        }
        let slack = 1e-9 * time.abs().max(start.abs()).max(1.0);
        if time < start - slack {
            return Err(StateError::BeforeStart { time, start });
        }
        if let Some(stop) = self.stop_time {
            if !(stop.is_finite() && stop > start) {
                return Err(StateError::StopNotAfterStart { stop, start });
            }
            if time > stop + slack {
                return Err(StateError::PastStop { time, stop });
            }
        }
        let before_steps = matches!(self.mode, Mode::Instantiated | Mode::InitializationMode);
        if before_steps && (time - start).abs() > slack {
            return Err(StateError::NotAtStart {
                mode: self.mode,
                time,
                start,
            });
        }
        Ok(())
    }
}

/// Why bytes are not a state this FMU can restore (times in s).
#[derive(Debug, thiserror::Error)]
pub enum StateError {
    #[error("serialized FMU state is malformed: {0}")]
    Malformed(#[source] serde_json::Error),
    #[error("serialized FMU state has format \"{found}\", expected \"{STATE_FORMAT}\"")]
    Format { found: String },
    #[error("serialized FMU state has version {found}, this FMU reads versions {OLDEST_STATE_VERSION} to {STATE_VERSION}")]
    Version { found: u32 },
    #[error("serialized FMU state has a non-finite time")]
    NonFiniteTime,
    #[error("the state's time {time} s or start time {start} s is not finite")]
    ClockNotFinite { time: f64, start: f64 },
    #[error("the state's time {time} s is before its start time {start} s")]
    BeforeStart { time: f64, start: f64 },
    #[error("the state's stop time {stop} s is not after its start time {start} s")]
    StopNotAfterStart { stop: f64, start: f64 },
    #[error("the state's time {time} s is past its stop time {stop} s")]
    PastStop { time: f64, stop: f64 },
    #[error("the state was saved in {mode:?} mode at time {time} s, but before stepping the time must equal the start time {start} s")]
    NotAtStart { mode: Mode, time: f64, start: f64 },
}

impl<M: Model> Instance<M> {
    /// fmi2GetFMUstate.
    pub fn get_state(&mut self) -> CallResult<SavedState> {
        self.check(Call::GetState)?;
        Ok(SavedState {
            format: STATE_FORMAT.into(),
            version: STATE_VERSION,
            guid: self.guid.clone(),
            mode: self.mode,
            time: self.time,
            start_time: self.start_time,
            stop_time: self.stop_time,
            model: self.model.save(),
            event_pending: self.event_pending,
        })
    }

    /// fmi2SetFMUstate: also the way back from the Error mode.
    pub fn set_state(&mut self, state: &SavedState) -> CallResult<()> {
        self.check(Call::SetState)?;
        let call = self.names().set_fmu_state;
        if state.guid != self.guid {
            return Err(self.fail(
                call,
                &format!(
                    "the state belongs to the FMU with GUID {}, this is {}",
                    state.guid, self.guid
                ),
            ));
        }
        if state.mode == Mode::Error {
            return Err(self.fail(call, "a state saved in the Error mode cannot be restored"));
        }
        if let Err(e) = state.check_clock() {
            return Err(self.fail(call, &e.to_string()));
        }
        if (state.mode == Mode::EventMode || state.event_pending) && !self.events.event_mode_used {
            return Err(self.fail(
                call,
                "the state was saved in or before Event Mode, but this instance was instantiated with eventModeUsed = false",
            ));
        }
        if let Err(reason) = self
            .model
            .restore(state.model.clone(), state.version, state.time)
        {
            return Err(self.fail(call, &reason));
        }
        self.mode = state.mode;
        self.event_pending = state.event_pending;
        self.time = state.time;
        self.start_time = state.start_time;
        self.stop_time = state.stop_time;
        Ok(())
    }

    /// Checks the mode for fmi2FreeFMUstate (the ffi layer frees the memory).
    pub fn free_state(&mut self) -> CallResult<()> {
        self.check(Call::FreeState)
    }

    pub fn serialize_state(&mut self, state: &SavedState) -> CallResult<Vec<u8>> {
        self.check(Call::SerializeState)?;
        Ok(state.to_bytes())
    }

    pub fn deserialize_state(&mut self, bytes: &[u8]) -> CallResult<SavedState> {
        self.check(Call::SerializeState)?;
        SavedState::from_bytes(bytes)
            .map_err(|e| self.fail(self.names().deserialize_fmu_state, &e.to_string()))
    }
}
