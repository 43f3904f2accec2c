//! The physics' error types: the messages users read (the command line prints them after
//! `error: `, the FMUs log them), and the `source()` chains that let a caller find the
//! underlying cause (a pivot, an I/O error) without parsing the text.

use std::error::Error;
use stickslip::auto::{choose, paper_front, AutoError};
use stickslip::banded::NotPositiveDefinite;
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::{LawSource, NetworkOrigin};
use stickslip::neural::NeuralLaw;
use stickslip::scene::{FidelityLevel, Scene, SceneError, Scheme};
use stickslip::simulation::{SimulationError, Simulator, StateMismatch};
use stickslip::structure::{ModelError, StructuralModel};
use stickslip::study::{measure, Configuration, MeasureError, Resolution};

/// Every error in `e`'s `source()` chain, `e` first.
fn chain<'a>(e: &'a (dyn Error + 'static)) -> Vec<&'a (dyn Error + 'static)> {
    std::iter::successors(Some(e), |&e| e.source()).collect()
}

#[test]
fn scene_messages_name_the_field_value_and_requirement() {
    let mut scene = Scene::default();
    scene.material.youngs_modulus = -1.0;
    let e = scene.check().unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid scene: material.youngs_modulus = -1e0; it must be finite and > 0 (Pa)"
    );
    assert_eq!(
        SceneError::Parse("x.toml: unknown extension; use .toml or .json".into()).to_string(),
        "scene file: x.toml: unknown extension; use .toml or .json"
    );
}

#[test]
fn a_singular_matrix_keeps_its_pivot_as_the_source() {
    let pivot = NotPositiveDefinite {
        row: 3,
        pivot: -1.5,
    };
    assert_eq!(
        pivot.to_string(),
        "matrix is not positive definite: pivot -1.5e0 at row 3"
    );
    let e = SimulationError::from(ModelError::Singular {
        matrix: "stiffness",
        source: pivot.clone(),
    });
    // The simulation error is the model error, message and cause.
    assert_eq!(
        e.to_string(),
        "stiffness matrix is singular: matrix is not positive definite: pivot -1.5e0 at row 3"
    );
    let cause = e
        .source()
        .and_then(|s| s.downcast_ref::<NotPositiveDefinite>());
    assert_eq!(cause, Some(&pivot));
    assert_eq!(
        ModelError::DependentSubspace.to_string(),
        "reduced mass matrix is singular: subspace vectors became linearly dependent"
    );
}

#[test]
fn a_state_that_does_not_fit_says_why() {
    let mut scene = Scene::default();
    scene.fidelity.level = FidelityLevel::Beam;
    scene.fidelity.beam_elements = 5;
    let scene = scene.check().unwrap();
    let law = LawSource::resolve(&scene).unwrap().law().unwrap();
    let mut sim = Simulator::new(scene, law).unwrap();
    let mut state = sim.state().clone();
    state.kinematics.velocity.pop();
    let e = sim.restore(state).unwrap_err();
    assert_eq!(
        e,
        StateMismatch("velocity has 9 entries, the model has 10 degrees of freedom".into())
    );
    assert_eq!(
        e.to_string(),
        "saved state does not fit this model: velocity has 9 entries, the model has 10 degrees of freedom"
    );
}

#[test]
fn too_many_modes_and_a_bad_target_are_reported_with_their_numbers() {
    let mut scene = Scene::default();
    scene.fidelity.level = FidelityLevel::Modal;
    scene.fidelity.beam_elements = 5;
    scene.fidelity.modes = 50;
    let e = StructuralModel::build(&scene.check().unwrap()).unwrap_err();
    assert_eq!(
        e,
        ModelError::TooManyModes {
            asked: 50,
            available: 10
        }
    );
    assert_eq!(
        e.to_string(),
        "fidelity.modes = 50 exceeds the 10 degrees of freedom of the full model"
    );

    let scene = Scene::default().check().unwrap();
    let law = LawSource::resolve(&scene).unwrap().law().unwrap();
    let mut sim = Simulator::new(scene, law).unwrap();
    let e = sim.advance_to(-1.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "cannot advance to t = -1e0 s from t = 0e0 s: the target must be finite and not in the past"
    );
}

