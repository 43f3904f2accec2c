//! The structural model a scene's fidelity level asks for: a beam or plane-stress model
//! (`structure`), or a `modal` reduction of one of them.

use crate::modal::reduce;
use crate::scene::{CheckedScene, FidelityLevel, ModalBasis};
use crate::structure::{ModelError, StructuralModel};

impl StructuralModel {
    /// The model the scene's fidelity asks for; an unresolved `auto` level is refused.
    /// A scene with a `[structure]` gets that structure's full model (its check allows
    /// only `fidelity.level = plane-stress` with it).
    pub fn build(scene: &CheckedScene) -> Result<Self, ModelError> {
        if let Some(section) = &scene.structure {
            return Self::from_section(section);
        }
        let fidelity = &scene.fidelity;
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
