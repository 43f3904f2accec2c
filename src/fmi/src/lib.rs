//! The FMI 2.0 and 3.0 co-simulation layer: a thin adapter between the plain-Rust
//! physics and the C interfaces that FMI importers call, over one version-neutral
//! instance.
//!
//! One library serves two FMUs, told apart by the GUID passed to `fmi2Instantiate` (the
//! instantiationToken of `fmi3InstantiateCoSimulation`):
//! - `StickSlipBeam` (`beam`): the beam with its stick-slip contact and a friction law
//!   (analytical, neural, or supplied from outside through inputs);
//! - `NeuralFriction` (`friction`): the friction law alone, for coupling.
//!
//! Rooms:
//! - `model`: the `Model` trait each FMU's model implements, and its `ModelInfo`;
//! - `variables`: the table type each model fills once (names, value references, units,
//!   accessors);
//! - `model_description`: generates modelDescription.xml from that table;
//! - `declare`: the macros both models write their variable rows with; `law_state`: the
//!   friction law's state variables as output rows;
//! - `beam` (a folder: variables, build, saved states, the `Model`), `friction`: the
//!   models;
//! - `networks`: the neural weights files a model reads from the FMU's `resources/`;
//! - `version`: FMI 2.0 or 3.0, and the function names of each in the log;
//! - `instance`: the FMI state machine, logging and FMU state, in plain Rust;
//! - `boundary`: what both C interfaces share and neither version owns (the component
//!   behind an instance pointer, C strings and arrays, FMU-state handles, catching
//!   panics);
//! - `ffi2`: the 34 FMI 2.0 `extern "C"` functions, which only convert C arguments;
//! - `ffi3`: the 75 FMI 3.0 functions over the same instances (the FMUs under
//!   `target/fmu/3.0/`), and `ffi3::values3`, what an FMI 3.0 Float64 request stands
//!   for (time, arrays, scalars). Neither interface calls the other.

// The C interfaces rest on what the importer promises about its pointers: each unsafe
// function states those promises and each unsafe block names the one it relies on.
#![deny(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]
#![warn(clippy::missing_safety_doc)]

pub mod beam;
mod boundary;
mod declare;
pub mod export;
pub mod ffi2;
pub mod ffi3;
pub mod friction;
pub mod instance;
mod law_state;
pub mod model;
pub mod model_description;
pub mod networks;
pub mod variables;
pub mod version;
pub mod xml;

use model::{Model, ModelInfo};

/// The FMUs this library serves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmuKind {
    StickSlipBeam,
    NeuralFriction,
}

impl FmuKind {
    pub const ALL: [FmuKind; 2] = [FmuKind::StickSlipBeam, FmuKind::NeuralFriction];

    pub fn info(self) -> &'static ModelInfo {
        match self {
            FmuKind::StickSlipBeam => &beam::StickSlipBeam::INFO,
            FmuKind::NeuralFriction => &friction::NeuralFriction::INFO,
        }
    }

    pub fn model_identifier(self) -> &'static str {
        self.info().model_identifier
    }

    /// The generated modelDescription.xml.
    pub fn model_description(self) -> String {
        match self {
            FmuKind::StickSlipBeam => model_description::generate::<beam::StickSlipBeam>(),
            FmuKind::NeuralFriction => model_description::generate::<friction::NeuralFriction>(),
        }
    }

    /// The generated FMI 3.0 modelDescription.xml.
    pub fn model_description3(self) -> String {
        match self {
            FmuKind::StickSlipBeam => model_description::generate3::<beam::StickSlipBeam>(),
            FmuKind::NeuralFriction => model_description::generate3::<friction::NeuralFriction>(),
        }
    }

    /// The GUID written into modelDescription.xml: a hash of everything else in it, so it
    /// changes whenever the interface does.
    pub fn guid(self) -> String {
        match self {
            FmuKind::StickSlipBeam => model_description::guid::<beam::StickSlipBeam>(),
            FmuKind::NeuralFriction => model_description::guid::<friction::NeuralFriction>(),
        }
    }

    pub fn from_guid(guid: &str) -> Option<FmuKind> {
        FmuKind::ALL.into_iter().find(|k| k.guid() == guid)
    }
}
