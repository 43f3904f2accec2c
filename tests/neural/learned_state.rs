//! The learned friction law with memory (issue 24, item 3): trained on noisy synthetic
//! tribometer records of rate-and-state friction, it reproduces the generating law's
//! velocity-step response; its weights file round-trips and refuses corrupted files with
//! the reason.

use std::sync::Arc;
use stickslip::friction::learned_state::{LearnedStateFriction, StateEvolution, StateLawFile};
use stickslip::friction::rate_and_state::RateStateLaw;
use stickslip::friction::state::response::velocity_step;
use stickslip::neural::NeuralError;
use stickslip_train::learned_state::{
    train_state_law, LearnedEvolution, StateTrainConfig, TribometerSpec,
};

/// Trains on the default records (3 normal forces x 4 histories, 0.2 N noise) of the
/// generating law with `evolution`, with a learned law of the same evolution and a
/// shorter schedule than the command's, and returns the generating and the learned law.
fn trained(evolution: StateEvolution) -> (TribometerSpec, RateStateLaw, StateLawFile) {
    let mut spec = TribometerSpec::default();
    spec.law.state_evolution = evolution;
    let records = spec.generate(7).unwrap();
    let config = StateTrainConfig {
        max_iterations: 150,
        grid_iterations: 25,
        evolution: match evolution {
            StateEvolution::Aging => LearnedEvolution::Aging,
            StateEvolution::Slip => LearnedEvolution::Slip,
        },
        ..StateTrainConfig::default()
    };
    let (file, report) = train_state_law(
        &records,
        &config,
        &spec.describe(),
        spec.noise_std,
        |_, _| {},
    )
    .unwrap();
    eprintln!("{report:?}\nlaw {:?}\nmetrics {:?}", file.law, file.metrics);
    (spec.clone(), spec.generating_law(), file)
}

/// Issue 24's must-show: direct effect and decay length of velocity steps within 10 %
/// of the generating law's, at two steps inside the trained range (up by 10 from the
/// slowest speed, down by 10 to the middle one) and at the three trained normal forces.
/// Why 10 % holds with margin: 12 records of ~10^4 samples with 0.2 N noise pin a and
/// D_c far tighter (the fit's standard errors are below 1 %); what is left is the
/// correction network's freedom, which the test bounds as a whole. The held-out records'
/// RMS error must be at the noise level (0.2 N) within 25 %: a law that only matched the
/// steps but not the ramps, reversal and healing would not.
#[test]
fn the_learned_law_reproduces_the_velocity_step_response() {
    reproduces_the_velocity_step_response(StateEvolution::Aging);
}

/// The same with the slip law (Ruina) generating the records and evolving the learned
/// law's state: the aging law fitted to them missed the direct effect by a factor 4
/// (docs/learned-friction-with-memory.md), so this is what the slip evolution is for.
/// The same bounds and the same reasons: only the step's formula differs.
#[test]
fn the_learned_slip_law_reproduces_the_slip_law_velocity_step_response() {
    reproduces_the_velocity_step_response(StateEvolution::Slip);
}

fn reproduces_the_velocity_step_response(evolution: StateEvolution) {
    let (spec, truth, file) = trained(evolution);
    assert_eq!(file.law.state_evolution, evolution);
    let mut truth = truth;
    let mut learned = LearnedStateFriction::new(Arc::new(file.law()));
    let d_c = spec.law.characteristic_slip;
    for normal_force in [60.0, 100.0, 140.0] {
        for steps in [(1e-3, 1e-2), (1e-1, 1e-2)] {
            let (v1, v2) = steps;
            // Settled over 1000 D_c; sampled every D_c / 1000 (0.1 % of the decay).
            let want = velocity_step(&mut truth, steps, normal_force, 1e3 * d_c, 1e-3 * d_c);
            let got = velocity_step(&mut learned, steps, normal_force, 1e3 * d_c, 1e-3 * d_c);
            let direct = (got.direct_effect - want.direct_effect).abs() / want.direct_effect.abs();
            let decay = (got.decay_length - want.decay_length).abs() / want.decay_length;
            eprintln!("F_n {normal_force} N, {v1} -> {v2} m/s: direct {} vs {} ({direct:.4}), decay {} vs {} m ({decay:.4})",
                got.direct_effect, want.direct_effect, got.decay_length, want.decay_length);
            assert!(direct < 0.1, "direct effect off by {direct}");
            assert!(decay < 0.1, "decay length off by {decay}");
        }
    }
    let m = file.metrics;
    assert!(
        m.rms_error_test < 1.25 * spec.noise_std && m.rms_error_test > 0.75 * spec.noise_std,
        "{m:?}"
    );
}

