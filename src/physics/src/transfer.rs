//! Scene-relative resolution: what a front point measured on one scene (the paper's)
//! asks for on another.
//!
//! A front point's mode count is a property of the scene it was measured on. What
//! carries over is the cut-off it stands for: the highest retained angular frequency
//! relative to the scene's first one. On another scene the point keeps every mode of
//! that scene's own model (the same basis: beam or plane-stress mesh) up to
//! omega_1' sqrt(omega_N omega_(N+1)) / omega_1 ([`modes_for_scene`]): the cut-off sits
//! halfway (geometrically) between the point's last kept mode and the next one.
//!
//! Measured (`cargo run --release -p stickslip --example mode_cutoff`: the modal model
//! against the full model it reduces, same step and integrator, largest tip deviation
//! over the first stick-slip cycle; docs/measurements.md, docs/speed-accuracy.md):
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
//! The count is capped at twice the paper point's ([`MAX_COUNT_FACTOR`]).
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
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// Relative slack of the cut-off comparison, so that a point whose last two modes
/// coincide still maps to itself despite the eigen solver's round-off (1e-10 relative
/// on omega^2).
const CUTOFF_SLACK: f64 = 1e-6;

/// A point keeps at most this many times its paper-scene mode count. Shear crowds a
/// stubby beam's spectrum: under the cut-off of the paper's 10th mode (253 omega_1)
/// its 0.02 m mesh has 28 modes, while 8 modes of its 0.005 m mesh already leave
/// 0.003 um of truncation error at 2e-5 s (module doc), against 0.142 um for the paper
/// point's 5. The cap also bounds the eigen solve that the mapping costs.
const MAX_COUNT_FACTOR: usize = 2;

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

/// The spectra computed in this process (omega^2, ascending), by basis: `auto` maps the
/// same front for every tolerance and FMU instance of a scene, and every modal point of
/// one mesh shares that mesh's spectrum.
fn spectra() -> &'static Mutex<HashMap<String, Vec<f64>>> {
    static SPECTRA: OnceLock<Mutex<HashMap<String, Vec<f64>>>> = OnceLock::new();
    SPECTRA.get_or_init(|| Mutex::new(HashMap::new()))
}

/// The lowest `count` eigenvalues omega^2 of `resolution`'s basis on `scene` (fewer if
/// the basis has fewer dofs), from the cache when it holds as many.
fn spectrum(
    resolution: Resolution,
    scene: &CheckedScene,
    count: usize,
) -> Result<Vec<f64>, ModelError> {
    let size = match resolution {
        Resolution::PlaneStressModal { element_size, .. } => element_size,
        _ => 0.0,
    };
    // The basis depends on these fields only.
    let key = serde_json::to_string(&(
        resolution.kind(),
        size,
        &scene.geometry,
        &scene.material,
        scene.fidelity.clamp,
        scene.fidelity.beam_elements,
    ))
    .unwrap_or_default();
    if let Some(cached) = spectra().lock().ok().and_then(|c| c.get(&key).cloned()) {
        if cached.len() >= count {
            return Ok(cached[..count].to_vec());
        }
    }
    let Some(model) = basis(resolution, scene) else {
        return Ok(Vec::new());
    };
    let eigenvalues = modes_of(&model, count.min(model.dofs()))?.eigenvalues;
    if let Ok(mut c) = spectra().lock() {
        c.insert(key, eigenvalues.clone());
    }
    Ok(eigenvalues)
}

/// The number of eigenvalues omega_n^2 <= (`ratio` omega_1)^2 of `resolution`'s basis on
/// `scene`, at least 1 and at most `cap` (and the basis's size).
fn modes_below(
    resolution: Resolution,
    scene: &CheckedScene,
    ratio: f64,
    cap: usize,
) -> Result<usize, ModelError> {
    // One more than the cap tells whether the cap binds.
    let eigenvalues = spectrum(resolution, scene, cap.min(MAX_MODES) + 1)?;
    let Some(&first) = eigenvalues.first() else {
        return Ok(1);
    };
    let bound = (ratio * (1.0 + CUTOFF_SLACK)).powi(2) * first;
    let count = eigenvalues.iter().filter(|&&w2| w2 <= bound).count();
    Ok(count.clamp(1, cap.min(MAX_MODES)))
}

/// The mode count on `scene` of a modal resolution measured on `measured_on`: every
/// mode of the scene's basis up to the same cut-off relative to omega_1 (module doc); `None` for
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
    // The cut-off sits halfway (geometrically) between the point's last mode and the
    // next, so that a shift of a few 1e-4 in a frequency (the mesh's shear, another
    // slenderness) does not move a mode across it.
    let from = spectrum(resolution, measured_on, modes + 1)?;
    let (Some(first), Some(last)) = (from.first(), from.get(modes - 1)) else {
        return Ok(None);
    };
    let next = from.get(modes).copied().unwrap_or(*last);
    let ratio = (last * next).sqrt().sqrt() / first.sqrt();
    // At most twice the point's count (module doc: where shear crowds the spectrum).
    Ok(Some(modes_below(
        resolution,
        scene,
        ratio,
        MAX_COUNT_FACTOR * modes,
    )?))
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
    // Same geometry and material: the same spectra, nothing to map or compute.
    if paper.geometry == checked.geometry && paper.material == checked.material {
        return front.to_vec();
    }
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
        let paper_spectrum = spectrum(resolution, &paper, 6).unwrap();
        let ratio =
            (paper_spectrum[4] * paper_spectrum[5]).sqrt().sqrt() / paper_spectrum[0].sqrt();
        let eigen = modes_of(&basis(resolution, &stubby).unwrap(), mapped + 1).unwrap();
        let w = |n: usize| (eigen.eigenvalues[n] / eigen.eigenvalues[0]).sqrt();
        assert!(w(mapped - 1) <= ratio && w(mapped) > ratio, "{ratio}");
    }
}
