//! Readers of other people's files, one module per format, each reading a foreign file
//! into plain data of its own (issue 34 item 7):
//! - `onnx`: an ONNX `ModelProto` (a protobuf reader of the ONNX schema and a
//!   graph-to-layers converter, pure Rust) into a chain of dense layers
//!   ([`onnx::OnnxNetwork`]);
//! - `calculix`: the matrices CalculiX writes for `*FREQUENCY, SOLVER=MATRIXSTORAGE`
//!   (`JOB.sti`, `JOB.mas`, `JOB.dof`) into [`structure_file::StructureMatrices`];
//! - `matrix_market`: Matrix Market `.mtx` coordinate files and a DOF map file, into the
//!   same;
//! - `structure_file`: what those two give (triplets, DOF labels) and their errors, which
//!   name the file, the line and the fault; both parse text (`FileText`): the physics
//!   opens the files (`stickslip::files`);
//! - `sniff`: which kind of network file a user handed in, told from its name or its
//!   first bytes ([`sniff::WeightsFileKind`]).
//!
//! - `gmsh`: a Gmsh MSH 4.1 ASCII mesh (nodes, elements, physical groups) into
//!   [`gmsh::Mesh`], which `stickslip::plane_mesh` assembles in plane stress (issue 35).
//!
//! # Direction
//! This crate knows nothing of the physics: it does not depend on `stickslip`, and its
//! types are its own (layers as `Vec<Vec<f64>>`, its own `Activation`, its own
//! errors). The physics (`stickslip::neural::onnx`) turns what it reads into a
//! `NeuralModel` and wraps its errors in `NeuralError`, so that a scene's
//! `friction.weights = "x.onnx"` is read inside `run_scene` with no callback. Nothing
//! here panics on bad input: every refusal is an error naming what is wrong.

pub mod calculix;
pub mod gmsh;
pub mod matrix_market;
pub mod onnx;
pub mod sniff;
pub mod structure_file;
