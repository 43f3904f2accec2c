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

/// The scenes on which `stickslip study --verify-auto --auto-with-state` checks the
/// choice for the laws with state (issue 36): the paper scene with each law (LuGre,
/// rate-and-state with the aging and the slip law, the learned law with memory of
/// `learned_weights`, e.g. weights/rate-and-state-learned.json), and scenes that move
/// what the state does: rate-and-state near its stick-slip threshold (D_c* = 4.35e-4 m
/// on the paper beam, friction-with-memory.md; at D_c = 1.74e-4 m = 0.4 D_c* the tip
/// still sticks in each of the 13 cycles of 3 s, at 2.6e-4 m = 0.6 D_c* it sticks three
/// times and then slides on a limit cycle: modal 4 modes, 1e-4 s), LuGre with soft
/// bristles (sigma0 = 1e6 N/m, 160 times the tip stiffness rather than 1600: 50 um of
/// presliding at breakaway, a period of 0.287 s against 0.20 s), belt speeds, a longer
/// beam and a larger normal force.
pub fn verification_scenes_with_state(learned_weights: &str) -> Vec<(&'static str, Scene)> {
    use crate::friction::rate_and_state::{StateEvolution, CHARACTERISTIC_SLIP, STATE_EVOLUTION};
    use crate::friction::{lugre, FrictionLawKind};
    let with_law = |law: FrictionLawKind, edit: &dyn Fn(&mut Scene)| {
        let mut scene = Scene::default();
        scene.friction.law = law;
        edit(&mut scene);
        scene
    };
    let learned = |scene: &mut Scene| scene.friction.weights = Some(learned_weights.into());
    let slip_law = |scene: &mut Scene| {
        let slip = f64::from(crate::choice::Choice::code(StateEvolution::Slip));
        scene.friction.laws.set(&STATE_EVOLUTION, slip);
    };
    let (lugre, rate_state) = (FrictionLawKind::Lugre, FrictionLawKind::RateAndState);
    vec![
        ("lugre paper", with_law(lugre, &|_| {})),
        ("rate-and-state paper", with_law(rate_state, &|_| {})),
        (
            "rate-and-state slip law paper",
            with_law(rate_state, &slip_law),
        ),
        (
            "learned memory paper",
            with_law(FrictionLawKind::Neural, &learned),
        ),
        (
            "rate-and-state D_c 0.4 D_c* (sticks)",
            with_law(rate_state, &|s| {
                s.friction.laws.set(&CHARACTERISTIC_SLIP, 1.74e-4)
            }),
        ),
        (
            "rate-and-state D_c 0.6 D_c* (stops sticking)",
            with_law(rate_state, &|s| {
                s.friction.laws.set(&CHARACTERISTIC_SLIP, 2.6e-4)
            }),
        ),
        (
            "lugre soft bristles 1e6 N/m",
            with_law(lugre, &|s| {
                s.friction.laws.set(&lugre::BRISTLE_STIFFNESS, 1e6)
            }),
        ),
        (
            "lugre belt 0.05 m/s",
            with_law(lugre, &|s| s.loading.belt_speed = 0.05),
        ),
        (
            "rate-and-state belt 0.05 m/s",
            with_law(rate_state, &|s| s.loading.belt_speed = 0.05),
        ),
        (
            "rate-and-state beam 1.5 m",
            with_law(rate_state, &|s| s.geometry.length = 1.5),
        ),
        (
            "learned memory normal force 180 N",
            with_law(FrictionLawKind::Neural, &|s| {
                learned(s);
                s.loading.normal_force = 180.0;
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