/// The file reads back to the same law bit for bit; corrupted files are refused with
/// the reason (not JSON, another format, a newer version, a negative D_c, a NaN).
#[test]
fn the_weights_file_round_trips_and_refuses_corruption() {
    let spec = TribometerSpec {
        hold_slip: 5e-5,
        hold_time: 0.02,
        normal_forces: vec![100.0],
        ..TribometerSpec::default()
    };
    let records = spec.generate(3).unwrap();
    let config = StateTrainConfig {
        max_iterations: 5,
        grid_iterations: 2,
        hidden: 2,
        test_every: 0,
        ..StateTrainConfig::default()
    };
    let (file, _) = train_state_law(&records, &config, "test", 0.2, |_, _| {}).unwrap();
    let text = file.to_json().unwrap();
    let back = StateLawFile::from_json(&text, "w.json").unwrap();
    assert_eq!(back, file);
    assert_eq!(back.to_json().unwrap(), text);
    let refused = |text: &str| StateLawFile::from_json(text, "w.json").unwrap_err();
    assert!(matches!(
        refused(&text[..text.len() / 2]),
        NeuralError::Json { .. }
    ));
    let other = text.replace("stickslip-state-friction", "stickslip-neural-friction");
    assert_eq!(refused(&other).to_string(), "weights file w.json: format is 'stickslip-neural-friction', expected 'stickslip-state-friction'");
    let newer = text.replacen("\"version\": 1", "\"version\": 2", 1);
    assert!(refused(&newer)
        .to_string()
        .contains("format version 2 is not supported"));
    let slip = format!("\"characteristic_slip\": {}", file.law.characteristic_slip);
    let negative = text.replacen(&slip, "\"characteristic_slip\": -1e-4", 1);
    assert_eq!(refused(&negative).to_string(), "weights file w.json: inconsistent model: law.characteristic_slip must be positive, got -0.0001");
    let nan = text.replacen(&slip, "\"characteristic_slip\": NaN", 1);
    assert!(matches!(refused(&nan), NeuralError::Json { .. }));

    // The state evolution: written, read back; absent (a file from before the slip
    // law) it is aging; another word is refused with the words it may be.
    assert!(text.contains("\"state_evolution\": \"aging\""), "{text}");
    let mut slip_file = file.clone();
    slip_file.law.state_evolution = StateEvolution::Slip;
    let slip_text = slip_file.to_json().unwrap();
    assert!(slip_text.contains("\"state_evolution\": \"slip\""));
    let back = StateLawFile::from_json(&slip_text, "w.json").unwrap();
    assert_eq!(back.law().parameters.state_evolution, StateEvolution::Slip);
    let old = slip_text.replacen(",\n    \"state_evolution\": \"slip\"", "", 1);
    assert!(!old.contains("state_evolution"), "{old}");
    let old = StateLawFile::from_json(&old, "w.json").unwrap();
    assert_eq!(old.law.state_evolution, StateEvolution::Aging);
    let bad = slip_text.replacen(
        "\"state_evolution\": \"slip\"",
        "\"state_evolution\": \"healing\"",
        1,
    );
    let message = refused(&bad).to_string();
    assert!(
        message.contains("unknown variant `healing`, expected `aging` or `slip`"),
        "{message}"
    );
}

/// The shipped file (written before the slip law, without `state_evolution`) reads as
/// the aging law.
#[test]
fn the_shipped_learned_law_reads_as_the_aging_law() {
    let path = stickslip_tests::weights_dir().join("rate-and-state-learned.json");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(!text.contains("state_evolution"));
    let file = StateLawFile::load(&path).unwrap();
    assert_eq!(file.law.state_evolution, StateEvolution::Aging);
}

/// Issue 24's must-show, item 5: the shipped learned law (weights/rate-and-state-learned.json,
/// made by `stickslip train-memory`) runs the paper scene beside its generating law, the
/// scene's default rate-and-state law, through the same contact for laws with state.
/// Measured at modal fidelity: period 0.2920 s against 0.2921 s, corridor 6.270-9.066 mm
/// against 6.265-9.068 mm, breakaway 0.4423 s against 0.4424 s. Bounds: 1 % of the
/// period and 0.1 mm of the corridor, about 5x and 15x the measured differences, which
/// come from the fit's 0.4 % in the direct effect; a law that missed the memory (a
/// memoryless fit of the steady curve) would not stick-slip with this period at all.
#[test]
fn the_shipped_learned_law_runs_the_paper_scene_beside_its_generating_law() {
    use stickslip::friction::FrictionLawKind;
    use stickslip::law_source::LawSource;
    use stickslip::scene::{FidelityLevel, Scene};
    let run = |law: FrictionLawKind, weights: Option<String>| {
        let mut scene = Scene::default();
        scene.fidelity.level = FidelityLevel::Modal;
        scene.friction.law = law;
        scene.friction.weights = weights;
        let checked = scene.check().unwrap();
        let source = LawSource::resolve(&checked).unwrap();
        stickslip::run::run_scene(checked, &source, 100)
            .unwrap()
            .summary
    };
    let weights = stickslip_tests::weights_dir().join("rate-and-state-learned.json");
    let learned = run(FrictionLawKind::Neural, Some(weights.display().to_string()));
    let truth = run(FrictionLawKind::RateAndState, None);
    let (p, q) = (learned.period.unwrap(), truth.period.unwrap());
    assert!((p - q).abs() < 0.01 * q, "period {p} vs {q} s");
    let ((a, b), (c, d)) = (learned.corridor.unwrap(), truth.corridor.unwrap());
    assert!(
        (a - c).abs() < 1e-4 && (b - d).abs() < 1e-4,
        "corridor {a}-{b} vs {c}-{d} m"
    );
    assert!(learned.major_slips.len() >= 2, "{learned:?}");
}

