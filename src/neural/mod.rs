//! Neural-network friction law (issue 3), after Vater, Stender & Hoffmann, "Towards
//! neural network-based numerical friction models", PAMM 2023.
//!
//! - `data`: the paper's synthetic friction data (seeded) and data sets in general;
//!   `csv`: measured data from CSV files with named columns and units.
//! - `network`: fully connected network, batched forward pass and backpropagation;
//!   `lbfgs`: full-batch L-BFGS with a strong-Wolfe line search;
//!   `train`: standardisation, the loss (and how its lambda maps to MATLAB's and
//!   scikit-learn's), metrics, history; `search`: grid search with k-fold CV.
//! - `weights`: the self-describing JSON weights file; `law`: `NeuralLaw`, the trained
//!   model as a `crate::friction::FrictionLaw`.
//! - `cli`: the `stickslip train` and `stickslip search` commands.
//!
//! Two shipped models, trained on the paper's data with the default seed, are embedded:
//! `NeuralLaw::paper_default()` (plain, the paper's model) and `NeuralLaw::paper_signed()`.
//! `stickslip train` (and `--variant signed`) regenerates them byte for byte.

pub mod cli;
pub mod csv;
pub mod data;
mod error;
pub mod law;
pub mod lbfgs;
pub mod network;
pub mod search;
pub mod train;
pub mod weights;

use std::path::Path;

pub use data::{Dataset, FeatureRole, Quantity, Split, SyntheticSpec};
pub use error::NeuralError;
pub use law::NeuralLaw;
pub use network::Activation;
pub use train::{train, train_synthetic, TrainConfig, TrainReport};
pub use weights::{NeuralModel, Variant};

use crate::friction::FrictionLaw;

/// The shipped plain-variant weights (`weights/paper-plain.json`).
pub const PAPER_PLAIN_JSON: &str = include_str!("../../weights/paper-plain.json");
/// The shipped signed-variant weights (`weights/paper-signed.json`).
pub const PAPER_SIGNED_JSON: &str = include_str!("../../weights/paper-signed.json");

/// The shipped model of `variant` as the beam's friction law.
pub fn default_friction_law(variant: Variant) -> Result<Box<dyn FrictionLaw>, NeuralError> {
    match variant {
        Variant::Plain => NeuralLaw::paper_default()?,
        Variant::Signed => NeuralLaw::paper_signed()?,
    }
    .into_friction_law()
}

/// A weights file as the beam's friction law; refused (with the reason) if the model's
/// features are not exactly what the beam supplies (sliding velocity, normal force).
/// For models with further features use `NeuralLaw::from_file(..)?.with_fixed_feature(..)`.
pub fn load_friction_law(path: &Path) -> Result<Box<dyn FrictionLaw>, NeuralError> {
    NeuralLaw::from_file(path)?.into_friction_law()
}
