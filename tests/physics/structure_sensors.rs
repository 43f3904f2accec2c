//! Sensors of a user's structure (`[structure] sensors`, issue 35 item 3): named output
//! DOFs read by every fidelity. Checked on the CalculiX paper beam
//! (examples/calculix-beam: 1002 free DOFs, contact at node 502, the end face's mid
//! node, in y):
//! - a sensor at the contact DOF reads the tip's bits, full and modal (one observation
//!   rule, `structure::observe`, and the same projection on the modal basis);
//! - a sensor at mid-span (node 252: x = 1 m, y = 0.005 m) during the first stick,
//!   full and modal, against the built-in plane stress's same node and the
//!   cantilever's closed form;
//! - the refusals, each naming the sensor.

use std::path::{Path, PathBuf};
use stickslip::law_source::LawSource;
use stickslip::run::{run_scene, Run};
use stickslip::scene::{FidelityLevel, Scene};
use stickslip::simulation::{SensorReading, Simulator};
use stickslip::structure::StructuralModel;
use stickslip::user_structure::{SceneDof, Sensor};

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/calculix-beam")
}

fn sensor(name: &str, node: u64, direction: u8) -> Sensor {
    Sensor::at_node(name, node, direction)
}

/// The example scene at `level` (10 modes) to `end` s with `sensors`.
fn scene_with(level: FidelityLevel, end: f64, sensors: Vec<Sensor>) -> Scene {
    let loaded = Scene::load(&example().join("scene.toml")).unwrap();
    let mut scene = loaded.scene().clone();
    scene.fidelity.level = level;
    scene.fidelity.modes = 10;
    scene.time.end = end;
    scene.structure.as_mut().unwrap().sensors = sensors;
    scene
}

fn run(scene: Scene) -> Run {
    let checked = scene.check().unwrap();
    let law = LawSource::resolve(&checked).unwrap();
    run_scene(checked, &law, 1).unwrap()
}

/// Through breakaway (0.40 s) and a slip, so that stick, slip and the switch are all
/// read: the sensor at the contact DOF equals tip deflection and velocity bit for bit
/// at every step, on the full model and its modal reduction.
#[test]
fn a_sensor_at_the_contact_reads_the_tips_bits() {
    for level in [FidelityLevel::PlaneStress, FidelityLevel::Modal] {
        let run = run(scene_with(
            level,
            0.5,
            vec![sensor("mid", 252, 2), sensor("contact", 502, 2)],
        ));
        assert_eq!(run.sensors.len(), run.samples.len());
        assert!(run.summary.slip_phases > 0, "{level:?}: no slip to read");
        for (sample, readings) in run.samples.iter().zip(&run.sensors) {
            assert_eq!(readings.len(), 2);
            let contact = readings[1];
            assert_eq!(
                contact.displacement.to_bits(),
                sample.tip_deflection.to_bits(),
                "{level:?} at t = {}",
                sample.time
            );
            assert_eq!(
                contact.velocity.to_bits(),
                sample.tip_velocity.to_bits(),
                "{level:?} at t = {}",
                sample.time
            );
        }
    }
}

