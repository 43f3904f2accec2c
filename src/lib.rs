//! Stick-slip cantilever beam with analytical or neural friction.
//!
//! The physics (scene, structural models, integrator, contact, friction laws) is plain
//! Rust; the FMI 2.0 layer is a thin adapter over it.

pub mod auto;
pub mod banded;
pub mod cli;
pub mod contact;
pub mod element;
pub mod fmu;
pub mod friction;
pub mod integrator;
pub mod mesh;
pub mod metrics;
pub mod modal;
pub mod neural;
pub mod scene;
pub mod simulation;
pub mod structure;
pub mod study;
