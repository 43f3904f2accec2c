//! The saved FMU state: plain, versioned data that the FMU-state functions get, set and
//! (de)serialize, with the checks that keep a restored clock one the instance could
//! have reached.

use super::base::{CallResult, Instance};
use super::machine::{Call, Mode};
use crate::model::{Model, Restoring};
use crate::variables::set_all;
use serde::de::DeserializeOwned;
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
/// - 5: the JSON text is followed by its checksum ([`CHECKSUM_VERSION`]); the JSON is
///   that of version 4.
/// - 6: NeuralFriction's state always carries `step_size`, the master's h that its
///   step-consistent pair looks ahead over (issue 36). Version-5 states were written
///   with and without it (it came without a bump); one without it, of a law with state
///   after a step, is refused (`friction::state_laws`), because restored with h = 0 its
///   first outputs would be the instantaneous pair, not the run's.
/// - 7: StickSlipBeam's running simulation carries `mean_relative_velocity`, the mean
///   sliding velocity over the last step (an output, issue 36); an older state after a
///   step with `friction.law = external` lacks it and is refused (`beam::saved`). NeuralFriction's settings gain
///   `state_velocity` (absent: `end`, as those states committed) and the input
///   `mean_sliding_velocity` with whether a master has set it (absent: not).
/// - 8: StickSlipBeam's inputs gain the `table` coupling's curves (`table_force`,
///   `table_step_force`; absent: 0, as no older state could couple by `table`).
pub const STATE_VERSION: u32 = 8;
/// The first version whose bytes end in a checksum: the JSON text, then
/// [`CHECKSUM_MARK`] and the CRC-32 (IEEE) of the JSON text's bytes in 8 lowercase hex
/// digits. Older versions are the JSON text alone.
pub const CHECKSUM_VERSION: u32 = 5;
/// What separates the JSON text from its checksum. A newline cannot occur inside the
/// JSON text that `to_bytes` writes (serde_json escapes it in strings).
pub const CHECKSUM_MARK: &[u8] = b"\ncrc32:";
/// Hex digits of the checksum.
const CHECKSUM_DIGITS: usize = 8;
/// The oldest version this FMU still reads (version-1 and version-2 beam states are
/// converted; their transition lists are checked against the count, then dropped).
pub const OLDEST_STATE_VERSION: u32 = 1;

/// The CRC-32 of `json` as the bytes of a version-5 state write it.
fn checksum_text(json: &[u8]) -> String {
    format!("{:08x}", crc32fast::hash(json))
}

/// The serialized form of a state's JSON text from version 5 on: the text, then
/// [`CHECKSUM_MARK`] and its checksum.
pub fn with_checksum(json: &[u8]) -> Vec<u8> {
    let mut bytes = json.to_vec();
    append_checksum(&mut bytes);
    bytes
}

/// Appends [`CHECKSUM_MARK`] and the checksum of `json` to it. In place: the buffer
/// serde_json grew by doubling usually has the room, so that getting a state costs
/// the same allocations whatever its length (tests/fmu/long_run.rs).
fn append_checksum(json: &mut Vec<u8>) {
    let checksum = checksum_text(json);
    json.extend_from_slice(CHECKSUM_MARK);
    json.extend_from_slice(checksum.as_bytes());
}

/// The JSON text of serialized bytes, and whether they ended in a checksum (which is
/// then checked). Bytes that do not end in the mark and 8 characters are the JSON text
/// of an older version, or malformed, which parsing then says.
fn json_of(bytes: &[u8]) -> Result<(&[u8], bool), StateError> {
    let trailer = CHECKSUM_MARK.len() + CHECKSUM_DIGITS;
    let Some(split) = bytes.len().checked_sub(trailer) else {
        return Ok((bytes, false));
    };
    let (json, end) = bytes.split_at(split);
    let Some(found) = end.strip_prefix(CHECKSUM_MARK) else {
        return Ok((bytes, false));
    };
    let computed = checksum_text(json);
    // Compared as written, so that a flipped case bit in a hex digit is a mismatch too.
    if found != computed.as_bytes() {
        return Err(StateError::ChecksumMismatch {
            found: String::from_utf8_lossy(found).into_owned(),
            computed,
        });
    }
    Ok((json, true))
}

