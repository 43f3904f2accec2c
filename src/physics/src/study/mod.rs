//! The speed-accuracy study: one scene run over a grid of fidelity levels, time steps,
//! integrators, friction laws ([`Law`], issue 24) and, for the neural law, ways of
//! evaluating it (`friction.inference`), each run timed and compared with a converged
//! reference of its own law.
//!
//! For every configuration the study records the wall time (model build plus stepping,
//! as [`crate::run::run_scene`] measures it, runs one after the other so that no two
//! compete for a core) and these errors against the reference run:
//! - breakaway time, first major-slip duration and stick-slip period (s), from
//!   [`Summary`];
//! - deflection corridor after breakaway (m): the larger of the differences of its
//!   minimum and of its maximum;
//! - RMS of the tip-deflection difference over the whole run (m), on a 1 ms grid
//!   that every time step of the grid divides.
//!
//! The reference is the most expensive configuration of the grid unless given: by
//! default the finest plane-stress mesh (0.005 m) at the smallest step (1e-5 s) with
//! generalised-alpha, with the scene's own inference (exact by default). With a law
//! axis every law has its own reference, that configuration run with that law: an error
//! across laws would measure the laws' difference, not the discretisation's. A
//! configuration is on its law's Pareto front when no other run of that law is both
//! faster and more accurate (in RMS).
//!
//! One module per concept: [`configuration`] (what one run is), [`law`] (the law axis),
//! [`grid`] (the axes), [`measure`] (one timed run), [`errors`] (against a reference),
//! [`front`](mod@front) (the Pareto front), [`csv`] (study.csv) and [`run`](mod@run) (the whole study: per-law
//! references, rows, fronts).
//! The wall time does not include building the friction law (parsing the network,
//! tabulating it: 1 to 25 ms for the shipped networks), as [`run_scene`] times it.

pub mod configuration;
pub mod csv;
pub mod errors;
pub mod front;
pub mod grid;
pub mod law;
pub mod measure;
pub mod run;
#[cfg(test)]
mod tests;

pub use configuration::{Configuration, Resolution};
pub use csv::{csv_line, CSV_HEADER};
pub use errors::{rms_difference, Errors};
pub use front::{front, front_of, front_points, mark_pareto_front, FrontPoint, Row};
pub use grid::Grid;
pub use law::{Law, LawError};
pub use measure::{measure, measure_on, Failed, MeasureError, Measured, COMPARISON_INTERVAL};
pub use run::{run, Progress, Reference, Study, StudyError};
