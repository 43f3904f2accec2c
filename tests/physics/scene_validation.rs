//! Every invalid scene field gives its own clear error naming the field and its value.

use stickslip::scene::{Scene, SceneError};

/// Checks that `edit` applied to the paper's scene is rejected for `field`, with the
/// field's name and `value_text` in the message.
fn rejects(edit: impl FnOnce(&mut Scene), field: &str, value_text: &str) {
    let mut scene = Scene::default();
    edit(&mut scene);
    let err = scene.check().expect_err("scene should be rejected");
    assert_eq!(err.field(), Some(field), "wrong field in: {err}");
    let message = err.to_string();
    assert!(message.contains(field), "{message}");
    assert!(message.contains(value_text), "{message}");
    assert!(message.contains("must be"), "{message}");
}

macro_rules! invalid_field {
    ($name:ident, $field:literal, $value:literal, |$s:ident| $edit:expr) => {
        #[test]
        fn $name() {
            rejects(|$s: &mut Scene| $edit, $field, $value);
        }
    };
}

invalid_field!(negative_length, "geometry.length", "-2e0", |s| s
    .geometry
    .length =
    -2.0);
invalid_field!(nan_length, "geometry.length", "NaN", |s| s
    .geometry
    .length =
    f64::NAN);
invalid_field!(zero_height, "geometry.height", "0e0", |s| s
    .geometry
    .height = 0.0);
invalid_field!(height_not_below_length, "geometry.height", "3e0", |s| s
    .geometry
    .height =
    3.0);
invalid_field!(zero_width, "geometry.width", "0e0", |s| s.geometry.width =
    0.0);
invalid_field!(negative_density, "material.density", "-1e3", |s| s
    .material
    .density =
    -1000.0);
invalid_field!(negative_modulus, "material.youngs_modulus", "-2e11", |s| {
    s.material.youngs_modulus = -2e11
});
invalid_field!(infinite_modulus, "material.youngs_modulus", "inf", |s| s
    .material
    .youngs_modulus =
    f64::INFINITY);
invalid_field!(poisson_half, "material.poisson_ratio", "5e-1", |s| s
    .material
    .poisson_ratio =
    0.5);
invalid_field!(poisson_minus_one, "material.poisson_ratio", "-1e0", |s| s
    .material
    .poisson_ratio =
    -1.0);
invalid_field!(nan_belt_speed, "loading.belt_speed", "NaN", |s| s
    .loading
    .belt_speed =
    f64::NAN);
invalid_field!(negative_normal_force, "loading.normal_force", "-1e2", |s| {
    s.loading.normal_force = -100.0
});
invalid_field!(
    negative_static_coefficient,
    "friction.static_coefficient",
    "-5e-1",
    |s| s.friction.static_coefficient = -0.5
);
invalid_field!(
    kinetic_above_static,
    "friction.kinetic_coefficient",
    "6e-1",
    |s| s.friction.kinetic_coefficient = 0.6
);
invalid_field!(negative_decay, "friction.decay", "-5e0", |s| s
    .friction
    .decay =
    -5.0);
invalid_field!(
    negative_stick_threshold,
    "friction.stick_threshold",
    "-1e-3",
    |s| s.friction.stick_threshold = -1e-3
);
invalid_field!(empty_weights_path, "friction.weights", "\"\"", |s| s
    .friction
    .weights =
    Some(" ".into()));
invalid_field!(
    negative_mass_damping,
    "damping.mass_proportional",
    "-1e0",
    |s| s.damping.mass_proportional = -1.0
);
invalid_field!(
    nan_stiffness_damping,
    "damping.stiffness_proportional",
    "NaN",
    |s| s.damping.stiffness_proportional = f64::NAN
);
invalid_field!(zero_time_step, "time.step", "0e0", |s| s.time.step = 0.0);
invalid_field!(negative_time_step, "time.step", "-1e-4", |s| s.time.step =
    -1e-4);
invalid_field!(step_beyond_end, "time.step", "2e0", |s| s.time.step = 2.0);
invalid_field!(too_many_steps, "time.step", "1e-12", |s| s.time.step =
    1e-12);