/// Parses `value`, the part of a saved state that belongs to a model, as `T`, naming
/// the field where it fails.
pub fn parse_saved<T: DeserializeOwned>(value: serde_json::Value) -> Result<T, String> {
    serde_path_to_error::deserialize(value)
        .map_err(|e| format!("malformed at {}: {}", e.path(), e.inner()))
}

/// Checks the settings a saved state gives model `M` (`part` of `from`, a model holding
/// them) as the setters would: every settable variable is read off `from` and set
/// through its setter into a model at its defaults, and the settings that come out
/// must be these; a field no variable sets must therefore hold its default. The reason
/// names the variable or field.
pub fn check_as_set<M: Model, S: Serialize + PartialEq>(
    from: &M,
    part: fn(&M) -> &S,
) -> Result<(), String> {
    let mut into = M::with_defaults();
    set_all(M::variables(), from, &mut into).map_err(|e| e.to_string())?;
    if part(&into) == part(from) {
        return Ok(());
    }
    let saved = serde_json::to_value(part(from)).unwrap_or_default();
    let as_set = serde_json::to_value(part(&into)).unwrap_or_default();
    let (field, value, settable) = difference_at(&saved, &as_set, String::new());
    Err(format!(
        "{field} = {value} is not what the FMU's variables can set it to (setting every variable of the state gives {settable})"
    ))
}

/// The first field (dotted path) where two JSON values differ.
pub fn first_difference(a: &serde_json::Value, b: &serde_json::Value) -> String {
    difference_at(a, b, String::new()).0
}

/// The first place under `path` where `a` and `b` differ: its dotted path and both
/// values.
fn difference_at(
    a: &serde_json::Value,
    b: &serde_json::Value,
    path: String,
) -> (String, serde_json::Value, serde_json::Value) {
    use serde_json::Value;
    let join = |key: &str| {
        if path.is_empty() {
            key.to_owned()
        } else {
            format!("{path}.{key}")
        }
    };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (key, value) in x {
                let other = y.get(key).unwrap_or(&Value::Null);
                if value != other {
                    return difference_at(value, other, join(key));
                }
            }
            for (key, value) in y {
                if !x.contains_key(key) {
                    return (join(key), Value::Null, value.clone());
                }
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (k, (u, v)) in x.iter().zip(y).enumerate() {
                if u != v {
                    return difference_at(u, v, join(&k.to_string()));
                }
            }
        }
        _ => {}
    }
    (path, a.clone(), b.clone())
}

impl SavedState {
    /// The bytes of the current version: the JSON text and its checksum.
    pub fn to_bytes(&self) -> Vec<u8> {
        // A SavedState holds only strings, numbers and JSON values: it always serialises.
        let mut json = serde_json::to_vec(self).unwrap_or_default();
        if self.version >= CHECKSUM_VERSION {
            append_checksum(&mut json);
            json
        } else {
            // An older version's state (a test's or a migration's) is written as that
            // version was: the JSON text alone.
            json
        }
    }

