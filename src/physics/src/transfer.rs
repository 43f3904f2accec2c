//! Scene-relative resolution: what a front point measured on one scene (the paper's)
//! asks for on another.
//!
//! A front point's mode count is a property of the scene it was measured on. What
//! carries over is the cut-off it stands for: the highest retained angular frequency
//! relative to the scene's first one, omega_N / omega_1. On another scene the point
//! keeps every mode of that scene's own model (the same basis: beam or plane-stress
//! mesh) up to omega_1' omega_N / omega_1 ([`modes_for_scene`]).
//!
//! Measured (`cargo run --release -p stickslip --example mode_cutoff`: the modal model
//! against the full model it reduces, same step and integrator, largest tip deviation
//! over the first stick-slip cycle; README "Measured", docs/speed-accuracy.md):
//! - The truncation error follows the cut-off relative to omega_1, not the absolute one.
//!   With the paper's 5 modes (324.6 Hz) the error is 0.142 um on the paper scene and
//!   0.002 to 0.023 um on the 1.5 m and 2.5 m beams and on aluminium, whose 5th modes
//!   lie at 577, 208 and 117 Hz. An absolute cut-off (the same omega_N dt) would give
//!   aluminium 8 modes where 3 already stay below the paper's error (0.10 um).
//! - On the plane-stress mesh of a stubby beam (L/h = 10) axial modes fall among the
//!   bending modes and do not take part: the 3rd and the 7th mode leave the error
//!   unchanged (13.7 and 2.36 um at 2e-5 s). Counting modes up to a frequency rather than
//!   a number keeps as many bending modes as the paper point had, and the axial modes
//!   below the cut-off on top. For every Euler-Bernoulli cantilever omega_n / omega_1 is
//!   the same, so on the beam basis, and on slender meshes (the paper mesh's first axial
//!   mode is above its 10th bending mode), the rule keeps the count.
//!
//! Beam element counts are already relative to the length, and bending wavelengths
//! scale with it, so they carry over as they are. The plane-stress element size is kept
//! in metres: scaled with the height it coarsens the stubby beam's mesh to the 0.01 m
//! one (first-cycle error 7.3 um against 0.31 um for 0.005 m, issue 17's verification),
//! scaled with the length it asks 100 times the paper mesh's elements.

use crate::modal::modes_of;
use crate::scene::{CheckedScene, ModalBasis, Scene, MAX_MODES};
use crate::structure::{ModelError, StructuralModel};
use crate::study::{Configuration, FrontPoint, Resolution};

/// Relative slack of the cut-off comparison, so that a scene's own point maps to itself
/// despite the eigen solver's round-off (1e-10 relative on omega^2).
const CUTOFF_SLACK: f64 = 1e-6;

/// The modal basis a resolution reduces, on `scene`; `None` for the full models.
fn basis(resolution: Resolution, scene: &CheckedScene) -> Option<StructuralModel> {
    match resolution {
        Resolution::Modal { .. } => {
            Some(StructuralModel::beam(scene, scene.fidelity.beam_elements))
        }
        Resolution::PlaneStressModal { element_size, .. } => {
            Some(StructuralModel::plane_stress(scene, element_size))
        }
        _ => None,
    }
}

/// omega_N / omega_1 of `model`'s lowest `modes` modes.
fn cutoff_ratio(model: &StructuralModel, modes: usize) -> Result<f64, ModelError> {
    let eigen = modes_of(model, modes)?;
    Ok((eigen.eigenvalues[modes - 1] / eigen.eigenvalues[0]).sqrt())
}

/// The number of modes of `model` with omega_n <= `ratio` omega_1 (at least 1, at most
/// [`MAX_MODES`] and the model's size).
pub fn modes_below(model: &StructuralModel, ratio: f64) -> Result<usize, ModelError> {
    let limit = MAX_MODES.min(model.dofs());
    let mut asked = 8.min(limit);
    loop {
        let eigen = modes_of(model, asked)?;
        let bound = (ratio * (1.0 + CUTOFF_SLACK)).powi(2) * eigen.eigenvalues[0];
        let count = eigen.eigenvalues.iter().filter(|&&w2| w2 <= bound).count();
        if count < asked || asked == limit {
            return Ok(count.max(1));
        }
        asked = (2 * asked).min(limit);
    }
}

/// The mode count on `scene` of a modal resolution measured on `measured_on`: every
/// mode of the scene's basis up to the same omega_N / omega_1 (module doc); `None` for
/// the full models.
pub fn modes_for_scene(
    resolution: Resolution,
    measured_on: &CheckedScene,
    scene: &CheckedScene,
) -> Result<Option<usize>, ModelError> {
    let modes = match resolution {
        Resolution::Modal { modes } | Resolution::PlaneStressModal { modes, .. } => modes,
        _ => return Ok(None),
    };
    match (basis(resolution, measured_on), basis(resolution, scene)) {
        (Some(from), Some(to)) => {
            let ratio = cutoff_ratio(&from, modes.min(from.dofs()))?;
            Ok(Some(modes_below(&to, ratio)?))
        }
        _ => Ok(None),
    }
}