#[test]
fn a_failed_study_run_names_its_configuration_and_keeps_the_reason_as_source() {
    let configuration = Configuration {
        resolution: Resolution::Modal { modes: 1 },
        dt: 3e-4,
        scheme: Scheme::GeneralizedAlpha,
        inference: None,
    };
    let failed = measure(
        &Scene::default(),
        &stickslip_tests::law_of(&Scene::default()),
        configuration,
    )
    .unwrap_err();
    assert_eq!(
        failed.to_string(),
        "modal 1 modes, dt 3e-4 s, generalized-alpha: time step 0.0003 s does not divide the comparison interval 0.001 s"
    );
    assert!(matches!(failed.reason, MeasureError::Interval { dt } if dt == 3e-4));
    assert!(failed
        .source()
        .is_some_and(|s| s.downcast_ref::<MeasureError>().is_some()));
}

/// A calibration run of `fidelity = auto` that fails (a configuration whose law the
/// network cannot serve): the message says which run failed and why. Weights that cannot
/// be read fail before any calibration run, when the law is resolved (once, for every
/// run), and the chain reaches the file's error.
#[test]
fn a_failed_auto_calibration_leads_down_to_the_file_error() {
    let mut scene = Scene::default();
    scene.time.end = 0.01;
    scene.friction.law = FrictionLawKind::Neural;
    let front = paper_front().unwrap();
    let three =
        NeuralLaw::from_json(&stickslip_tests::three_input_weights(), "three.json").unwrap();
    let law = LawSource::network(
        std::sync::Arc::new(three),
        NetworkOrigin::Weights("three.json".into()),
        scene.friction.inference,
        scene.loading.normal_force,
    );
    let e = choose(&scene, &law, 1e-3, &front, &mut |_| {}).unwrap_err();
    assert!(matches!(e, AutoError::Calibration(_)), "{e:?}");
    // The first calibration run is the cheapest front point's (the front is data).
    let message = e.to_string();
    assert!(
        message.starts_with(&format!(
            "fidelity = auto, running {}: friction.weights: weights file three.json: ",
            front[0].configuration
        )),
        "{message}"
    );

    scene.friction.weights = Some("/nonexistent/w.json".into());
    let e = LawSource::resolve(&scene.check().unwrap()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "friction.weights: weights file /nonexistent/w.json: no such file"
    );
    let neural = chain(&e)
        .into_iter()
        .find_map(|s| s.downcast_ref::<stickslip::neural::NeuralError>())
        .expect("the chain reaches the reader's error");
    assert!(
        matches!(neural, stickslip::neural::NeuralError::File(f)
            if f.problem == stickslip::files::InputProblem::Missing),
        "{neural:?}"
    );
}

#[test]
fn an_unmet_tolerance_says_what_would_be_needed() {
    let e = AutoError::Unmet {
        tolerance: 1e-12,
        best: 1.0389e-8,
        over: stickslip::auto::span(stickslip::auto::Reach::Whole, 1.2),
        among: "of the front data/pareto_front.json".to_string(),
    };
    assert_eq!(
        e.to_string(),
        "fidelity = auto: no configuration of the front data/pareto_front.json is verified to meet the tolerance 1e-12 m on this scene over the whole run, 0 to 1.200 s; the best achievable estimated largest tip deviation is 1.039e-8 m. Choose a tolerance of at least that, a shorter run, or a fidelity by hand."
    );
    let front = paper_front().unwrap();
    let e = stickslip::auto::check_front(&[front[1], front[0]]).unwrap_err();
    assert!(
        e.to_string().starts_with(&format!(
            "the front is not ordered: {} (",
            front[1].configuration
        )),
        "{e}"
    );
}
