//! Helpers shared by the fuzz targets and the seed writer (`seeds.rs`).
//!
//! The targets feed outside bytes to the crate's own entry points. Parsing and
//! validation always run in full; only the work that follows a successful parse
//! (building and stepping a simulation) is skipped for inputs that are valid but would
//! take long, so that the fuzzer keeps its speed. Those limits lie far inside what the
//! crate accepts (`scene::MAX_DOFS`, `scene::MAX_STEPS`): an input skipped here is a
//! legitimate, merely expensive, request.

use std::path::{Path, PathBuf};
use stickslip::scene::{
    plane_stress_divisions, FidelityLevel, Friction, Loading, ModalBasis, Scene, Time,
};

/// Probe feature vectors for a loaded model: per feature its training minimum,
/// maximum, middle, zero, and values far outside (-1e300, f64::MAX); all finite.
pub fn probes(model: &stickslip::neural::NeuralModel) -> Vec<Vec<f64>> {
    (0..6)
        .map(|k| {
            model
                .features
                .iter()
                .map(|f| match k {
                    0 => f.min,
                    1 => f.max,
                    2 => 0.5 * f.min + 0.5 * f.max,
                    3 => 0.0,
                    4 => -1e300,
                    _ => f64::MAX,
                })
                .collect()
        })
        .collect()
}

/// The shipped weights folder, standing in for an unpacked FMU's `resources/`.
pub fn resources() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../weights")
}

/// A per-process scratch file for targets that read a file path, as the CLI does.
/// `STICKSLIP_FUZZ_TMP` chooses the folder (default: `$TMPDIR/stickslip-fuzz`).
pub fn scratch_file(target: &str, extension: &str) -> PathBuf {
    let dir = std::env::var_os("STICKSLIP_FUZZ_TMP")
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("stickslip-fuzz"));
    std::fs::create_dir_all(&dir).expect("cannot create the fuzz scratch folder");
    dir.join(format!("{target}-{}.{extension}", std::process::id()))
}

/// Degrees of freedom of the plane-stress mesh of a checked scene, if at most `limit`
/// and at most 8 elements through the height (the band width grows with those).
fn plane_stress_dofs(scene: &Scene, limit: usize) -> Option<usize> {
    let (nx, ny) = plane_stress_divisions(&scene.geometry, scene.fidelity.element_size);
    if nx > limit || ny > 8 {
        return None;
    }
    let dofs = 2 * ((2 * nx + 1) * (ny + 1) + (nx + 1) * ny);
    (dofs <= limit).then_some(dofs)
}

/// Whether the structural model of a scene that passed `Scene::check` builds in a few
/// milliseconds. Not `auto`: resolving it runs the scene several times.
pub fn cheap_to_build(scene: &Scene) -> bool {
    let f = &scene.fidelity;
    match f.level {
        FidelityLevel::Auto => false,
        FidelityLevel::Beam => f.beam_elements <= 100,
        FidelityLevel::PlaneStress => plane_stress_dofs(scene, 1200).is_some(),
        FidelityLevel::Modal => {
            f.modes <= 12
                && match f.modal_basis {
                    ModalBasis::Beam => f.beam_elements <= 40,
                    ModalBasis::PlaneStress => plane_stress_dofs(scene, 300).is_some(),
                }
        }
    }
}

/// For a scene held in an FMU state: false when the FMU could build an expensive model
/// from it. The FMU checks the scene after replacing the time span, the loading and the
/// friction law with its own values, so those are neutralised here: if the rest fails
/// the check, the FMU refuses the scene too and builds nothing.
pub fn fmu_scene_is_cheap(scene: &Scene) -> bool {
    let mut probe = scene.clone();
    probe.time = Time::default();
    probe.loading = Loading::default();
    probe.friction = Friction::default();
    match probe.check() {
        Err(_) => true,
        Ok(checked) => cheap_to_build(&checked),
    }
}

/// A weights name that the FMU resolves inside `resources/` (no folder separators).
/// Other names (absolute paths, `../..`) would make the FMU read arbitrary files of the
/// machine running the fuzzer; the FMU-state target skips states that hold them.
pub fn weights_name_stays_in_resources(name: &str) -> bool {
    !name.contains('/') && !name.contains('\\')
}
