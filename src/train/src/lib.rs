//! Trains the neural friction law (the paper's Sec. 3) and writes the weights files that
//! `stickslip::neural` reads.
//!
//! - `error`: [`TrainError`], the one error type of the trainer;
//! - `data`: the paper's synthetic friction data (seeded) and data sets in general;
//!   `csv`: measured data from CSV files with named columns and units.
//! - `objective`: the training loss on standardised data and its gradient;
//!   `lbfgs`: full-batch L-BFGS with a strong-Wolfe line search;
//!   `train`: standardisation, the loss (and how its lambda maps to MATLAB's and
//!   scikit-learn's), metrics, history; `search`: grid search with k-fold CV.
//!
//! The L-BFGS is our own rather than argmin's: it reproduces the shipped weights byte for
//! byte (its summation order is part of that), and it was measured against the
//! scikit-learn peer (see `lbfgs`).

pub mod csv;
pub mod data;
mod error;
pub mod lbfgs;
pub mod objective;
pub mod search;
pub mod train;

pub use data::{Dataset, Quantity, Split, Synthetic};
pub use error::TrainError;
pub use train::{train, train_synthetic, TrainConfig, TrainReport};
