//! The `stickslip` command line: clap arguments and the commands behind them, over the
//! physics (`stickslip`) and the trainer (`stickslip-train`).
//!
//! - `simulate`: `simulate`, `static` and `study`;
//! - `train`: `train` and `search`;
//! - `choice`: the command-line values of the scene's choices;
//! - `error`: [`CliError`], what a command reports when it fails.
//!
//! A library as well as a binary, so that the tests can run the commands in-process.

pub mod choice;
mod error;
pub mod simulate;
pub mod train;

pub use error::CliError;
