//! The friction law through the instance: external friction, NeuralFriction's outputs,
//! the network (weights files, their errors, when the beam reads one, its inference).

use super::*;

/// A network that cannot be had says which file, once, and keeps the loader's error.
#[test]
fn network_errors_name_the_weights_file() {
    use stickslip_fmi::networks::{NetworkError, Networks};
    let mut networks = Networks::default();
    let e = networks.get("w.json").unwrap_err();
    assert_eq!(
        e.to_string(),
        "weights \"w.json\": no resources folder is known"
    );
    let e = networks
        .open(std::path::Path::new("/nonexistent"))
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "weights file /nonexistent/paper-plain.json: no such file"
    );
    let dir = std::env::temp_dir().join(format!("stickslip-fmu-networks-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let not_weights = dir.join("not-weights.json");
    std::fs::write(&not_weights, "x").unwrap();
    let e = networks.get(not_weights.to_str().unwrap()).unwrap_err();
    let path = not_weights.display().to_string();
    let message = e.to_string();
    assert!(
        message.starts_with(&format!(
            "weights file {path}: not a valid model description"
        )),
        "{message}"
    );
    assert_eq!(message.matches(&path).count(), 1, "{message}");
    assert!(
        matches!(
            e,
            NetworkError::Unreadable(stickslip::neural::NeuralError::Json { .. })
        ),
        "{e:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn missing_or_corrupted_weights_fail_instantiation_with_a_reason() {
    let dir = std::env::temp_dir().join(format!("stickslip-res-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (logger, log) = collecting_logger();
    assert!(Instance::<StickSlipBeam>::new("b", Some(&dir), false, logger).is_err());
    assert!(logged(&log, "paper-plain.json: no such file"));
    std::fs::write(dir.join("paper-plain.json"), "{\"format\": 3").unwrap();
    let (logger, log) = collecting_logger();
    assert!(Instance::<NeuralFriction>::new("f", Some(&dir), false, logger).is_err());
    assert!(
        logged(&log, "paper-plain.json"),
        "{:?}",
        log.lock().unwrap()
    );
    let (logger, log) = collecting_logger();
    assert!(Instance::<StickSlipBeam>::new("b", None, false, logger).is_err());
    assert!(logged(&log, "no resource location"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn external_friction_equal_to_the_law_reproduces_coulomb() {
    // friction.law = external with inputs mu_k F_n and mu_s F_n is Coulomb friction
    // with the static limit mu_s F_n: same as friction.law = coulomb.
    let runs: Vec<Vec<f64>> = [FrictionLawKind::Coulomb, FrictionLawKind::External]
        .iter()
        .map(|&model| {
            let (mut b, _) = beam(false);
            b.setup_experiment(0.0, Some(1.2)).unwrap();
            b.set_integer(
                &[
                    vr::<StickSlipBeam>("fidelity.level"),
                    vr::<StickSlipBeam>("friction.law"),
                ],
                &[FidelityLevel::Modal.code(), model.code()],
            )
            .unwrap();
            b.set_real(
                &[
                    vr::<StickSlipBeam>("external.kinetic_force"),
                    vr::<StickSlipBeam>("external.static_limit"),
                ],
                &[20.0, 50.0],
            )
            .unwrap();
            b.enter_initialization_mode().unwrap();
            b.exit_initialization_mode().unwrap();
            run(&mut b, 0.0, 1.0, 1e-3)
        })
        .collect();
    assert_eq!(runs[0], runs[1]);
}

#[test]
fn neural_friction_outputs_follow_the_inputs() {
    let (logger, _) = collecting_logger();
    let mut f = Instance::<NeuralFriction>::new("f", Some(&resources()), false, logger).unwrap();
    f.set_integer(
        &[vr::<NeuralFriction>("law")],
        &[NeuralFrictionLaw::EXPONENTIAL.code()],
    )
    .unwrap();
    f.setup_experiment(0.0, None).unwrap();
    f.enter_initialization_mode().unwrap();
    f.exit_initialization_mode().unwrap();
    let outputs = [
        vr::<NeuralFriction>("friction_force"),
        vr::<NeuralFriction>("friction_force_magnitude"),
        vr::<NeuralFriction>("friction_coefficient"),
        vr::<NeuralFriction>("static_limit"),
    ];
    for v in [-0.2, 0.05, 0.3] {
        f.set_real(&[vr::<NeuralFriction>("sliding_velocity")], &[v])
            .unwrap();
        let mut out = [0.0; 4];
        f.get_real(&outputs, &mut out).unwrap();
        let mu = 0.2 + 0.3 * stickslip::elementary::exp(-5.0 * v.abs());
        assert!((out[0] - v.signum() * mu * 100.0).abs() < 1e-12);
        assert_eq!(out[1], out[0].abs());
        assert!((out[2] - mu).abs() < 1e-14);
        assert_eq!(out[3], 50.0);
    }
}

/// Parts a scene does not use cost nothing: a StickSlipBeam with an analytical law
/// never reads a network, not at instantiation, not when stepping; the neural law reads
/// exactly one, once, however often the simulation is rebuilt.
#[test]
fn the_beam_reads_a_network_only_for_the_neural_law() {
    let (mut b, _) = initialized_beam(FidelityLevel::Modal);
    run(&mut b, 0.0, 0.5, 1e-2);
    assert_eq!(b.model().networks_read(), 0);
    b.reset();
    assert_eq!(b.model().networks_read(), 0);
    let law = vr::<StickSlipBeam>("friction.law");
    let level = vr::<StickSlipBeam>("fidelity.level");
    for _ in 0..2 {
        b.reset();
        b.set_integer(&[level, law], &[FidelityLevel::Modal.code(), 3])
            .unwrap();
        b.setup_experiment(0.0, Some(1.2)).unwrap();
        b.enter_initialization_mode().unwrap();
        b.exit_initialization_mode().unwrap();
        run(&mut b, 0.0, 0.5, 1e-2);
        assert_eq!(b.model().networks_read(), 1);
    }
}

/// `friction.inference` of StickSlipBeam: each option runs the library's simulation of
/// the same scene bit for bit; f32 and the table follow the exact network to nanometres;
/// a network with more inputs than the table is refused at fmi2ExitInitializationMode
/// with the reason in the log.
#[test]
fn neural_inference_is_a_parameter_of_the_beam() {
    use stickslip::neural::inference::Inference;
    let mut runs = Vec::new();
    for inference in Inference::ALL {
        let (mut b, _) = beam(false);
        b.setup_experiment(0.0, Some(0.6)).unwrap();
        b.set_integer(
            &[
                vr::<StickSlipBeam>("fidelity.level"),
                vr::<StickSlipBeam>("friction.law"),
                vr::<StickSlipBeam>("friction.inference"),
            ],
            &[
                FidelityLevel::Modal.code(),
                FrictionLawKind::Neural.code(),
                inference.code(),
            ],
        )
        .unwrap();
        b.enter_initialization_mode().unwrap();
        b.exit_initialization_mode().unwrap();
        let fmu = run(&mut b, 0.0, 0.6, 1e-3);
        let mut scene = Scene::default();
        scene.fidelity.level = FidelityLevel::Modal;
        scene.friction.law = FrictionLawKind::Neural;
        scene.friction.inference = *inference;
        scene.time.end = 0.6;
        let scene = scene.check().unwrap();
        let law = LawSource::resolve(&scene).unwrap().law().unwrap();
        let mut sim = Simulator::new(scene, law).unwrap();
        let library: Vec<f64> = (1..=600)
            .map(|k| {
                sim.advance_to(k as f64 * 1e-3).unwrap();
                sim.sample().tip_deflection
            })
            .collect();
        assert_eq!(fmu, library, "{inference:?}");
        runs.push(fmu);
    }
    for (inference, tip) in Inference::ALL.iter().zip(&runs).skip(1) {
        let deviation = runs[0]
            .iter()
            .zip(tip)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(deviation < 1e-7, "{inference:?}: {deviation} m");
    }

    let dir = std::env::temp_dir().join(format!("stickslip-inference-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let weights = dir.join("three.json");
    std::fs::write(&weights, stickslip_tests::three_input_weights()).unwrap();
    let (mut b, log) = beam(false);
    b.set_integer(
        &[
            vr::<StickSlipBeam>("friction.law"),
            vr::<StickSlipBeam>("friction.inference"),
        ],
        &[FrictionLawKind::Neural.code(), Inference::Table.code()],
    )
    .unwrap();
    b.set_string(
        &[vr::<StickSlipBeam>("friction.weights")],
        &[weights.to_str().unwrap()],
    )
    .unwrap();
    b.enter_initialization_mode().unwrap();
    assert!(b.exit_initialization_mode().is_err());
    assert!(
        logged(&log, "friction.inference = table") && logged(&log, "temperature"),
        "{:?}",
        log.lock().unwrap()
    );
    std::fs::remove_dir_all(&dir).ok();
}
