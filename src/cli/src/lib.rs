//! The `stickslip` command line: clap arguments and the commands behind them, over the
//! physics (`stickslip`) and the trainer (`stickslip-train`).
//!
//! - `scene_args`: the scene flags of `simulate`, `static` and `estimates`;
//! - `simulate`: `simulate` and `static`;
//! - `study`: `study` (and its `--verify-auto`);
//! - `train`: `train` and `search`; `train_memory`: `train-memory`;
//! - `import`: `import-network` (an ONNX network as a weights file, checked on data);
//! - `estimates`: `estimates` (beam-theory numbers of a scene, as JSON);
//! - `choice`: the command-line values of the scene's choices;
//! - `error`: [`CliError`], what a command reports when it fails.
//!
//! A library as well as a binary, so that the tests can run the commands in-process.

pub mod choice;
mod error;
pub mod estimates;
pub mod export_fmu;
pub mod import;
pub mod scene_args;
pub mod simulate;
pub mod study;
pub mod train;
pub mod train_memory;

pub use error::CliError;
