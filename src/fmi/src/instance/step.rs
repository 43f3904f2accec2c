//! The step (fmi2DoStep, fmi3DoStep with early return and event handling) and the
//! status functions of FMI 2.0.

use super::base::{CallResult, Instance, Status, EVENTS};
use super::machine::Call;
use crate::model::Model;
use stickslip::short::Short;

/// Status kinds of fmi2Get*Status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusKind {
    DoStepStatus,
    PendingStatus,
    LastSuccessfulTime,
    Terminated,
}

/// What an FMI 3.0 step did (fmi3DoStep's output arguments).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepOutcome {
    /// The step ended before currentCommunicationPoint + communicationStepSize.
    pub early_return: bool,
    /// The step ended at an event and the importer uses event mode: it is asked to
    /// enter Event Mode before the next step.
    pub event_handling_needed: bool,
    /// Where the step ended (s).
    pub last_successful_time: f64,
}

impl<M: Model> Instance<M> {
    /// fmi2DoStep: the communication point must match the instance's time (within 1e-9
    /// relative), h must be positive and finite, and the step must not pass stopTime.
    pub fn do_step(&mut self, current: f64, h: f64) -> CallResult<()> {
        self.step(current, h, false).map(|_| ())
    }

    /// fmi3DoStep: fmi2DoStep's checks and step, except that with earlyReturnAllowed the
    /// step ends at the model's first internal event (the beam: a stick/slip switch), and
    /// with eventModeUsed a step that ends at an event asks for Event Mode; the next step
    /// is refused until the importer has entered it. Without earlyReturnAllowed the step
    /// always reaches its communication point (events inside it are the model's own
    /// business), so the results are FMI 2.0's.
    pub fn do_step3(&mut self, current: f64, h: f64) -> CallResult<StepOutcome> {
        if self.event_pending {
            self.check(Call::DoStep)?;
            let reason = format!(
                "illegal call sequence: the last step ended at an event at t = {} s (eventHandlingNeeded = true); call fmi3EnterEventMode, fmi3UpdateDiscreteStates and fmi3EnterStepMode first",
                Short(self.time)
            );
            return Err(self.fail("fmi3DoStep", &reason));
        }
        let target = current + h;
        let event = self.step(current, h, self.events.early_return_allowed)?;
        let event_handling_needed = event.is_some() && self.events.event_mode_used;
        self.event_pending = event_handling_needed;
        Ok(StepOutcome {
            early_return: self.time < target && event.is_some(),
            event_handling_needed,
            last_successful_time: self.time,
        })
    }

    /// The step of fmi2DoStep and fmi3DoStep; `until_event`: end at the model's first
    /// internal event and return its time.
    fn step(&mut self, current: f64, h: f64, until_event: bool) -> CallResult<Option<f64>> {
        self.check(Call::DoStep)?;
        let call = self.names().do_step;
        let tolerance = 1e-9 * self.time.abs().max(1.0);
        if !current.is_finite() || (current - self.time).abs() > tolerance {
            return Err(self.fail(
                call,
                &format!(
                    "currentCommunicationPoint = {} s does not match the FMU's time {} s",
                    Short(current),
                    Short(self.time)
                ),
            ));
        }
        if !(h > 0.0 && h.is_finite()) {
            return Err(self.fail(
                call,
                &format!(
                    "communicationStepSize = {} s must be positive and finite",
                    Short(h)
                ),
            ));
        }
        let target = current + h;
        if let Some(stop) = self.stop_time {
            if target > stop + 1e-9 * stop.abs().max(1.0) {
                return Err(self.fail(
                    call,
                    &format!(
                        "the step to t = {} s passes stopTime = {} s",
                        Short(target),
                        Short(stop)
                    ),
                ));
            }
        }
        let mut events = Vec::new();
        let result = if until_event {
            self.model.do_step_until_event(target, h, &mut events)
        } else {
            self.model.do_step(target, h, &mut events).map(|()| None)
        };
        for event in &events {
            self.log(EVENTS, Status::Ok, event);
        }
        match result {
            Ok(None) => {
                self.time = target;
                Ok(None)
            }
            Ok(Some(at)) => {
                self.time = at;
                Ok(Some(at))
            }
            Err(reason) => Err(self.fail(call, &reason)),
        }
    }

    /// fmi2GetRealStatus and friends. Only LastSuccessfulTime (Real) and Terminated
    /// (Boolean, always false: the FMU never ends a simulation by itself) are known;
    /// other kinds give Discard, as the standard asks for an unavailable status.
    pub fn real_status(&mut self, kind: StatusKind) -> Result<f64, Status> {
        self.check(Call::GetStatus).map_err(|_| Status::Error)?;
        match kind {
            StatusKind::LastSuccessfulTime => Ok(self.time),
            _ => Err(self.unavailable_status("fmi2GetRealStatus", kind)),
        }
    }

    pub fn boolean_status(&mut self, kind: StatusKind) -> Result<bool, Status> {
        self.check(Call::GetStatus).map_err(|_| Status::Error)?;
        match kind {
            StatusKind::Terminated => Ok(false),
            _ => Err(self.unavailable_status("fmi2GetBooleanStatus", kind)),
        }
    }

    /// Status kinds that this FMU never provides (no asynchronous steps).
    pub fn unavailable_status(&mut self, call: &str, kind: StatusKind) -> Status {
        if self.check(Call::GetStatus).is_err() {
            return Status::Error;
        }
        self.warn(&format!(
            "{call}: status kind {kind:?} is not available (steps are synchronous)"
        ));
        Status::Discard
    }
}
