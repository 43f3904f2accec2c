//! The physics of the stick-slip beam: plain Rust, with no C types, no command line and
//! no training.
//!
//! A scene (`scene`) is checked once into a `CheckedScene`. Its fidelity level
//! (`fidelity`) builds a structural model (`structure`: Hermite beam or Q8 plane stress
//! from `element` and `mesh` with `banded` solves, or a `modal` reduction of either),
//! which the `integrator` steps and the `contact` switches between stick and slip under
//! a `friction` law (analytical, or a trained network from `neural`, inference only),
//! resolved once per scene by `law_source`.
//! `simulation` ties these together step by step; `run` runs a scene to its end;
//! `metrics` reads breakaway, slips and period off a run; `study` measures speed against
//! accuracy, `transfer` carries a front point's mode count to another scene, and `auto`
//! picks the cheapest fidelity that meets a tolerance. `linear_structure` is a user's
//! structure from another FE code (matrices read by `stickslip_formats::calculix` or
//! `matrix_market`, or a Gmsh mesh that `plane_mesh` assembles in plane stress with the
//! built-in Q8), checked and solved for statics and modes. Beside the
//! dynamics: `statics`, the paper's static tip-load case and its mesh convergence
//! (Sec. 2.1); `stability`, closed-form cantilever frequencies, Rayleigh damping at two
//! modes and the belt speed above which steady sliding is stable. `choice` is the
//! `Choice` trait and `choice!` macro that every enumerated setting is declared with.
//! `elementary` holds the transcendental functions (exp, tanh, ...), from the pure-Rust
//! `libm` crate so that results are the same bits on every CPU and platform; `short`
//! prints numbers in messages short. `files` reads the files a user hands in and
//! writes outputs whole or not at all, for every crate above.
//!
//! The FMI adapter (`stickslip-fmi`), the command line (`stickslip-cli`) and the trainer
//! (`stickslip-train`) depend on this crate, never the reverse.

// The only unsafe code is the AVX2 dispatch (banded, neural::forward); a new block must
// say why it is sound.
#![deny(clippy::undocumented_unsafe_blocks)]
#![warn(clippy::missing_safety_doc)]

pub mod auto;
pub mod banded;
pub mod choice;
pub mod contact;
pub mod element;
pub mod elementary;
pub mod fidelity;
pub mod files;
pub mod friction;
pub mod integrator;
pub mod jacobian;
pub mod law_source;
pub mod linear_structure;
pub mod mesh;
pub mod metrics;
pub mod modal;
pub mod modal_slip;
pub mod neural;
pub mod plane_mesh;
pub mod run;
pub mod scene;
pub mod scene_preset;
pub mod short;
pub mod simulation;
pub mod stability;
pub mod statics;
pub mod structure;
pub mod study;
pub mod transfer;
pub mod user_structure;
