//! StickSlipBeam's outputs of the friction law's state, one per entry of
//! `stickslip::friction::state::STATE_VARIABLES`: their rows in both model descriptions, the
//! values against the command line's CSV column of the same scene, through the FMU
//! state, and zeros for a memoryless law.

use stickslip::choice::Choice;
use stickslip::friction::state::STATE_VARIABLES;
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::LawSource;
use stickslip::run::run_scene;
use stickslip::scene::{FidelityLevel, Scene};
use stickslip_cli::scene_args::SceneArgs;
use stickslip_cli::simulate::{simulate, SimulateArgs};
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::instance::Instance;
use stickslip_fmi::model::Model;
use stickslip_fmi::variables::{Access, Causality};
use stickslip_fmi::FmuKind;
use stickslip_tests::vr;

/// Communication step (s): ten internal steps of the default 1e-4 s.
const H: f64 = 1e-3;

fn state_vrs() -> Vec<u32> {
    STATE_VARIABLES
        .iter()
        .map(|v| vr::<StickSlipBeam>(v.name))
        .collect()
}

/// The shipped learned law with memory (`friction.law = neural`).
fn learned_weights() -> String {
    let path = stickslip_tests::weights_dir().join("rate-and-state-learned.json");
    path.to_str().unwrap().to_string()
}

/// The paper scene at modal fidelity (4 modes) with `law` (and its `weights`), to `end`.
fn scene(law: FrictionLawKind, weights: Option<&str>, end: f64) -> Scene {
    let mut scene = Scene::default();
    scene.friction.law = law;
    scene.friction.weights = weights.map(str::to_string);
    scene.fidelity.level = FidelityLevel::Modal;
    scene.fidelity.modes = 4;
    scene.time.end = end;
    scene
}

/// The library's samples of `scene` every 10 steps (1 ms), and the slots its law fills.
fn library(scene: &Scene) -> (Vec<stickslip::simulation::Sample>, Vec<usize>) {
    let checked = scene.clone().check().unwrap();
    let run = run_scene(checked.clone(), &LawSource::resolve(&checked).unwrap(), 10).unwrap();
    (run.samples, run.law_state_slots)
}

/// StickSlipBeam on `scene(law, weights, end)`, initialised for 0..`end` s.
fn initialized(law: FrictionLawKind, weights: Option<&str>, end: f64) -> Instance<StickSlipBeam> {
    let logger = Box::new(|_, _: &str, _: &str| {});
    let mut b =
        Instance::new("beam", Some(&stickslip_tests::weights_dir()), false, logger).unwrap();
    b.setup_experiment(0.0, Some(end)).unwrap();
    b.set_integer(
        &[
            vr::<StickSlipBeam>("fidelity.level"),
            vr::<StickSlipBeam>("fidelity.modes"),
            vr::<StickSlipBeam>("friction.law"),
        ],
        &[FidelityLevel::Modal.code(), 4, law.code()],
    )
    .unwrap();
    if let Some(weights) = weights {
        b.set_string(&[vr::<StickSlipBeam>("friction.weights")], &[weights])
            .unwrap();
    }
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    b
}

fn state_outputs(b: &mut Instance<StickSlipBeam>) -> Vec<f64> {
    let mut out = vec![f64::NAN; STATE_VARIABLES.len()];
    b.get_real(&state_vrs(), &mut out).unwrap();
    out
}

/// The state outputs at every communication point of `steps` steps from `from`.
fn run(b: &mut Instance<StickSlipBeam>, from: f64, steps: usize) -> Vec<Vec<f64>> {
    (0..steps)
        .map(|k| {
            b.do_step(from + k as f64 * H, H).unwrap();
            state_outputs(b)
        })
        .collect()
}

/// Each entry is a Real output named, united and described by its state variable (a
/// dimensionless one without a unit), listed in the FMI 2.0 and 3.0 descriptions.
#[test]
fn each_state_variable_is_an_output_of_both_descriptions() {
    let (v2, v3) = (
        FmuKind::StickSlipBeam.model_description(),
        FmuKind::StickSlipBeam.model_description3(),
    );
    for variable in STATE_VARIABLES {
        let row = StickSlipBeam::variables()
            .iter()
            .find(|row| row.name == variable.name)
            .unwrap();
        assert_eq!(row.causality, Causality::Output);
        assert!(row.description.starts_with(variable.description));
        assert!(row
            .description
            .contains("0 for a law without this variable"));
        let Access::Real { unit, set, .. } = &row.access else {
            panic!("{} is not a Real", row.name);
        };
        assert!(set.is_none());
        assert_eq!(*unit, (variable.unit != "1").then_some(variable.unit));
        let name = format!("name=\"{}\"", variable.name);
        assert!(
            v2.contains(&name) && v3.contains(&name),
            "{}",
            variable.name
        );
    }
}

