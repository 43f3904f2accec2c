//! Stick-slip cantilever beam with analytical or neural friction.
//!
//! The physics (scene, structural models, integrator, contact, friction laws) is plain
//! Rust; the FMI 2.0 layer is a thin adapter over it.

pub mod friction;
pub mod scene;