/// `configuration`, measured on `measured_on`, as it applies to `scene`: modal
/// resolutions get the scene's mode count ([`modes_for_scene`]); everything else, and
/// any configuration whose spectra cannot be computed (the run will then report why),
/// is kept.
pub fn for_scene(
    configuration: Configuration,
    measured_on: &CheckedScene,
    scene: &CheckedScene,
) -> Configuration {
    let Ok(Some(modes)) = modes_for_scene(configuration.resolution, measured_on, scene) else {
        return configuration;
    };
    let resolution = match configuration.resolution {
        Resolution::Modal { .. } => Resolution::Modal { modes },
        Resolution::PlaneStressModal { element_size, .. } => Resolution::PlaneStressModal {
            element_size,
            modes,
        },
        other => other,
    };
    Configuration {
        resolution,
        ..configuration
    }
}

/// The paper-scene front as it applies to `scene`: each point through [`for_scene`], its
/// measured cost and error kept (they order the front). The paper scene's own spectra
/// are computed with `scene`'s beam element count and clamp, so that only geometry,
/// material and mesh differ. A scene that does not check is returned unchanged.
pub fn front_for_scene(scene: &Scene, front: &[FrontPoint]) -> Vec<FrontPoint> {
    let Ok(checked) = scene.clone().check() else {
        return front.to_vec();
    };
    let mut paper = Scene::default();
    paper.fidelity.beam_elements = checked.fidelity.beam_elements;
    paper.fidelity.clamp = checked.fidelity.clamp;
    paper.fidelity.modal_basis = ModalBasis::Beam;
    let Ok(paper) = paper.check() else {
        return front.to_vec();
    };
    front
        .iter()
        .map(|p| FrontPoint {
            configuration: for_scene(p.configuration, &paper, &checked),
            ..*p
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scheme;

    fn modal(resolution: Resolution) -> Configuration {
        Configuration {
            resolution,
            dt: 1e-4,
            scheme: Scheme::GeneralizedAlpha,
            inference: None,
        }
    }

    #[test]
    fn the_paper_scene_maps_to_itself_and_beams_keep_their_count() {
        let paper = CheckedScene::paper();
        for resolution in [
            Resolution::Modal { modes: 5 },
            Resolution::PlaneStressModal {
                element_size: 0.02,
                modes: 10,
            },
        ] {
            assert_eq!(
                for_scene(modal(resolution), &paper, &paper).resolution,
                resolution
            );
        }
        // Every Euler-Bernoulli cantilever has the same omega_n / omega_1: another length
        // or material keeps the beam basis's count.
        let mut other = Scene::default();
        other.geometry.length = 1.5;
        other.material.youngs_modulus = 70e9;
        let other = other.check().unwrap();
        let five = Resolution::Modal { modes: 5 };
        assert_eq!(for_scene(modal(five), &paper, &other).resolution, five);
        // Full models are kept.
        let beam = Resolution::Beam { elements: 10 };
        assert_eq!(for_scene(modal(beam), &paper, &other).resolution, beam);
    }

    #[test]
    fn a_stubby_mesh_keeps_the_bending_modes_and_adds_the_axial_ones_below_the_cutoff() {
        // L/h = 10: the first axial mode (c / 4L, 15.5 omega_1 here) falls between the
        // 2nd and 3rd bending modes, and shear lowers the higher bending modes relative
        // to omega_1, so more modes lie under the paper point's cut-off.
        let paper = CheckedScene::paper();
        let mut stubby = Scene::default();
        stubby.geometry.length = 0.2;
        stubby.geometry.height = 0.02;
        stubby.material.youngs_modulus = 40e6;
        let stubby = stubby.check().unwrap();
        let resolution = Resolution::PlaneStressModal {
            element_size: 0.005,
            modes: 5,
        };
        let mapped = modes_for_scene(resolution, &paper, &stubby)
            .unwrap()
            .unwrap();
        assert!(mapped > 5, "{mapped}");
        // The cut-off is respected: the mapped count's highest mode is under it and the
        // next one above.
        let ratio = cutoff_ratio(&basis(resolution, &paper).unwrap(), 5).unwrap();
        let model = basis(resolution, &stubby).unwrap();
        let eigen = modes_of(&model, mapped + 1).unwrap();
        let w = |n: usize| (eigen.eigenvalues[n] / eigen.eigenvalues[0]).sqrt();
        assert!(w(mapped - 1) <= ratio && w(mapped) > ratio, "{ratio}");
    }
}
