//! The verification scenes and the check of a choice against a scene's reference.

use super::{choose, window_deviation, AutoError, Selection};
use crate::law_source::LawSource;
use crate::scene::Scene;
use crate::study::{measure, rms_difference, Configuration, FrontPoint, Measured, Resolution};

/// The scenes on which `stickslip study --verify-auto` checks the choice: the paper's
/// and ten that move the answer: belt speed (more, shorter cycles or fewer, longer
/// ones), beam length (stiffer tip and higher frequencies, or the reverse), normal
/// force (later breakaway, larger deflections), material (aluminium: other wave speed
/// and stiffness), friction law (Coulomb: no velocity weakening; the shipped neural
/// network), and a stubby beam (L/h = 10, soft material so that the tip still deflects
/// by millimetres) where shear makes Euler-Bernoulli off by about 1 %.
pub fn verification_scenes() -> Vec<(&'static str, Scene)> {
    let paper = Scene::default();
    let with = |edit: &dyn Fn(&mut Scene)| {
        let mut scene = paper.clone();
        edit(&mut scene);
        scene
    };
    vec![
        ("paper", paper.clone()),
        ("belt 0.05 m/s", with(&|s| s.loading.belt_speed = 0.05)),
        ("belt 0.01 m/s", with(&|s| s.loading.belt_speed = 0.01)),
        ("beam 1.5 m", with(&|s| s.geometry.length = 1.5)),
        ("beam 2.5 m", with(&|s| s.geometry.length = 2.5)),
        (
            "normal force 180 N",
            with(&|s| s.loading.normal_force = 180.0),
        ),
        (
            "aluminium",
            with(&|s| {
                s.material.youngs_modulus = 70e9;
                s.material.density = 2700.0;
            }),
        ),
        (
            "coulomb",
            with(&|s| s.friction.law = crate::friction::FrictionLawKind::Coulomb),
        ),
        (
            "neural",
            with(&|s| s.friction.law = crate::friction::FrictionLawKind::Neural),
        ),
        (
            "stubby 0.2 m x 0.02 m E 40 MPa",
            with(&|s| {
                s.geometry.length = 0.2;
                s.geometry.height = 0.02;
                s.material.youngs_modulus = 40e6;
            }),
        ),
    ]
}

/// The choice on one scene, checked against the scene's own converged reference over
/// the whole run.
#[derive(Clone, Debug)]
pub struct Verification {
    pub choice: Selection,
    /// Largest tip deviation of the choice from the reference over the whole run (m).
    pub true_error: f64,
    /// RMS tip deviation of the choice from the reference over the whole run (m).
    pub true_rms: f64,
    /// Wall time of the choice's run over the whole run (s).
    pub seconds: f64,
    /// The next cheaper front point and its largest deviation from the reference over
    /// the whole run (m).
    pub cheaper: Option<(Configuration, f64)>,
}

impl Verification {
    /// The choice meets the tolerance and the next cheaper point does not.
    pub fn holds(&self, tolerance: f64) -> bool {
        self.true_error <= tolerance && self.cheaper.is_none_or(|(_, e)| e > tolerance)
    }
}

/// Runs [`choose`] on `scene` (the bound over its whole run, to `time.end`), then
/// measures the choice and the next cheaper point against `reference` (an already
/// measured run of the same scene) over the whole run.
pub fn verify(
    scene: &Scene,
    law: &LawSource,
    tolerance: f64,
    front: &[FrontPoint],
    reference: &Measured,
) -> Result<Verification, AutoError> {
    let choice = choose(scene, law, tolerance, front, &mut |_| {})?;
    let front = &super::front::for_scene(scene, front)?;
    let run_of = |configuration: Configuration| -> Result<Measured, AutoError> {
        measure(scene, law, configuration).map_err(|f| AutoError::Verification(f.reason))
    };
    let chosen = run_of(choice.configuration)?;
    let cheaper = match choice.index.checked_sub(1) {
        Some(k) => {
            let run = run_of(front[k].configuration)?;
            Some((
                front[k].configuration,
                window_deviation(&run.tip, &reference.tip),
            ))
        }
        None => None,
    };
    Ok(Verification {
        choice,
        true_error: window_deviation(&chosen.tip, &reference.tip),
        true_rms: rms_difference(&chosen.tip, &reference.tip),
        seconds: chosen.seconds,
        cheaper,
    })
}

/// A run finer than `reference`, to check that the reference is converged: half its
/// time step and, for a modal basis, twice its modes.
pub fn finer(reference: Configuration) -> Configuration {
    let resolution = match reference.resolution {
        Resolution::PlaneStressModal {
            element_size,
            modes,
        } => Resolution::PlaneStressModal {
            element_size,
            modes: 2 * modes,
        },
        Resolution::Modal { modes } => Resolution::Modal { modes: 2 * modes },
        Resolution::StructureModal { modes } => Resolution::StructureModal { modes: 2 * modes },
        other => other,
    };
    Configuration {
        resolution,
        dt: reference.dt / 2.0,
        ..reference
    }
}
