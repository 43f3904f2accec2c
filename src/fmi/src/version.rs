//! The FMI versions this library speaks. One state machine (`instance`) serves both;
//! they differ in the C interface (`ffi`, `ffi3`), the model description, and the names
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

impl FmiVersion {
    /// The name of an FMI 2.0 function (or a message naming them) in this version.
    pub fn rename(self, fmi2: &str) -> String {
        match self {
            FmiVersion::V2 => fmi2.to_string(),
            FmiVersion::V3 => {
                let mut name = fmi2.to_string();
                for (old, new) in [
                    ("fmi2SetupExperiment", "fmi3EnterInitializationMode"),
                    ("fmi2GetReal", "fmi3GetFloat64"),
                    ("fmi2SetReal", "fmi3SetFloat64"),
                    ("fmi2GetInteger", "fmi3GetInt32"),
                    ("fmi2SetInteger", "fmi3SetInt32"),
                    ("fmi2DeSerializeFMUstate", "fmi3DeserializeFMUState"),
                    ("fmi2(De)SerializeFMUstate", "fmi3(De)SerializeFMUState"),
                    ("fmi2SerializeFMUstate", "fmi3SerializeFMUState"),
                    ("fmi2SerializedFMUstateSize", "fmi3SerializedFMUStateSize"),
                    ("FMUstate", "FMUState"),
                    ("fmi2", "fmi3"),
                ] {
                    name = name.replace(old, new);
                }
                name
            }
        }
    }
}
