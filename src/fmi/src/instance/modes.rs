//! The calls the state machine tells apart, the modes it allows them in (FMI 2.0
//! section 4.2.4, FMI 3.0 section 4.2), and the calls that change modes: initialisation,
//! FMI 3.0's Event Mode, termination and reset.

use super::{CallResult, Instance, Status, EVENTS};
use crate::model::Model;
use crate::version::FmiVersion;
use serde::{Deserialize, Serialize};

/// Where an instance is in the co-simulation state machine: FMI 2.0's (section 4.2.4),
/// which FMI 3.0 co-simulation shares with Step Mode as `StepComplete`, plus FMI 3.0's
/// Event Mode (section 4.2, only for an instance instantiated with eventModeUsed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
    /// FMI 3.0 Event Mode: entered from initialisation or by fmi3EnterEventMode, left by
    /// fmi3EnterStepMode. Inputs can be set and outputs read; time does not advance.
    EventMode,
}

/// The FMI calls the state machine tells apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Get,
    Set,
    GetState,
    SetState,
    FreeState,
    SerializeState,
    DoStep,
    GetStatus,
    EnterEventMode,
    UpdateDiscreteStates,
    EnterStepMode,
}

impl Call {
    /// The call's name in the log of an instance of `version`. The FMI 3.0 Event Mode
    /// calls have no FMI 2.0 twin.
    pub fn name(self, version: FmiVersion) -> &'static str {
        let names = version.names();
        match self {
            Call::SetupExperiment => names.setup_experiment,
            Call::EnterInitializationMode => names.enter_initialization_mode,
            Call::ExitInitializationMode => names.exit_initialization_mode,
            Call::Terminate => names.terminate,
            Call::Get => names.get_any,
            Call::Set => names.set_any,
            Call::GetState => names.get_fmu_state,
            Call::SetState => names.set_fmu_state,
            Call::FreeState => names.free_fmu_state,
            Call::SerializeState => names.serialize_any,
            Call::DoStep => names.do_step,
            Call::GetStatus => names.get_status_any,
            Call::EnterEventMode => "fmi3EnterEventMode",
            Call::UpdateDiscreteStates => "fmi3UpdateDiscreteStates",
            Call::EnterStepMode => "fmi3EnterStepMode",
        }
    }

    /// The modes in which the call is legal. `EventMode` occurs only in FMI 3.0
    /// instances that use event mode; there, as in Step Mode, inputs can be set, outputs
    /// read, the FMU state saved and restored, and the instance terminated (FMI 3.0,
    /// section 4.2: the co-simulation state machine). Time only advances in Step Mode.
    pub fn allowed_in(self) -> &'static [Mode] {
        use Mode::*;
        match self {
            Call::SetupExperiment | Call::EnterInitializationMode => &[Instantiated],
            Call::ExitInitializationMode => &[InitializationMode],
            Call::Terminate => &[StepComplete, StepFailed, EventMode],
            Call::Get => &[
                InitializationMode,
                StepComplete,
                StepFailed,
                Terminated,
                Error,
                EventMode,
            ],
            Call::Set => &[Instantiated, InitializationMode, StepComplete, EventMode],
            Call::GetState | Call::SerializeState | Call::SetState | Call::FreeState => &[
                Instantiated,
                InitializationMode,
                StepComplete,
                StepFailed,
                Terminated,
                Error,
                EventMode,
            ],
            Call::DoStep => &[StepComplete],
            Call::GetStatus => &[StepComplete, StepFailed, Terminated],
            Call::EnterEventMode => &[StepComplete],
            Call::UpdateDiscreteStates | Call::EnterStepMode => &[EventMode],
        }
    }
}

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
            return Err(self.fail(call, &format!("startTime = {start_time} is not finite")));
        }
        if let Some(stop) = stop_time {
            if !(stop.is_finite() && stop > start_time) {
                return Err(self.fail(
                    call,
                    &format!("stopTime = {stop} must be finite and greater than startTime = {start_time}"),
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
