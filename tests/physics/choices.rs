//! Every choice of a scene is one `Choice` enum: its words are the scene file's words,
//! its positions are the FMI codes. `fidelity.level = auto` and `friction.law =
//! external` are scene values; a stand-alone run refuses them with a clear error until
//! auto is resolved (and always for external, whose force only the FMU has).

use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::LawSource;
use stickslip::neural::inference::Inference;
use stickslip::neural::{Activation, Variant};
use stickslip::run::{run_scene, RunError};
use stickslip::scene::{
    Clamp, FidelityLevel, HoldingForce, InitialState, ModalBasis, Scene, Scheme, SlidingVelocity,
};
use stickslip::structure::{ModelError, StructuralModel};
use stickslip_fmi::friction::NeuralFrictionLaw;

/// For each value of a choice: serde writes and reads its word, its code is its 1-based
/// position, and words are unique and described.
macro_rules! check_choice {
    ($t:ty) => {{
        let mut seen = std::collections::HashSet::new();
        for (k, &c) in <$t>::ALL.iter().enumerate() {
            let word = serde_json::Value::String(c.name().to_string());
            assert_eq!(serde_json::to_value(c).unwrap(), word, "{c:?}");
            assert_eq!(serde_json::from_value::<$t>(word).unwrap(), c);
            assert_eq!(c.code(), k as i32 + 1, "{c:?}");
            assert_eq!(<$t>::from_code(c.code()), Some(c));
            assert_eq!(<$t>::from_name(c.name()), Some(c));
            assert!(!c.description().is_empty(), "{c:?}");
            assert!(seen.insert(c.name()), "{} twice", c.name());
        }
        assert_eq!(<$t>::from_code(0), None);
        assert_eq!(<$t>::from_code(<$t>::ALL.len() as i32 + 1), None);
        assert!(!<$t>::TYPE_NAME.is_empty() && !<$t>::TYPE_DESCRIPTION.is_empty());
    }};
}

#[test]
fn every_choice_word_is_its_scene_word_and_its_position_its_fmi_code() {
    check_choice!(FrictionLawKind);
    check_choice!(HoldingForce);
    check_choice!(SlidingVelocity);
    check_choice!(InitialState);
    check_choice!(FidelityLevel);
    check_choice!(ModalBasis);
    check_choice!(Clamp);
    check_choice!(Scheme);
    check_choice!(NeuralFrictionLaw);
    check_choice!(Variant);
    check_choice!(Activation);
    check_choice!(Inference);
}

/// The FMI interface numbers these values: auto and external are item 4 of their types,
/// after the levels and laws that a stand-alone run has; the laws with state came later
/// and follow as items 5 and 6, and every law added since after them, so that the codes
/// of the earlier laws stay (the lists' heads are asserted; a new law appends).
#[test]
fn auto_and_external_keep_their_fmi_items_and_type_names() {
    let words = |all: &[FrictionLawKind]| all.iter().map(|c| c.name()).collect::<Vec<_>>();
    assert_eq!(
        words(FrictionLawKind::ALL)[..6],
        [
            "exponential",
            "coulomb",
            "neural",
            "external",
            "lugre",
            "rate-and-state"
        ]
    );
    assert_eq!(FrictionLawKind::TYPE_NAME, "FrictionModel");
    let levels: Vec<&str> = FidelityLevel::ALL.iter().map(|c| c.name()).collect();
    assert_eq!(levels, ["modal", "beam", "plane-stress", "auto"]);
    assert_eq!(FidelityLevel::Auto.code(), 4);
    assert_eq!(FrictionLawKind::External.code(), 4);
    let laws: Vec<&str> = NeuralFrictionLaw::ALL.iter().map(|c| c.name()).collect();
    // The laws with state come after, so that saved codes 1 and 2 keep their meaning.
    assert_eq!(
        laws[..4],
        ["neural", "exponential", "lugre", "rate-and-state"]
    );
    assert_eq!(NeuralFrictionLaw::TYPE_NAME, "FrictionLaw");
}

#[test]
fn a_scene_file_names_auto_with_its_tolerance_and_external() {
    let scene = Scene::from_toml_str(
        "[fidelity]\nlevel = \"auto\"\ntolerance = 2e-4\n[friction]\nlaw = \"external\"\n",
    )
    .unwrap();
    assert_eq!(scene.fidelity.level, FidelityLevel::Auto);
    assert_eq!(scene.fidelity.tolerance, Some(2e-4));
    assert_eq!(scene.friction.law, FrictionLawKind::External);
    let checked = scene.check().unwrap();
    // JSON reads back the same scene; an absent tolerance stays absent.
    let json = serde_json::to_string(&*checked).unwrap();
    assert_eq!(&Scene::from_json_str(&json).unwrap(), checked.scene());
    let plain = serde_json::to_string(&Scene::default()).unwrap();
    assert!(!plain.contains("tolerance"), "{plain}");
}

