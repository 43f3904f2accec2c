//! Serialized FMU states written by an earlier version of the FMUs restore bit for bit:
//! the fixtures in `tests/fmu/fixtures/states/` are version-4 states of both FMUs, FMI 2.0
//! and 3.0, with the outputs the same run gave after the save. A fresh instance restores
//! each and must give those outputs, bit for bit.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use stickslip::choice::Choice;
use stickslip::friction::LawChoice;
use stickslip::scene::{FidelityLevel, FrictionLawKind};
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::instance::{FmiVersion, Instance};
use stickslip_fmi::model::Model;
use stickslip_tests::vr;

/// One fixture: a serialized state and what the instance gave after it was saved.
#[derive(Serialize, Deserialize)]
pub(crate) struct Fixture {
    /// "StickSlipBeam" or "NeuralFriction".
    pub fmu: String,
    /// "2.0" or "3.0".
    pub fmi: String,
    /// The serialized state, as fmi2SerializeFMUstate gave it.
    pub state: String,
    /// The communication point of the save (s) and the steps that follow it.
    pub time: f64,
    pub step: f64,
    pub steps: usize,
    /// NeuralFriction: the sliding velocity set before each step (m/s).
    pub velocities: Vec<f64>,
    /// The outputs read after each step, as `f64::to_bits`, in the order of `outputs`.
    pub outputs: Vec<String>,
    pub values: Vec<Vec<u64>>,
}

pub(crate) fn fixtures_dir() -> PathBuf {
    stickslip_tests::workspace_root().join("tests/fmu/fixtures/states")
}

/// Every fixture, by file name.
pub(crate) fn fixtures() -> Vec<(String, Fixture)> {
    let mut all: Vec<(String, Fixture)> = std::fs::read_dir(fixtures_dir())
        .expect("the fixtures folder")
        .map(|entry| {
            let path = entry.unwrap().path();
            let text = std::fs::read_to_string(&path).unwrap();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, serde_json::from_str(&text).unwrap())
        })
        .collect();
    all.sort_by(|a, b| a.0.cmp(&b.0));
    all
}

pub(crate) fn fmi_version(name: &str) -> FmiVersion {
    match name {
        "2.0" => FmiVersion::V2,
        "3.0" => FmiVersion::V3,
        other => panic!("FMI version {other}"),
    }
}

fn quiet<M: Model>(version: FmiVersion) -> Instance<M> {
    let logger = Box::new(|_, _: &str, _: &str| {});
    let dir = stickslip_tests::weights_dir();
    Instance::instantiate(version, "old", Some(&dir), false, logger).unwrap()
}

fn step<M: Model>(instance: &mut Instance<M>, version: FmiVersion, t: f64, h: f64) {
    match version {
        FmiVersion::V2 => instance.do_step(t, h).unwrap(),
        FmiVersion::V3 => {
            instance.do_step3(t, h).unwrap();
        }
    }
}

/// Runs the fixture's steps on `instance` (already at the fixture's time) and returns
/// the outputs' bits after each.
fn replay<M: Model>(instance: &mut Instance<M>, version: FmiVersion, f: &Fixture) -> Vec<Vec<u64>> {
    let vrs: Vec<u32> = f.outputs.iter().map(|name| vr::<M>(name)).collect();
    let mut values = Vec::new();
    for k in 0..f.steps {
        if let Some(&v) = f.velocities.get(k) {
            instance
                .set_real(&[vr::<M>("sliding_velocity")], &[v])
                .unwrap();
        }
        step(instance, version, f.time + k as f64 * f.step, f.step);
        let mut out = vec![0.0; vrs.len()];
        instance.get_real(&vrs, &mut out).unwrap();
        values.push(out.iter().map(|x| x.to_bits()).collect());
    }
    values
}

/// The fixture's state with the GUID of the FMU as built now. The GUID hashes the whole
/// model description, descriptions included, so any change of the interface's text
/// changes it, and a state of another GUID is refused by design; what the fixtures
/// test is the format, which the GUID is not part of.
pub(crate) fn with_current_guid<M: Model>(state: &str) -> String {
    let recorded: serde_json::Value = serde_json::from_str(state).unwrap();
    let recorded = recorded["guid"].as_str().unwrap();
    state.replacen(recorded, &stickslip_fmi::model_description::guid::<M>(), 1)
}

/// A fresh instance restores the fixture's bytes and gives its outputs.
pub(crate) fn restored_outputs(f: &Fixture) -> Vec<Vec<u64>> {
    fn run<M: Model>(f: &Fixture) -> Vec<Vec<u64>> {
        let version = fmi_version(&f.fmi);
        let mut fresh = quiet::<M>(version);
        let state = fresh
            .deserialize_state(with_current_guid::<M>(&f.state).as_bytes())
            .unwrap();
        fresh.set_state(&state).unwrap();
        replay(&mut fresh, version, f)
    }
    match f.fmu.as_str() {
        "StickSlipBeam" => run::<StickSlipBeam>(f),
        "NeuralFriction" => run::<NeuralFriction>(f),
        other => panic!("FMU {other}"),
    }
}

