//! The co-simulation state machine's vocabulary: the modes, the calls it tells apart
//! and where each is legal, and how an FMI 3.0 importer drives it (`EventOptions`).

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
    /// fmi2GetDirectionalDerivative, fmi3GetDirectionalDerivative.
    GetDirectionalDerivative,
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
            Call::GetDirectionalDerivative => names.get_directional_derivative,
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
            // FMI 2.0.x section 4.2.4: where the reads are (in stepFailed and error for
            // debugging only); FMI 3.0: Initialization, Event and Step Mode, Terminated.
            Call::Get | Call::GetDirectionalDerivative => &[
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

/// How an FMI 3.0 importer instantiated a co-simulation instance
/// (fmi3InstantiateCoSimulation's eventModeUsed and earlyReturnAllowed). FMI 2.0
/// instances use neither.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EventOptions {
    /// The importer handles events in Event Mode: fmi3ExitInitializationMode enters Event
    /// Mode, and a step that ends at an event asks for it (eventHandlingNeeded).
    pub event_mode_used: bool,
    /// The importer accepts a step that ends before its communication point: the model
    /// then stops at its internal events (`Model::do_step_until_event`).
    pub early_return_allowed: bool,
}