#[test]
fn auto_takes_the_default_or_a_finite_positive_tolerance() {
    let mut scene = Scene::default();
    scene.fidelity.level = FidelityLevel::Auto;
    // Absent: the default, the same as the FMU's start value (issue 17, item 6).
    assert!(scene.clone().check().is_ok());
    assert_eq!(
        stickslip::auto::tolerance_of(&scene),
        stickslip::auto::DEFAULT_TOLERANCE
    );
    for bad in [0.0, -1e-4, f64::NAN, f64::INFINITY] {
        scene.fidelity.tolerance = Some(bad);
        let error = scene.clone().check().unwrap_err();
        assert_eq!(error.field(), Some("fidelity.tolerance"), "{bad}: {error}");
    }
    scene.fidelity.tolerance = Some(1e-4);
    assert!(scene.clone().check().is_ok());
    // A concrete level ignores a tolerance, but a given one must still make sense.
    scene.fidelity.level = FidelityLevel::Beam;
    assert!(scene.clone().check().is_ok());
    scene.fidelity.tolerance = Some(-1.0);
    assert!(scene.check().is_err());
}

/// An auto scene that was not resolved reaches no model: the error says what to do.
#[test]
fn an_unresolved_auto_scene_builds_no_model_and_does_not_run() {
    let mut scene = Scene::default();
    scene.fidelity.level = FidelityLevel::Auto;
    scene.fidelity.tolerance = Some(1e-4);
    let checked = scene.check().unwrap();
    let error = StructuralModel::build(&checked).err().unwrap();
    assert_eq!(error, ModelError::UnresolvedAuto);
    assert!(error.to_string().contains("resolve"), "{error}");
    let law = LawSource::resolve(&checked).unwrap();
    let error = run_scene(checked, &law, 1).err().unwrap();
    assert!(
        error.to_string().contains("fidelity.level = auto"),
        "{error}"
    );
}

#[test]
fn the_external_law_is_refused_by_a_stand_alone_run() {
    let mut scene = Scene::default();
    scene.friction.law = FrictionLawKind::External;
    scene.fidelity.level = FidelityLevel::Modal;
    let checked = scene.check().unwrap();
    let law = LawSource::resolve(&checked).unwrap();
    assert!(law.is_external());
    assert!(matches!(
        run_scene(checked.clone(), &law, 1),
        Err(RunError::External)
    ));
    let error = run_scene(checked, &law, 1).err().unwrap().to_string();
    for needle in ["friction.law = external", "StickSlipBeam", "exponential"] {
        assert!(error.contains(needle), "{needle}: {error}");
    }
}

/// `auto::resolve` turns an auto scene into the concrete scene of its choice, and leaves
/// any other scene as it is.
#[test]
fn resolve_replaces_auto_by_the_choice_and_leaves_concrete_scenes_alone() {
    let front = stickslip::auto::paper_front().unwrap();
    let law = stickslip_tests::law_of(&Scene::default());
    let (same, none) =
        stickslip::auto::resolve(Scene::default(), &law, &front, &mut |_| {}).unwrap();
    assert_eq!(same, Scene::default());
    assert!(none.is_none());

    let mut scene = Scene::default();
    scene.time.end = 0.6;
    scene.fidelity.level = FidelityLevel::Auto;
    scene.fidelity.tolerance = Some(1e-4);
    let (resolved, choice) =
        stickslip::auto::resolve(scene.clone(), &law, &front, &mut |_| {}).unwrap();
    let choice = choice.unwrap();
    assert_ne!(resolved.fidelity.level, FidelityLevel::Auto);
    assert_eq!(resolved, choice.configuration.apply(&scene));
    assert!(choice.estimated_error <= 1e-4);
    assert!(run_scene(resolved.check().unwrap(), &law, 1).is_ok());

    // Without a tolerance: the default's choice, the same as asking for it.
    scene.fidelity.tolerance = None;
    let (by_default, _) =
        stickslip::auto::resolve(scene.clone(), &law, &front, &mut |_| {}).unwrap();
    scene.fidelity.tolerance = Some(stickslip::auto::DEFAULT_TOLERANCE);
    let (mut explicit, _) = stickslip::auto::resolve(scene, &law, &front, &mut |_| {}).unwrap();
    explicit.fidelity.tolerance = None;
    assert_eq!(by_default, explicit);
}