invalid_field!(zero_end_time, "time.end", "0e0", |s| s.time.end = 0.0);
invalid_field!(zero_beam_elements, "fidelity.beam_elements", "0e0", |s| s
    .fidelity
    .beam_elements =
    0);
invalid_field!(zero_element_size, "fidelity.element_size", "0e0", |s| s
    .fidelity
    .element_size =
    0.0);
invalid_field!(
    element_size_beyond_length,
    "fidelity.element_size",
    "5e0",
    |s| s.fidelity.element_size = 5.0
);
invalid_field!(mesh_too_fine, "fidelity.element_size", "1e-5", |s| s
    .fidelity
    .element_size =
    1e-5);
invalid_field!(zero_modes, "fidelity.modes", "0e0", |s| s.fidelity.modes =
    0);
invalid_field!(too_many_modes, "fidelity.modes", "1e3", |s| s
    .fidelity
    .modes =
    1000);
invalid_field!(rho_above_one, "integrator.rho_inf", "1.5e0", |s| s
    .integrator
    .rho_inf =
    1.5);
invalid_field!(theta_below_half, "integrator.theta", "4e-1", |s| s
    .integrator
    .theta =
    0.4);

#[test]
fn paper_scene_is_valid_and_has_the_papers_values() {
    let scene = Scene::default().check().unwrap();
    assert_eq!(scene.geometry.length, 2.0);
    assert_eq!(scene.geometry.height, 0.01);
    assert_eq!(scene.material.youngs_modulus, 200e9);
    assert_eq!(scene.loading.belt_speed, 0.02);
    assert_eq!(scene.loading.normal_force, 100.0);
    assert_eq!(scene.friction.static_coefficient, 0.5);
    assert_eq!(scene.friction.kinetic_coefficient, 0.2);
    assert_eq!(scene.friction.decay, 5.0);
    assert_eq!(scene.friction.stick_threshold, 1e-3);
    assert_eq!(scene.time.step, 1e-4);
    assert_eq!(scene.time.end, 1.2);
    // Derived: EI = 16 667 N m2, rho A = 10 kg/m, k = 3 EI / L^3 = 6250 N/m.
    assert!((scene.bending_stiffness() - 16_666.666_666_666_67).abs() < 1e-8);
    assert!((scene.mass_per_length() - 10.0).abs() < 1e-12);
    assert!((scene.euler_bernoulli_tip_stiffness() - 6250.0).abs() < 1e-9);
}

#[test]
fn toml_and_json_round_trip_and_partial_files_take_paper_defaults() {
    let scene = Scene::default();
    let toml_text = toml::to_string(&scene).unwrap();
    assert_eq!(Scene::from_toml_str(&toml_text).unwrap(), scene);
    let json_text = serde_json::to_string(&scene).unwrap();
    assert_eq!(Scene::from_json_str(&json_text).unwrap(), scene);
    let partial = Scene::from_toml_str("[loading]\nbelt_speed = 0.05\n").unwrap();
    assert_eq!(partial.loading.belt_speed, 0.05);
    assert_eq!(partial.geometry, scene.geometry);
}

#[test]
fn malformed_files_give_parse_errors_not_panics() {
    for text in [
        "[geometry\nlength = 2",
        "[geometry]\nlength = \"two\"",
        "[geometry]\nlenght = 2.0",
    ] {
        match Scene::from_toml_str(text) {
            Err(SceneError::Parse(msg)) => assert!(!msg.is_empty()),
            other => panic!("expected a parse error for {text:?}, got {other:?}"),
        }
    }
    assert!(matches!(
        Scene::from_json_str("{\"time\": {\"step\": "),
        Err(SceneError::Parse(_))
    ));
    let missing = Scene::load(std::path::Path::new("/nonexistent/scene.toml"));
    assert!(matches!(
        missing,
        Err(SceneError::File(f)) if f.problem == stickslip::files::InputProblem::Missing
            && f.path == std::path::Path::new("/nonexistent/scene.toml")
    ));
}
