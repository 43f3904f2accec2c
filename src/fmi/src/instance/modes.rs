//! The calls that change modes (FMI 2.0 section 4.2.4, FMI 3.0 section 4.2):
//! initialisation, FMI 3.0's Event Mode, termination and reset.

use super::base::{CallResult, Instance, Status, EVENTS};
use super::machine::{Call, Mode};
use crate::model::Model;
use stickslip::short::Short;

/// fmi3UpdateDiscreteStates's output arguments.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DiscreteUpdate {
    pub discrete_states_need_update: bool,
    pub terminate_simulation: bool,
    pub nominals_of_continuous_states_changed: bool,
    pub values_of_continuous_states_changed: bool,
    /// The next time event (s), if any.
    pub next_event_time: Option<f64>,
}

impl<M: Model> Instance<M> {
    /// A call whose only work is to move from a mode that allows it to `to`.
    fn change_mode(&mut self, call: Call, to: Mode) -> CallResult<()> {
        self.check(call)?;
        self.mode = to;
        Ok(())
    }

    /// Checks that `call` is legal now.
    pub fn check(&mut self, call: Call) -> CallResult<()> {
        if call.allowed_in().contains(&self.mode) {
            return Ok(());
        }
        let reason = format!(
            "illegal call sequence: called in mode {:?}; allowed in {:?}",
            self.mode,
            call.allowed_in()
        );
        Err(self.fail(call.name(self.version), &reason))
    }

    /// fmi2SetupExperiment. The tolerance is not used: the step size is a parameter.
    pub fn setup_experiment(&mut self, start_time: f64, stop_time: Option<f64>) -> CallResult<()> {
        self.check(Call::SetupExperiment)?;
        let call = self.names().setup_experiment;
        if !start_time.is_finite() {
            return Err(self.fail(
                call,
                &format!("startTime = {} is not finite", Short(start_time)),
            ));
        }
        if let Some(stop) = stop_time {
            if !(stop.is_finite() && stop > start_time) {
                return Err(self.fail(
                    call,
                    &format!(
                        "stopTime = {} must be finite and greater than startTime = {}",
                        Short(stop),
                        Short(start_time)
                    ),
                ));
            }
        }
        self.start_time = start_time;
        self.stop_time = stop_time;
        self.time = start_time;
        Ok(())
    }

    pub fn enter_initialization_mode(&mut self) -> CallResult<()> {
        self.change_mode(Call::EnterInitializationMode, Mode::InitializationMode)
    }

    /// fmi2ExitInitializationMode: every parameter is checked here, with the scene's
    /// messages.
    pub fn exit_initialization_mode(&mut self) -> CallResult<()> {
        self.check(Call::ExitInitializationMode)?;
        let result = self.model.initialize(self.start_time, self.stop_time);
        for note in self.model.take_notes() {
            self.log(EVENTS, Status::Ok, &note);
        }
        if let Err(reason) = result {
            return Err(self.fail(self.names().exit_initialization_mode, &reason));
        }
        // FMI 3.0 co-simulation with eventModeUsed enters Event Mode here, without it
        // Step Mode (section 4.2).
        self.mode = if self.events.event_mode_used {
            Mode::EventMode
        } else {
            Mode::StepComplete
        };
        Ok(())
    }

    /// fmi3EnterEventMode (only with eventModeUsed): from Step Mode, at the current time;
    /// clears the request of a step that ended at an event.
    pub fn enter_event_mode(&mut self) -> CallResult<()> {
        if !self.events.event_mode_used {
            return Err(self.fail(
                "fmi3EnterEventMode",
                "the instance was instantiated with eventModeUsed = false",
            ));
        }
        self.check(Call::EnterEventMode)?;
        self.mode = Mode::EventMode;
        self.event_pending = false;
        Ok(())
    }

    /// fmi3UpdateDiscreteStates. The models have no discrete states that the inputs
    /// set in Event Mode could change (the beam's stick/slip state is decided within its
    /// steps), so one call settles everything: no further iteration, no time event, no
    /// change of the continuous states.
    pub fn update_discrete_states(&mut self) -> CallResult<DiscreteUpdate> {
        self.check(Call::UpdateDiscreteStates)?;
        Ok(DiscreteUpdate::default())
    }

    /// fmi3EnterStepMode: back to Step Mode at the current time.
    pub fn enter_step_mode(&mut self) -> CallResult<()> {
        self.change_mode(Call::EnterStepMode, Mode::StepComplete)
    }

    pub fn terminate(&mut self) -> CallResult<()> {
        self.change_mode(Call::Terminate, Mode::Terminated)
    }

    /// fmi2Reset: back to the state right after instantiation (start values, no
    /// experiment), keeping the loaded resources and the logging settings.
    pub fn reset(&mut self) {
        self.model.reset();
        self.mode = Mode::Instantiated;
        self.event_pending = false;
        self.start_time = 0.0;
        self.stop_time = None;
        self.time = 0.0;
    }
}
