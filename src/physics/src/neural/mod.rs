//! Neural-network friction law, after Vater, Stender & Hoffmann, "Towards
//! neural network-based numerical friction models", PAMM 2023.
//!
//! This module holds what the simulation needs to *use* a trained network:
//! - `network`: fully connected network and its batched forward pass (the trainer's);
//! - `forward`: the single-sample forward pass of the time-step loop (blocked layout,
//!   vectorisable tanh, the slope by forward mode), in f64 or f32;
//! - `weights`: the self-describing JSON weights file (with `synthetic`'s
//!   `SyntheticSpec`, the generator settings a trained model records); `law`: `NeuralLaw`, the trained
//!   model as a `crate::friction::FrictionLaw`;
//! - `inference`: `Inference`, how the time loop evaluates a network (exact, f32, table);
//! - `table`: the network tabulated at initialisation, with its verified error (the
//!   law as `friction.inference` asks is built by `crate::law_source`);
//! - `onnx`: networks exported to ONNX (PyTorch, Keras, scikit-learn), read by
//!   `stickslip_formats::onnx` into a dense chain and turned here into the same
//!   `NeuralModel`;
//! - `error`: `NeuralError`, why a weights file or an evaluation was refused.
//!
//! The learned law with memory (rate-and-state with trained parameters and a network
//! correction, shipped as `weights/rate-and-state-learned.json`) is a friction law
//! beside the others: `crate::friction::learned_state`.
//!
//! Training (data, CSV, backpropagation, L-BFGS, the objective, search) lives in the
//! `stickslip-train` crate, and the `stickslip train` / `stickslip search` commands in
//! `stickslip-cli`.
//!
//! # Shipped models
//! Two models trained with the default seed (2) are embedded, on the synthetic data of
//! the generator as it was before the paper authors' published data were read
//! (`SyntheticPreset::Former`: F_n in [90, 110] N, 0.02 N additive noise; the default
//! generator now draws the authors' distribution, with 2 % relative noise; why the
//! shipped networks stay is in docs/decisions.md):
//! `NeuralLaw::paper_default()` (plain, the paper's 3 x 100 tanh network, lambda 0.004,
//! 200 L-BFGS iterations) and `NeuralLaw::paper_signed()`. These commands regenerate
//! them byte for byte (default `--threads 2`; matrixmultiply picks its kernel by CPU
//! features at run time, so a CPU without AVX2/FMA may differ in the last bits):
//!
//! ```text
//! stickslip train --generator former --out weights/paper-plain.json
//! stickslip train --generator former --variant signed --lambda 1e-5 --iterations 1000 \
//!     --out weights/paper-signed.json
//! ```
//!
//! The signed model uses a weaker penalty: with no jump to smooth, lambda 0.004 only
//! biases the smooth magnitude (test MSE 0.0036 N^2 instead of the noise floor 0.0004).
//!
//! # Decisions
//! - Names, units, order and roles of the features travel in the weights file (see
//!   `weights`); the trainer's decisions (loss, CSV units) are in `stickslip_train`.
//! - Inputs outside the training range are clamped to it (see `law`).
//! - A model is the beam's `FrictionLaw` only if it has a sliding-velocity and a
//!   normal-force feature and every other feature is given a fixed value (see `law`).
//! - Matrix products: nalgebra's gemm, i.e. `matrixmultiply`, measured at ~50 GFLOP/s
//!   per core here (100 x 100 by 100 x 1750); products are under a third of a training
//!   evaluation (tanh and element-wise work dominate), so faer could not be clearly
//!   faster and was not added. The trainer's backward pass uses the same
//!   `network::gemm`.

mod error;
pub(crate) mod file_checks;
pub mod forward;
pub mod inference;
pub mod jacobian;
pub mod law;
pub mod network;
pub mod onnx;
mod synthetic;
pub mod table;
pub mod weights;

pub use error::NeuralError;
pub use law::NeuralLaw;
pub use network::Activation;
pub use weights::{FeatureRole, NeuralModel, StopReason, SyntheticPreset, SyntheticSpec, Variant};

pub use law::{PAPER_PLAIN_JSON, PAPER_SIGNED_JSON};

/// Why a scene's neural law could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SceneLawError {
    /// `source` names the file (made by [`SceneLawError::weights`]), so the message
    /// names it once.
    #[error("friction.weights: {source}")]
    Weights { path: String, source: NeuralError },
    #[error("shipped neural weights: {0}")]
    Shipped(NeuralError),
}

impl SceneLawError {
    /// The weights file `path` refused for `source`, which is made to name the file.
    pub fn weights(path: &str, source: NeuralError) -> SceneLawError {
        SceneLawError::Weights {
            path: path.to_string(),
            source: source.in_file(std::path::Path::new(path)),
        }
    }
}
