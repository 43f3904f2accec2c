//! The structural model a scene's fidelity level asks for: a beam or plane-stress model
//! (`structure`), or a `modal` reduction of one of them.

use crate::linear_structure::sparse_modal::reduce_section;
use crate::modal::reduce;
use crate::scene::{CheckedScene, FidelityLevel, ModalBasis};
use crate::structure::{ModelError, StructuralModel};

impl StructuralModel {
    /// The model the scene's fidelity asks for; an unresolved `auto` level is refused.
    ///
    /// A scene with a `[structure]` gets that structure's full model at
    /// `fidelity.level = plane-stress`, and its reduction at `modal`: the lowest
    /// `fidelity.modes` modes of the full model plus, with `fidelity.static_correction`,
    /// the static shape under a unit force at the contact DOF (the tip), as the beam's
    /// modal level. `fidelity.modal_basis` is ignored there: the structure is the basis.
    /// A structure too wide for the band (a 3D solid) is reduced from its sparse
    /// matrices (`sparse_modal::reduce_section`); its full model is refused. (The check
    /// refuses `beam`.)
    pub fn build(scene: &CheckedScene) -> Result<Self, ModelError> {
        let fidelity = &scene.fidelity;
        if let Some(section) = &scene.structure {
            return match fidelity.level {
                FidelityLevel::Modal => {
                    reduce_section(section, fidelity.modes, fidelity.static_correction)
                }
                FidelityLevel::Auto => Err(ModelError::UnresolvedAuto),
                FidelityLevel::Beam | FidelityLevel::PlaneStress => Self::from_section(section),
            };
        }
        match fidelity.level {
            FidelityLevel::Beam => Ok(Self::beam(scene, fidelity.beam_elements)),
            FidelityLevel::PlaneStress => Ok(Self::plane_stress(scene, fidelity.element_size)),
            FidelityLevel::Modal => {
                let full = match fidelity.modal_basis {
                    ModalBasis::Beam => Self::beam(scene, fidelity.beam_elements),
                    ModalBasis::PlaneStress => Self::plane_stress(scene, fidelity.element_size),
                };
                reduce(&full, fidelity.modes, fidelity.static_correction)
            }
            FidelityLevel::Auto => Err(ModelError::UnresolvedAuto),
        }
    }
}
