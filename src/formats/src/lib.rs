//! Readers of other people's files, one module per format, each reading a foreign file
//! into plain data of its own (issue 34 item 7):
//! - `onnx`: an ONNX `ModelProto` (a protobuf reader of the ONNX schema and a
//!   graph-to-layers converter, pure Rust) into a chain of dense layers
//!   ([`onnx::OnnxNetwork`]);
//! - `sniff`: which kind of network file a user handed in, told from its name or its
//!   first bytes ([`sniff::WeightsFileKind`]).
//!
//! The structure readers that come next (CalculiX .inp, Matrix Market, Gmsh; issue 35)
//! belong here too, as `calculix`, `matrix_market`, `gmsh`.
//!
//! # Direction
//! This crate knows nothing of the physics: it does not depend on `stickslip`, and its
//! types are its own (layers as `Vec<Vec<f64>>`, its own `Activation`, its own
//! errors). The physics (`stickslip::neural::onnx`) turns what it reads into a
//! `NeuralModel` and wraps its errors in `NeuralError`, so that a scene's
//! `friction.weights = "x.onnx"` is read inside `run_scene` with no callback. Nothing
//! here panics on bad input: every refusal is an error naming what is wrong.

pub mod onnx;
pub mod sniff;
