//! One point of the grid's discretisation: the structural resolution, the time step,
//! the integrator and the evaluation of a neural law. The law itself is not part of it
//! (see [`super::law`]): `auto`'s front (data/pareto_front.json) is a list of these, one
//! law's.

use crate::choice::Choice;
use crate::neural::inference::Inference;
use crate::scene::{FidelityLevel, ModalBasis, Scene, Scheme};
use serde::{Deserialize, Serialize};
use std::fmt;

/// The structural resolution of one configuration.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "level")]
pub enum Resolution {
    /// Modal reduction of the scene's beam (100 elements unless the scene says
    /// otherwise) with this many modes (plus the static correction).
    Modal { modes: usize },
    /// Euler-Bernoulli beam with this many elements.
    Beam { elements: usize },
    /// Plane-stress Q8 mesh with this target element size (m).
    PlaneStress { element_size: f64 },
    /// Modal reduction of the plane-stress mesh of this element size (m) with this many
    /// modes (plus the static correction): the scene's `fidelity.level = modal` with
    /// `fidelity.modal_basis = plane-stress`. Its modes come from shift-invert Lanczos
    /// (`modal::lanczos_modes`).
    PlaneStressModal { element_size: f64, modes: usize },
    /// A user's structure (the scene's `[structure]`) as its files give it, the full
    /// model: the scene's `fidelity.level = plane-stress` with the section.
    Structure,
    /// A user's structure reduced to this many modes (plus the static correction): the
    /// scene's `fidelity.level = modal` with the section (`auto::structure`).
    StructureModal { modes: usize },
}

impl Resolution {
    pub fn level(&self) -> FidelityLevel {
        match self {
            Resolution::Modal { .. } => FidelityLevel::Modal,
            Resolution::Beam { .. } => FidelityLevel::Beam,
            Resolution::PlaneStress { .. } => FidelityLevel::PlaneStress,
            Resolution::PlaneStressModal { .. } => FidelityLevel::Modal,
            Resolution::Structure => FidelityLevel::PlaneStress,
            Resolution::StructureModal { .. } => FidelityLevel::Modal,
        }
    }

    /// Whether the model is the plane-stress continuum (the full mesh or a modal basis
    /// of it) rather than Euler-Bernoulli beam theory: only the continuum has shear and
    /// the clamp's elasticity, the model error that beam-theory points share. A user's
    /// structure is its own continuum: no beam theory to refine.
    pub fn is_continuum(&self) -> bool {
        matches!(
            self,
            Resolution::PlaneStress { .. }
                | Resolution::PlaneStressModal { .. }
                | Resolution::Structure
                | Resolution::StructureModal { .. }
        )
    }

    /// The resolution's kind as study.csv's `level` column writes it: the fidelity
    /// level's name, except `plane-stress-modal` for the modal level on the mesh.
    pub fn kind(&self) -> &'static str {
        match self {
            Resolution::PlaneStressModal { .. } => "plane-stress-modal",
            Resolution::Structure => "structure",
            Resolution::StructureModal { .. } => "structure-modal",
            other => other.level().name(),
        }
    }
}

impl fmt::Display for Resolution {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Resolution::Modal { modes } => write!(f, "modal {modes} modes"),
            Resolution::Beam { elements } => write!(f, "beam {elements} el."),
            Resolution::PlaneStress { element_size } => {
                write!(f, "plane stress {element_size} m")
            }
            Resolution::PlaneStressModal {
                element_size,
                modes,
            } => write!(f, "modal {modes} modes of plane stress {element_size} m"),
            Resolution::Structure => write!(f, "the structure's full model"),
            Resolution::StructureModal { modes } => {
                write!(f, "modal {modes} modes of the structure")
            }
        }
    }
}

/// One point of the grid: resolution, time step, integrator and the evaluation of a
/// neural law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Configuration {
    pub resolution: Resolution,
    /// Time step (s).
    pub dt: f64,
    pub scheme: Scheme,
    /// `friction.inference`; None keeps the scene's (the `auto` fidelity's front has
    /// none, so that its choice leaves the inference alone).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inference: Option<Inference>,
}

impl Configuration {
    /// `scene` with this configuration's fidelity, time step, integrator and inference
    /// (if it has one); every other field (geometry, material, loading, friction,
    /// damping, end time) kept.
    pub fn apply(&self, scene: &Scene) -> Scene {
        let mut scene = scene.clone();
        scene.fidelity.level = self.resolution.level();
        match self.resolution {
            Resolution::Modal { modes } => {
                scene.fidelity.modes = modes;
                scene.fidelity.modal_basis = ModalBasis::Beam;
            }
            Resolution::Beam { elements } => scene.fidelity.beam_elements = elements,
            Resolution::PlaneStress { element_size } => scene.fidelity.element_size = element_size,
            Resolution::PlaneStressModal {
                element_size,
                modes,
            } => {
                scene.fidelity.modes = modes;
                scene.fidelity.element_size = element_size;
                scene.fidelity.modal_basis = ModalBasis::PlaneStress;
            }
            // The level alone: the structure is the scene's [structure].
            Resolution::Structure => {}
            Resolution::StructureModal { modes } => scene.fidelity.modes = modes,
        }
        scene.time.step = self.dt;
        scene.integrator.scheme = self.scheme;
        if let Some(inference) = self.inference {
            scene.friction.inference = inference;
        }
        scene
    }

    pub fn scheme_name(&self) -> &'static str {
        self.scheme.name()
    }
}

impl fmt::Display for Configuration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}, dt {:e} s, {}",
            self.resolution,
            self.dt,
            self.scheme_name()
        )?;
        match self.inference {
            Some(inference) => write!(f, ", {} inference", inference.name()),
            None => Ok(()),
        }
    }
}