    /// Reads bytes written by `to_bytes` (or by an older version), refusing anything
    /// else with a reason: corrupted bytes by their checksum, and then what the state
    /// format itself requires. The values of the model's part are the model's to check
    /// (`Model::check_saved`).
    pub fn from_bytes(bytes: &[u8]) -> Result<SavedState, StateError> {
        let (json, has_checksum) = json_of(bytes)?;
        let mut reader = serde_json::Deserializer::from_slice(json);
        let state: SavedState = serde_path_to_error::deserialize(&mut reader).map_err(|e| {
            // The root's path is "."; only a field's is worth saying.
            let path = e.path().to_string();
            StateError::Malformed {
                at: if path == "." {
                    String::new()
                } else {
                    format!(" at {path}")
                },
                source: e.into_inner(),
            }
        })?;
        reader.end().map_err(|source| StateError::Malformed {
            at: String::new(),
            source,
        })?;
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
        match (has_checksum, state.version >= CHECKSUM_VERSION) {
            (false, true) => {
                return Err(StateError::ChecksumMissing {
                    version: state.version,
                })
            }
            (true, false) => {
                return Err(StateError::ChecksumUnexpected {
                    version: state.version,
                })
            }
            _ => {}
        }
        if !state.time.is_finite() || !state.start_time.is_finite() {
            return Err(StateError::NonFiniteTime);
        }
        state.check_clock()?;
        Ok(state)
    }

    /// Where the state puts the instance, for the model's checks.
    fn restoring(&self) -> Restoring {
        Restoring {
            version: self.version,
            time: self.time,
            start_time: self.start_time,
            initialized: !matches!(self.mode, Mode::Instantiated | Mode::InitializationMode),
        }
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
    #[error("serialized FMU state is malformed{at}: {source}")]
    Malformed {
        /// " at " and the field (dotted path) where parsing failed, or nothing.
        at: String,
        #[source]
        source: serde_json::Error,
    },
    #[error("serialized FMU state is corrupted: checksum mismatch (the bytes say crc32 {found}, their JSON text has {computed})")]
    ChecksumMismatch { found: String, computed: String },
    #[error("serialized FMU state of version {version} has no checksum; from version {CHECKSUM_VERSION} on the JSON text ends in one")]
    ChecksumMissing { version: u32 },
    #[error("serialized FMU state of version {version} ends in a checksum, which only versions {CHECKSUM_VERSION} and later have")]
    ChecksumUnexpected { version: u32 },
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

    /// The checks a state must pass before the model's part is looked at: its FMU, its
    /// mode and its clock.
    fn check_instance_part(&self, state: &SavedState) -> Result<(), String> {
        if state.guid != self.guid {
            return Err(format!(
                "the state belongs to the FMU with GUID {}, this is {}",
                state.guid, self.guid
            ));
        }
        if state.mode == Mode::Error {
            return Err("a state saved in the Error mode cannot be restored".into());
        }
        state.check_clock().map_err(|e| e.to_string())?;
        if (state.mode == Mode::EventMode || state.event_pending) && !self.events.event_mode_used {
            return Err("the state was saved in or before Event Mode, but this instance was instantiated with eventModeUsed = false".into());
        }
        Ok(())
    }

    /// fmi2SetFMUstate: also the way back from the Error mode.
    pub fn set_state(&mut self, state: &SavedState) -> CallResult<()> {
        self.check(Call::SetState)?;
        let call = self.names().set_fmu_state;
        if let Err(reason) = self.check_instance_part(state) {
            return Err(self.fail(call, &reason));
        }
        if let Err(reason) = self.model.restore(state.model.clone(), &state.restoring()) {
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

    /// fmi2DeSerializeFMUstate: the bytes, and the state they hold as this instance's
    /// fmi2SetFMUstate would check it (but for what needs the model built from it).
    pub fn deserialize_state(&mut self, bytes: &[u8]) -> CallResult<SavedState> {
        self.check(Call::SerializeState)?;
        let call = self.names().deserialize_fmu_state;
        let checked = SavedState::from_bytes(bytes)
            .map_err(|e| e.to_string())
            .and_then(|state| {
                // A state saved in the Error mode reads back (an importer may keep and
                // hand back whatever it got), but is never set: fmi2SetFMUstate refuses
                // it, so its model part is not looked at.
                if state.mode != Mode::Error {
                    self.check_instance_part(&state)?;
                    self.model.check_saved(&state.model, &state.restoring())?;
                }
                Ok(state)
            });
        checked.map_err(|reason| self.fail(call, &reason))
    }
}