/// The FMU's state outputs are the library's samples of the same scene, bit for bit,
/// and the command line's CSV column is the same number written as its other columns
/// are (`{:.10e}`); the column exists for the law's own variable only.
#[test]
fn the_state_outputs_are_the_command_lines_column() {
    let dir = std::env::temp_dir().join(format!("stickslip-law-state-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (law, slot) in [
        (FrictionLawKind::Lugre, 0),
        (FrictionLawKind::RateAndState, 1),
    ] {
        let end = 0.8;
        let mut b = initialized(law, None, end);
        let steps = (end / H).round() as usize;
        let fmu = run(&mut b, 0.0, steps);

        let scene = scene(law, None, end);
        let (library, _) = library(&scene);
        assert_eq!(library.len(), steps + 1);
        for (k, outputs) in fmu.iter().enumerate() {
            assert_eq!(outputs[..], library[k + 1].law_state[..], "{law:?} at {k}");
        }

        let scene_file = dir.join(format!("{}.toml", law.name()));
        std::fs::write(&scene_file, toml::to_string(&scene).unwrap()).unwrap();
        let csv = dir.join(format!("{}.csv", law.name()));
        simulate(&SimulateArgs {
            scene: SceneArgs {
                scene: Some(scene_file),
                ..SceneArgs::default()
            },
            out: Some(csv.clone()),
            every: 10,
            summary_json: None,
        })
        .unwrap();
        let text = std::fs::read_to_string(&csv).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(
            header,
            [
                "t",
                "tip_deflection",
                "tip_velocity",
                "friction_force",
                "stick",
                STATE_VARIABLES[slot].name
            ]
        );
        let column: Vec<String> = lines
            .map(|l| l.rsplit(',').next().unwrap().to_string())
            .collect();
        assert_eq!(column.len(), steps + 1);
        for (k, outputs) in fmu.iter().enumerate() {
            assert_eq!(
                column[k + 1],
                format!("{:.10e}", outputs[slot]),
                "{law:?} at {k}"
            );
        }
        // The law's state moved over the run.
        assert!(fmu.iter().any(|o| o[slot] != fmu[0][slot]), "{law:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// After fmi2SetFMUstate the outputs show the restored law state (not the state of the
/// time the FMU had reached), and the run on from there is the uninterrupted one, bit
/// for bit, the serialised state included.
#[test]
fn the_state_outputs_follow_a_restored_fmu_state() {
    for (law, slot) in [
        (FrictionLawKind::Lugre, 0),
        (FrictionLawKind::RateAndState, 1),
    ] {
        let mut b = initialized(law, None, 1.0);
        run(&mut b, 0.0, 450);
        let at_save = state_outputs(&mut b);
        let saved = b.get_state().unwrap();
        let bytes = b.serialize_state(&saved).unwrap();
        let first = run(&mut b, 0.45, 250);
        assert_ne!(first.last().unwrap()[slot], at_save[slot], "{law:?}");
        let restored = b.deserialize_state(&bytes).unwrap();
        b.set_state(&restored).unwrap();
        assert_eq!(state_outputs(&mut b), at_save, "{law:?}");
        assert_eq!(run(&mut b, 0.45, 250), first, "{law:?}");
    }
}

/// The learned law with memory (`friction.law = neural` with the shipped
/// `rate-and-state-learned.json`) fills `state_psi` and nothing else, with the library's
/// values of the same scene, bit for bit.
#[test]
fn the_learned_law_outputs_its_psi() {
    let weights = learned_weights();
    let mut b = initialized(FrictionLawKind::Neural, Some(&weights), 0.8);
    let fmu = run(&mut b, 0.0, 800);
    let (samples, slots) = library(&scene(FrictionLawKind::Neural, Some(&weights), 0.8));
    let psi = STATE_VARIABLES
        .iter()
        .position(|v| v.name == "state_psi")
        .unwrap();
    assert_eq!(slots, [psi]);
    for (k, outputs) in fmu.iter().enumerate() {
        assert_eq!(outputs[..], samples[k + 1].law_state[..], "at {k}");
        for (j, &value) in outputs.iter().enumerate() {
            assert!(j == psi || value == 0.0, "entry {j} at {k}: {value}");
        }
    }
    assert!(fmu.iter().any(|o| o[psi] != fmu[0][psi]));
}

/// A memoryless law has no state: every state output is 0, before the first step and
/// after stick-slip.
#[test]
fn a_memoryless_law_outputs_zero_state() {
    for law in [FrictionLawKind::Exponential, FrictionLawKind::Coulomb] {
        let mut b = initialized(law, None, 1.2);
        assert_eq!(state_outputs(&mut b), vec![0.0; STATE_VARIABLES.len()]);
        for outputs in run(&mut b, 0.0, 1200) {
            assert_eq!(outputs, vec![0.0; STATE_VARIABLES.len()], "{law:?}");
        }
        let mut transitions = [0];
        b.get_integer(&[vr::<StickSlipBeam>("transitions")], &mut transitions)
            .unwrap();
        assert!(transitions[0] > 2, "{law:?}: {transitions:?}");
    }
}