#[test]
fn version_4_states_restore_bit_for_bit() {
    let all = fixtures();
    assert_eq!(
        all.len(),
        10,
        "fixtures: {:?}",
        all.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for (name, fixture) in &all {
        assert!(fixture.state.contains("\"version\":4"), "{name}");
        assert_eq!(restored_outputs(fixture), fixture.values, "{name}");
    }
}

/// Writes the fixtures. Run once with the code of state version 4 (commit 3f22e47):
/// `cargo test --release -p stickslip-tests --test fmu write_version_4_fixtures -- --ignored`.
#[test]
#[ignore]
fn write_version_4_fixtures() {
    std::fs::create_dir_all(fixtures_dir()).unwrap();
    for (tag, version) in [("fmi2", FmiVersion::V2), ("fmi3", FmiVersion::V3)] {
        for law in [FrictionLawKind::Lugre, FrictionLawKind::RateAndState] {
            let mut b = quiet::<StickSlipBeam>(version);
            b.setup_experiment(0.0, Some(1.2)).unwrap();
            b.set_integer(
                &[
                    vr::<StickSlipBeam>("fidelity.level"),
                    vr::<StickSlipBeam>("friction.law"),
                ],
                &[FidelityLevel::Beam.code(), law.code()],
            )
            .unwrap();
            b.enter_initialization_mode().unwrap();
            b.exit_initialization_mode().unwrap();
            let h = 1e-2;
            for k in 0..45 {
                step(&mut b, version, k as f64 * h, h);
            }
            let mut stick = [true];
            b.get_boolean(&[vr::<StickSlipBeam>("stick")], &mut stick)
                .unwrap();
            assert!(!stick[0], "{law:?} {version:?}: saved in stick");
            let law_output = match law {
                FrictionLawKind::Lugre => "bristle_deflection",
                _ => "state_theta",
            };
            let outputs = [
                "tip_deflection",
                "tip_velocity",
                "friction_force",
                "holding_force",
                law_output,
            ];
            let name = format!("beam-{}-{tag}.json", law.name());
            write(&mut b, version, &name, 0.45, 2e-3, 50, &[], &outputs);
        }
        let lugre = (LawChoice::Lugre, None, "bristle_deflection");
        let rate = (LawChoice::RateAndState, None, "state_theta");
        let learned = (
            LawChoice::Neural,
            Some("rate-and-state-learned.json"),
            "state_psi",
        );
        for (law, weights, law_output) in [lugre, rate, learned] {
            let mut f = quiet::<NeuralFriction>(version);
            f.set_integer(&[vr::<NeuralFriction>("law")], &[law.code()])
                .unwrap();
            if let Some(w) = weights {
                f.set_string(&[vr::<NeuralFriction>("weights")], &[w])
                    .unwrap();
            }
            f.setup_experiment(0.0, None).unwrap();
            f.enter_initialization_mode().unwrap();
            f.exit_initialization_mode().unwrap();
            let h = 1e-3;
            for k in 0..30 {
                let v = 0.03 - 2e-3 * k as f64;
                f.set_real(&[vr::<NeuralFriction>("sliding_velocity")], &[v])
                    .unwrap();
                step(&mut f, version, k as f64 * h, h);
            }
            let velocities: Vec<f64> = (0..20).map(|k| -0.03 + 4e-3 * k as f64).collect();
            let outputs = ["friction_force", "friction_force_slope", law_output];
            let name = format!("friction-{}-{tag}.json", law_output.replace('_', "-"));
            write(&mut f, version, &name, 0.03, h, 20, &velocities, &outputs);
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn write<M: Model>(
    instance: &mut Instance<M>,
    version: FmiVersion,
    name: &str,
    time: f64,
    step: f64,
    steps: usize,
    velocities: &[f64],
    outputs: &[&str],
) {
    let saved = instance.get_state().unwrap();
    let bytes = instance.serialize_state(&saved).unwrap();
    let mut fixture = Fixture {
        fmu: M::INFO.model_identifier.into(),
        fmi: match version {
            FmiVersion::V2 => "2.0".into(),
            FmiVersion::V3 => "3.0".into(),
        },
        state: String::from_utf8(bytes).unwrap(),
        time,
        step,
        steps,
        velocities: velocities.to_vec(),
        outputs: outputs.iter().map(|s| s.to_string()).collect(),
        values: Vec::new(),
    };
    fixture.values = replay(instance, version, &fixture);
    let text = serde_json::to_string_pretty(&fixture).unwrap();
    std::fs::write(fixtures_dir().join(name), text + "\n").unwrap();
}