/// The mid-span sensor during the first stick, against the same node of the built-in
/// plane stress (the deck's mesh, 100 x 1 Q8, loaded and observed at the end face's mid
/// node as the example's contact) and against the cantilever's closed form.
///
/// In stick the tip moves with the belt and the structure moves in the static shape
/// psi = K^-1 c (the start puts it there, and a shape moving at constant speed has no
/// inertia), so that K (u + b u') = c F with the Rayleigh b: at any DOF
/// u + b u' = g F, g that DOF's static compliance under the end load (m/N). The run
/// gives g at the sensor as (u + b u') / F at 0.39 s, just before breakaway.
///
/// - Against the built-in at the same node: 2e-4, the 14-digit files (the read-back tip
///   compliance is 8.3e-5 from the built-in's, docs/structures.md; cond(K) ~ 7e10).
/// - Against the closed form, Timoshenko (bending plus shear, kappa = 5/6):
///   g(L/2) = 5 L^3 / (48 E I) + L / (2 kappa G A), E = 200 GPa, nu = 0.3,
///   I = t h^3 / 12, A = t h, t = 1 m, h = 0.01 m, L = 2 m (the deck's constants in
///   plane stress): the built-in within 2e-4 (measured +1.0e-4: beam theory's section
///   stays rigid and its load is a resultant, where the model's clamp holds u_x = 0 on
///   the face and u_y = 0 at its mid node only, and its load is a point force at the
///   face's mid node); the CalculiX beam is then within the sum (measured +1.9e-4).
#[test]
fn a_mid_span_sensor_reads_the_static_compliance_in_stick() {
    let (length, height, thickness) = (2.0_f64, 0.01_f64, 1.0_f64);
    let (e, nu) = (200e9, 0.3);
    let inertia = thickness * height.powi(3) / 12.0;
    let shear = e / (2.0 * (1.0 + nu)) * (5.0 / 6.0) * thickness * height;
    let closed_form = 5.0 * length.powi(3) / (48.0 * e * inertia) + length / (2.0 * shear);

    let scene = scene_with(
        FidelityLevel::PlaneStress,
        0.39,
        vec![sensor("mid", 252, 2)],
    );
    let b = scene.damping.stiffness_proportional;
    let compliance = |samples: &[stickslip::simulation::Sample], mid: SensorReading| {
        (mid.displacement + b * mid.velocity) / samples.last().unwrap().friction_force
    };
    // The built-in model at the deck's mesh: CalculiX node k is StripMesh node k - 1;
    // equations follow nodes, x then y, the clamp's (nodes 0 to 2: x fixed, y free at 0
    // and 2) first, so node k >= 3 has y at 3 + 2 (k - 3). Node 501 (the contact) is
    // then 999, which the tip's Simpson weights confirm.
    let mut built_in_scene = scene.clone();
    built_in_scene.structure = None;
    let built_in_scene = built_in_scene.check().unwrap();
    let mut model =
        StructuralModel::plane_stress(&built_in_scene, built_in_scene.fidelity.element_size);
    let y_of = |node: usize| 3 + 2 * (node - 3);
    let &(tip, weight) = model.tip.iter().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    assert_eq!((tip, weight), (y_of(501), 4.0 / 6.0));
    model.tip = vec![(tip, 1.0)];
    model.sensors = vec![vec![(y_of(251), 1.0)]];
    let law = LawSource::resolve(&built_in_scene).unwrap().law().unwrap();
    let mut sim = Simulator::with_model(built_in_scene, model, law).unwrap();
    let (samples, readings) = sim.run_observed(1).unwrap();
    assert!(sim.transitions().is_empty(), "built-in: still in stick");
    let built_in = compliance(&samples, readings.last().unwrap()[0]);
    let beam_theory = (built_in - closed_form) / closed_form;
    println!(
        "built-in at node 252: {built_in:.10e} m/N, closed form {closed_form:.10e}, {beam_theory:+.2e}"
    );
    assert!(beam_theory.abs() < 2e-4, "{beam_theory:e}");

    for level in [FidelityLevel::PlaneStress, FidelityLevel::Modal] {
        let run = run(scene_with(level, 0.39, vec![sensor("mid", 252, 2)]));
        assert_eq!(run.summary.slip_phases, 0, "{level:?}: still in stick");
        let calculix = compliance(&run.samples, run.sensors.last().unwrap()[0]);
        let files = (calculix - built_in) / built_in;
        let closed = (calculix - closed_form) / closed_form;
        println!(
            "{level:?}: CalculiX at node 252: {calculix:.10e} m/N, {files:+.2e} from the built-in, {closed:+.2e} from the closed form"
        );
        assert!(files.abs() < 2e-4, "{level:?}: {files:e}");
    }
}

/// The refusals name the sensor: its name, its DOF, the rule.
#[test]
fn bad_sensors_are_refused_by_name() {
    let refused = |sensors: Vec<Sensor>| {
        scene_with(FidelityLevel::PlaneStress, 0.01, sensors)
            .check()
            .err()
            .map(|e| e.to_string())
    };
    assert_eq!(
        refused(vec![sensor("mid-span", 252, 2)]).unwrap(),
        "invalid scene: structure.sensors = 'mid-span'; it must be a name of ASCII letters, digits and _ that starts with a letter or _ (it becomes an FMI variable and a CSV column)"
    );
    assert_eq!(
        refused(vec![sensor("a", 252, 2), sensor("a", 253, 2)]).unwrap(),
        "invalid scene: structure.sensors = 'a'; it must be a name whose outputs a and a_velocity no other sensor has: 'a' has a"
    );
    assert_eq!(
        refused(vec![sensor("a", 252, 2), sensor("a_velocity", 253, 2)]).unwrap(),
        "invalid scene: structure.sensors = 'a_velocity'; it must be a name whose outputs a_velocity and a_velocity_velocity no other sensor has: 'a' has a_velocity"
    );
    assert_eq!(
        refused(vec![sensor("mid", 252, 7)]).unwrap(),
        "invalid scene: structure.sensors = 'mid' at node 252 direction 7; it must be a direction in 1..=6 (x, y, z, then rotations about them)"
    );
    // Not in the files (node 9999), and removed by them (node 2 direction 2: the
    // clamp's middle node): known when the model is built.
    for (node, direction) in [(9999, 2), (2, 2)] {
        let scene = scene_with(
            FidelityLevel::PlaneStress,
            0.01,
            vec![sensor("mid", node, direction)],
        );
        let checked = scene.check().unwrap();
        let error = StructuralModel::build(&checked).err().unwrap().to_string();
        assert_eq!(
            error,
            format!("[structure]: structure.sensors 'mid' = node {node} direction {direction} is not a free DOF of the structure (1002 free DOFs: not in the files' DOF map, or removed by them or by structure.clamped; a sensor reads a DOF that can move)")
        );
        let mut modal = checked.scene().clone();
        modal.fidelity.level = FidelityLevel::Modal;
        let error = StructuralModel::build(&modal.check().unwrap())
            .err()
            .unwrap()
            .to_string();
        assert!(error.contains("structure.sensors 'mid'"), "{error}");
    }
    // In structure.clamped.
    let mut scene = scene_with(
        FidelityLevel::PlaneStress,
        0.01,
        vec![sensor("mid", 252, 2)],
    );
    scene.structure.as_mut().unwrap().clamped = vec![SceneDof {
        node: 252,
        direction: 2,
    }];
    assert_eq!(
        scene.check().err().unwrap().to_string(),
        "invalid scene: structure.sensors = 'mid' at node 252 direction 2; it must be a free DOF: structure.clamped fixes it, so it would read 0"
    );
}