/// Records that start mid-transient or from rest (each default record cut 2 samples
/// after its first velocity change: 2 D_c into the first step's decay, or at rest in
/// the slide-hold-slide record) need a trained initial state: without it they are
/// refused (a start at rest has no steady state); with it the learned law reproduces
/// the velocity-step response within the 10 % and the held-out error is at the
/// noise within 25 % (the same bounds and reasons as the test from steady sliding: the
/// 12 extra parameters are each pinned by the first few D_c of their record).
#[test]
fn records_starting_mid_transient_train_with_trained_initial_states() {
    let spec = TribometerSpec::default();
    let mut records = spec.generate(7).unwrap();
    for r in &mut records {
        let change = r.velocity.iter().position(|v| *v != r.velocity[0]).unwrap();
        let cut = change + 2;
        r.time.drain(..cut);
        r.velocity.drain(..cut);
        r.normal_force.drain(..cut);
        r.force.drain(..cut);
    }
    assert!(records.iter().any(|r| r.velocity[0] == 0.0));
    let mut config = StateTrainConfig {
        max_iterations: 150,
        grid_iterations: 25,
        ..StateTrainConfig::default()
    };
    let refused = train_state_law(&records, &config, "cut", 0.2, |_, _| {}).unwrap_err();
    assert!(
        refused.to_string().contains("or train its initial state"),
        "{refused}"
    );
    config.train_initial_state = true;
    let (file, report) = train_state_law(&records, &config, "cut", 0.2, |_, _| {}).unwrap();
    eprintln!("{report:?}\nlaw {:?}\nmetrics {:?}", file.law, file.metrics);
    let mut truth = spec.generating_law();
    let mut learned = LearnedStateFriction::new(Arc::new(file.law()));
    let d_c = spec.law.characteristic_slip;
    for steps in [(1e-3, 1e-2), (1e-1, 1e-2)] {
        let want = velocity_step(&mut truth, steps, 100.0, 1e3 * d_c, 1e-3 * d_c);
        let got = velocity_step(&mut learned, steps, 100.0, 1e3 * d_c, 1e-3 * d_c);
        let direct = (got.direct_effect - want.direct_effect).abs() / want.direct_effect.abs();
        let decay = (got.decay_length - want.decay_length).abs() / want.decay_length;
        eprintln!("{steps:?}: direct {direct:.4}, decay {decay:.4}");
        assert!(direct < 0.1 && decay < 0.1, "{direct} {decay}");
    }
    let m = file.metrics;
    assert!(
        m.rms_error_test < 1.25 * spec.noise_std && m.rms_error_test > 0.75 * spec.noise_std,
        "{m:?}"
    );
}

/// Rate-and-state has two implementations in the product, and this is their
/// cross-check: the scene's law (`friction::rate_and_state`, theta stepped in its own
/// form) and the learned law's core without a correction (`friction::learned_state`,
/// psi = ln(theta V_0 / D_c)), which the trainer fits. Each keeps its own bits (the runs
/// of each are pinned), so neither replaces the other; here they must give the same
/// forces to rounding over a history of slides, velocity steps, stick and a reversal,
/// for both evolution laws, at the default parameters (dt = 1e-4 s, F_n = 100 N).
/// Measured: the largest difference 1.2e-13 N with the aging law, 2.1e-14 N with the slip
/// law (2.4e-15 and 4.3e-16 of mu_0 F_n = 50 N, a few ulps); asserted below 1e-12 of
/// mu_0 F_n.
#[test]
fn the_scene_law_and_the_learned_law_core_are_one_rate_and_state_law() {
    use stickslip::friction::state::{LawStep, StatefulLaw};
    for evolution in [StateEvolution::Aging, StateEvolution::Slip] {
        let mut spec = TribometerSpec::default();
        spec.law.state_evolution = evolution;
        let mut scene_law = spec.generating_law();
        let mut core = LearnedStateFriction::new(Arc::new(spec.as_learned()));
        let normal = 100.0;
        let scale = spec.law.reference_coefficient * normal;
        let mut largest: f64 = 0.0;
        let segments = [
            (1e-3, 2000),
            (1e-2, 2000),
            (1e-4, 3000),
            (0.0, 2000),
            (-5e-3, 2000),
        ];
        for (velocity, steps) in segments {
            for _ in 0..steps {
                let step = LawStep {
                    dt: 1e-4,
                    sliding_velocity: velocity,
                    normal_force: normal,
                };
                scene_law.commit(step);
                core.commit(step);
                let a = scene_law.force_at_state(velocity, normal).force;
                let b = core.force_at_state(velocity, normal).force;
                largest = largest.max((a - b).abs());
            }
        }
        eprintln!(
            "{evolution:?}: largest force difference {largest:e} N ({:e} of mu_0 F_n)",
            largest / scale
        );
        assert!(largest < 1e-12 * scale, "{evolution:?}: {largest:e} N");
    }
}
