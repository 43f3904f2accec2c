//! A learned friction law with memory (issue 24, item 3): rate-and-state friction with
//! its parameters fitted to force records under velocity histories, plus a small
//! network correction (`law` says why this form and what is trained).
//!
//! - `evolution`: the state's evolution, by the aging (`aging`) or the slip law
//!   (`slip`), each stepped exactly for the step's end velocity;
//! - `regularised`: the force, regularised at v = 0 (asinh form);
//! - `correction`: the network part;
//! - `law`: [`LearnedStateLaw`], the three together, with the gradients training needs;
//! - `file`: the weights file (`stickslip-state-friction`, version 1);
//! - `stepped`: [`LearnedStateFriction`], the law with its state as a
//!   `crate::friction::state::StatefulLaw` of the time loop and NeuralFriction;
//!
//! Where a scene names it (`friction.law = neural` with a file of this format) is
//! `crate::law_source::learned_state`; its velocity-step response, read as that of any
//! law with state, `crate::friction::state::response`. Training (the time series,
//! their CSV form, the fit) is `stickslip_train::learned_state`.

pub mod aging;
pub mod correction;
pub mod evolution;
pub mod file;
pub mod law;
pub mod regularised;
pub mod slip;
pub mod state_step;
pub mod stepped;

pub use correction::{Correction, InputScale};
pub use evolution::{StateEvolution, StateStep};
pub use file::{StateLawFile, StateMetrics, StateTrainingInfo, TrainingRanges};
pub use law::{LearnedStateLaw, StateLawParameters, StepForce};
pub use stepped::LearnedStateFriction;
