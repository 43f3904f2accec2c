//! Trains the neural friction law (the paper's Sec. 3) and writes the weights files that
//! `stickslip::neural` reads.
//!
//! - `error`: [`TrainError`], the one error type of the trainer;
//! - `data`: the paper's synthetic friction data (seeded) and data sets in general;
//!   `csv`: measured data from CSV files with named columns and units.
//! - `objective`: the training loss on standardised data and its gradient, by
//!   `backprop` (backpropagation through the physics crate's forward pass);
//!   `lbfgs`: full-batch L-BFGS with a strong-Wolfe line search;
//!   `train`: standardisation, the loss (and how its lambda maps to MATLAB's and
//!   scikit-learn's), metrics, history; `search`: grid search with k-fold CV.
//!
//! The L-BFGS is our own rather than argmin's: it reproduces the shipped weights byte for
//! byte (its summation order is part of that), and it was measured against the
//! scikit-learn peer (see `lbfgs`).
//!
//! # Decisions
//! - Loss: MSE on the raw target plus lambda/2 ||W||^2 of the raw-output network; maps
//!   to scikit-learn's alpha = n lambda / 2 (see `train` for MATLAB's fitrnet).
//! - CSV units come from the header, `name[unit]`; a bare `name` has an empty unit
//!   (see `csv`). They are written into the weights file with the features' names,
//!   order and roles.

pub mod backprop;
pub mod csv;
pub mod data;
mod error;
pub mod lbfgs;
pub mod learned_state;
pub mod objective;
pub mod search;
pub mod train;

pub use data::{Dataset, Quantity, Split, Synthetic};
pub use error::TrainError;
pub use train::{train, train_synthetic, TrainConfig, TrainReport};
