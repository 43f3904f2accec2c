//! How the network is evaluated as the beam's friction law (`friction.inference`, the
//! choice [`Inference`] of the scene): speed for accuracy, each option's largest error
//! measured when it is built.
//!
//! - `exact`: the network in f64, as trained (`NeuralLaw`).
//! - `f32`: the same network in single precision ([`NeuralLaw::in_f32`]): half the
//!   bytes of weights to stream and twice the values per vector register. Its largest
//!   deviation from the exact network is measured at build over the training range
//!   (`law::F32_SAMPLES` points).
//! - `table`: the network tabulated at initialisation over its training range
//!   (`table::LawTable`): piecewise cubic in the sliding velocity, linear in the normal
//!   force, refined until its error is below [`table::TABLE_TOLERANCE`], the largest
//!   error verified at build on points between the nodes. It supports networks whose
//!   inputs are the sliding velocity and the normal force (or the velocity alone) and
//!   refuses others.
//!
//! The slip solve uses the law's slope either way: the f32 network differentiates in
//! f32, the table its own interpolant (so Newton sees a consistent law).

use super::error::NeuralError;
use super::law::NeuralLaw;
use super::table::TableLaw;
use crate::choice::Choice;
use crate::friction::FrictionLaw;
use crate::scene::Inference;

/// `law` as the beam's friction law, evaluated as `inference` asks; the table is built
/// at `normal_force` (N), the force the beam will press with. Refused with the reason
/// if the model cannot serve the beam, or the table cannot cover its inputs.
pub fn friction_law(
    law: NeuralLaw,
    inference: Inference,
    normal_force: f64,
) -> Result<Box<dyn FrictionLaw>, NeuralError> {
    match inference {
        Inference::Exact => law.into_friction_law(),
        Inference::F32 => law.in_f32().into_friction_law(),
        Inference::Table => {
            if let Some(reason) = TableLaw::refusal(&law) {
                return Err(NeuralError::Inference {
                    inference: Inference::Table.name(),
                    reason,
                });
            }
            if let Some(problem) = law.beam_problem() {
                return Err(NeuralError::NotAFrictionLaw(problem));
            }
            Ok(Box::new(TableLaw::build(law, normal_force)))
        }
    }
}
