//! The FMI versions this library speaks. One state machine (`instance`) serves both;
//! they differ in the C interface (`ffi2`, `ffi3`), the model description, and the names
//! of the functions in the log.

/// The FMI version an instance was instantiated through. The state machine is shared:
/// FMI 3.0 co-simulation without event mode has the same modes as FMI 2.0 (Step Mode is
/// `StepComplete`; fmi3EnterInitializationMode does fmi2SetupExperiment's work), so only
/// the function names in the log differ. With eventModeUsed an FMI 3.0 instance also
/// has Event Mode (`instance::Mode::EventMode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmiVersion {
    V2,
    V3,
}

/// The names a version's log gives the functions (and arguments) that the shared code
/// reports on. A message is written with the name of the function that was called, so
/// nothing is ever rewritten afterwards: a reason or a path is logged as it is.
#[derive(Debug)]
pub struct Names {
    /// The status a failed call returns, as the log categories' descriptions name it.
    pub error_status: &'static str,
    pub warning_status: &'static str,
    /// The function that creates an instance (FMI 3.0: co-simulation, the only kind).
    pub instantiate: &'static str,
    /// The argument that names the resources folder.
    pub resource_argument: &'static str,
    pub set_debug_logging: &'static str,
    /// The function that sets the start and stop time (FMI 3.0 does it on entering
    /// Initialization Mode).
    pub setup_experiment: &'static str,
    pub enter_initialization_mode: &'static str,
    pub exit_initialization_mode: &'static str,
    pub terminate: &'static str,
    /// Any get or set (the state machine's name for the call).
    pub get_any: &'static str,
    pub set_any: &'static str,
    pub get_real: &'static str,
    pub get_integer: &'static str,
    pub get_boolean: &'static str,
    pub get_string: &'static str,
    pub set_real: &'static str,
    pub set_integer: &'static str,
    pub set_boolean: &'static str,
    pub set_string: &'static str,
    pub do_step: &'static str,
    /// Any of FMI 2.0's fmi2Get*Status (FMI 3.0 has none).
    pub get_status_any: &'static str,
    pub get_fmu_state: &'static str,
    pub set_fmu_state: &'static str,
    pub free_fmu_state: &'static str,
    /// Serialization and deserialization together (the state machine's name).
    pub serialize_any: &'static str,
    pub serialized_fmu_state_size: &'static str,
    pub serialize_fmu_state: &'static str,
    pub deserialize_fmu_state: &'static str,
    /// The argument that holds an FMU state.
    pub fmu_state_argument: &'static str,
    pub get_directional_derivative: &'static str,
    /// The capability flag of directional derivatives in the model description.
    pub directional_derivative_flag: &'static str,
}

const FMI2: Names = Names {
    error_status: "fmi2Error",
    warning_status: "fmi2Warning",
    instantiate: "fmi2Instantiate",
    resource_argument: "fmuResourceLocation",
    set_debug_logging: "fmi2SetDebugLogging",
    setup_experiment: "fmi2SetupExperiment",
    enter_initialization_mode: "fmi2EnterInitializationMode",
    exit_initialization_mode: "fmi2ExitInitializationMode",
    terminate: "fmi2Terminate",
    get_any: "fmi2Get*",
    set_any: "fmi2Set*",
    get_real: "fmi2GetReal",
    get_integer: "fmi2GetInteger",
    get_boolean: "fmi2GetBoolean",
    get_string: "fmi2GetString",
    set_real: "fmi2SetReal",
    set_integer: "fmi2SetInteger",
    set_boolean: "fmi2SetBoolean",
    set_string: "fmi2SetString",
    do_step: "fmi2DoStep",
    get_status_any: "fmi2Get*Status",
    get_fmu_state: "fmi2GetFMUstate",
    set_fmu_state: "fmi2SetFMUstate",
    free_fmu_state: "fmi2FreeFMUstate",
    serialize_any: "fmi2(De)SerializeFMUstate",
    serialized_fmu_state_size: "fmi2SerializedFMUstateSize",
    serialize_fmu_state: "fmi2SerializeFMUstate",
    deserialize_fmu_state: "fmi2DeSerializeFMUstate",
    fmu_state_argument: "FMUstate",
    get_directional_derivative: "fmi2GetDirectionalDerivative",
    directional_derivative_flag: "providesDirectionalDerivative",
};

const FMI3: Names = Names {
    error_status: "fmi3Error",
    warning_status: "fmi3Warning",
    instantiate: "fmi3InstantiateCoSimulation",
    resource_argument: "resourcePath",
    set_debug_logging: "fmi3SetDebugLogging",
    setup_experiment: "fmi3EnterInitializationMode",
    enter_initialization_mode: "fmi3EnterInitializationMode",
    exit_initialization_mode: "fmi3ExitInitializationMode",
    terminate: "fmi3Terminate",
    get_any: "fmi3Get*",
    set_any: "fmi3Set*",
    get_real: "fmi3GetFloat64",
    get_integer: "fmi3GetInt32",
    get_boolean: "fmi3GetBoolean",
    get_string: "fmi3GetString",
    set_real: "fmi3SetFloat64",
    set_integer: "fmi3SetInt32",
    set_boolean: "fmi3SetBoolean",
    set_string: "fmi3SetString",
    do_step: "fmi3DoStep",
    get_status_any: "fmi3Get*Status",
    get_fmu_state: "fmi3GetFMUState",
    set_fmu_state: "fmi3SetFMUState",
    free_fmu_state: "fmi3FreeFMUState",
    serialize_any: "fmi3(De)SerializeFMUState",
    serialized_fmu_state_size: "fmi3SerializedFMUStateSize",
    serialize_fmu_state: "fmi3SerializeFMUState",
    deserialize_fmu_state: "fmi3DeserializeFMUState",
    fmu_state_argument: "FMUState",
    get_directional_derivative: "fmi3GetDirectionalDerivative",
    directional_derivative_flag: "providesDirectionalDerivatives",
};

impl FmiVersion {
    /// The names of this version's functions in the log.
    pub fn names(self) -> &'static Names {
        match self {
            FmiVersion::V2 => &FMI2,
            FmiVersion::V3 => &FMI3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instance::Call;

    #[test]
    fn each_version_names_its_own_functions() {
        assert_eq!(Call::Get.name(FmiVersion::V2), "fmi2Get*");
        assert_eq!(Call::Get.name(FmiVersion::V3), "fmi3Get*");
        assert_eq!(
            Call::SetupExperiment.name(FmiVersion::V3),
            "fmi3EnterInitializationMode"
        );
        assert_eq!(
            Call::SerializeState.name(FmiVersion::V3),
            "fmi3(De)SerializeFMUState"
        );
        let (two, three) = (FmiVersion::V2.names(), FmiVersion::V3.names());
        assert_eq!(two.deserialize_fmu_state, "fmi2DeSerializeFMUstate");
        assert_eq!(three.deserialize_fmu_state, "fmi3DeserializeFMUState");
        assert_eq!(three.get_integer, "fmi3GetInt32");
        // Every FMI 2.0 name is an FMI 2.0 function's, every FMI 3.0 name an FMI 3.0 one's.
        for (names, prefix) in [(two, "fmi2"), (three, "fmi3")] {
            for name in [
                names.instantiate,
                names.setup_experiment,
                names.get_real,
                names.set_string,
                names.do_step,
                names.get_fmu_state,
                names.serialized_fmu_state_size,
            ] {
                assert!(name.starts_with(prefix), "{name}");
            }
        }
    }
}
