//! Writes the seed inputs of every fuzz target into `fuzz/corpus/<target>/seed-*`:
//! real serialized FMU states from short runs of both FMUs, weights files derived from
//! the shipped ones, small ONNX networks, scene files as the CLI accepts them, and
//! training CSV files. Every seed is checked to be accepted by the code it is for, so the fuzzer starts from
//! valid inputs.
//!
//! `cargo run --release --manifest-path fuzz/Cargo.toml --example seeds`
//! (scripts/fuzz.sh runs it). The output is deterministic: running it again rewrites the
//! same files.

use std::path::{Path, PathBuf};
use stickslip::neural::{
    Activation, FeatureRole, NeuralLaw, NeuralModel, SyntheticSpec, PAPER_PLAIN_JSON,
    PAPER_SIGNED_JSON,
};
use stickslip::scene::Scene;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::instance::{Instance, Mode, SavedState};
use stickslip_fmi::model::Model;
use stickslip_fuzz::resources;
use stickslip_tests::onnx::cut;
use stickslip_tests::vr;
use stickslip_train::csv::{read_csv_file, ColumnSelection};
use stickslip_train::data::Synthetic;

fn corpus(target: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("corpus")
        .join(target);
    std::fs::create_dir_all(&dir).expect("cannot create the corpus folder");
    dir
}

fn write(target: &str, name: &str, bytes: &[u8]) {
    let path = corpus(target).join(format!("seed-{name}"));
    std::fs::write(&path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    println!("{:>7} bytes  {}", bytes.len(), path.display());
}

fn instance<M: Model>() -> Instance<M> {
    Instance::new("seeds", Some(&resources()), false, Box::new(|_, _, _| {}))
        .expect("instantiation on the shipped weights")
}

/// Serializes the FMU's state, checks that a fresh instance restores it, and writes it.
fn save_state<M: Model>(fmu: &mut Instance<M>, name: &str) {
    let state = fmu.get_state().expect("fmi2GetFMUstate");
    let bytes = fmu.serialize_state(&state).expect("fmi2SerializeFMUstate");
    let mut fresh = instance::<M>();
    let back = fresh
        .deserialize_state(&bytes)
        .expect("fmi2DeSerializeFMUstate");
    if state.mode != Mode::Error {
        fresh.set_state(&back).expect("fmi2SetFMUstate");
    }
    write("fmu_state", &format!("{name}.json"), &bytes);
}

/// A beam on `level` (1 modal, 2 beam, 3 plane-stress) with a coarse model and a 1 ms
/// step, initialised for 0..1.2 s after `configure` set its parameters.
fn beam(
    level: i32,
    configure: impl FnOnce(&mut Instance<StickSlipBeam>),
) -> Instance<StickSlipBeam> {
    let mut b = instance::<StickSlipBeam>();
    b.setup_experiment(0.0, Some(1.2)).unwrap();
    let ints = [
        (vr::<StickSlipBeam>("fidelity.level"), level),
        (vr::<StickSlipBeam>("fidelity.beam_elements"), 6),
        (vr::<StickSlipBeam>("fidelity.modes"), 3),
    ];
    for (r, v) in ints {
        b.set_integer(&[r], &[v]).unwrap();
    }
    let reals = [
        (vr::<StickSlipBeam>("time.step"), 1e-3),
        (vr::<StickSlipBeam>("fidelity.element_size"), 0.25),
    ];
    for (r, v) in reals {
        b.set_real(&[r], &[v]).unwrap();
    }
    configure(&mut b);
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    b
}

fn steps(b: &mut Instance<StickSlipBeam>, n: usize, h: f64) {
    for _ in 0..n {
        let t = b.time();
        b.do_step(t, h).unwrap();
    }
}

fn fmu_states() {
    let mut fresh = instance::<StickSlipBeam>();
    save_state(&mut fresh, "beam-instantiated");

    let mut init = instance::<StickSlipBeam>();
    init.setup_experiment(0.0, Some(1.2)).unwrap();
    init.set_integer(&[vr::<StickSlipBeam>("fidelity.level")], &[2])
        .unwrap();
    init.set_integer(&[vr::<StickSlipBeam>("fidelity.beam_elements")], &[6])
        .unwrap();
    init.enter_initialization_mode().unwrap();
    save_state(&mut init, "beam-initialization-mode");

    let mut b = beam(2, |_| {});
    steps(&mut b, 3, 1e-3);
    save_state(&mut b, "beam-stepped");

    // Until a few stick/slip transitions are recorded.
    let mut slipping = beam(2, |_| {});
    let mut transitions = [0];
    while transitions[0] < 3 && slipping.time() < 1.1 {
        steps(&mut slipping, 1, 1e-2);
        slipping
            .get_integer(&[vr::<StickSlipBeam>("transitions")], &mut transitions)
            .unwrap();
    }
    save_state(&mut slipping, "beam-transitions");
    slipping.terminate().unwrap();
    save_state(&mut slipping, "beam-terminated");

    let mut modal = beam(1, |b| {
        let enums = [
            ("integrator.scheme", 2),
            ("friction.law", 4),
            ("contact.initial_state", 2),
            ("contact.holding_force", 2),
            ("contact.sliding_velocity", 2),
        ];
        for (name, v) in enums {
            b.set_integer(&[vr::<StickSlipBeam>(name)], &[v]).unwrap();
        }
    });
    steps(&mut modal, 2, 2.5e-3);
    save_state(&mut modal, "beam-modal-moreau-external");

    let mut plane = beam(3, |b| {
        b.set_integer(&[vr::<StickSlipBeam>("fidelity.clamp")], &[2])
            .unwrap();
    });
    steps(&mut plane, 2, 1e-3);
    save_state(&mut plane, "beam-plane-stress");

    let mut neural = beam(2, |b| {
        b.set_integer(&[vr::<StickSlipBeam>("friction.law")], &[3])
            .unwrap();
        b.set_string(
            &[vr::<StickSlipBeam>("friction.weights")],
            &["paper-signed.json"],
        )
        .unwrap();
    });
    steps(&mut neural, 2, 1e-3);
    save_state(&mut neural, "beam-neural");

    // The Error mode: a step from the wrong time.
    let mut failed = beam(2, |_| {});
    steps(&mut failed, 1, 1e-3);
    assert!(failed.do_step(0.5, 1e-3).is_err());
    save_state(&mut failed, "beam-error");

    let mut f = instance::<NeuralFriction>();
    save_state(&mut f, "friction-instantiated");
    f.setup_experiment(0.0, None).unwrap();
    f.set_real(&[vr::<NeuralFriction>("sliding_velocity")], &[0.1])
        .unwrap();
    f.enter_initialization_mode().unwrap();
    f.exit_initialization_mode().unwrap();
    f.do_step(0.0, 1e-3).unwrap();
    save_state(&mut f, "friction-stepped");

    let mut e = instance::<NeuralFriction>();
    e.set_integer(&[vr::<NeuralFriction>("law")], &[2]).unwrap();
    e.set_string(&[vr::<NeuralFriction>("weights")], &["paper-signed.json"])
        .unwrap();
    e.enter_initialization_mode().unwrap();
    save_state(&mut e, "friction-exponential");

    // A hand-made state: valid syntax, wrong format name (the first check).
    let mut foreign: SavedState = fresh.get_state().unwrap();
    foreign.format = "another-format".into();
    write(
        "fmu_state",
        "foreign-format.json",
        &serde_json::to_vec(&foreign).unwrap(),
    );
}

fn weights() {
    let plain = NeuralModel::from_json(PAPER_PLAIN_JSON, "paper-plain").unwrap();
    let signed = NeuralModel::from_json(PAPER_SIGNED_JSON, "paper-signed").unwrap();
    let mut models = vec![
        ("plain-tanh-2-4-1", cut(&plain, &[4], Activation::Tanh)),
        ("plain-linear-2-1", cut(&plain, &[], Activation::Tanh)),
        (
            "signed-sigmoid-2-3-2-1",
            cut(&signed, &[3, 2], Activation::Sigmoid),
        ),
        ("signed-relu-2-2-1", cut(&signed, &[2], Activation::Relu)),
    ];
    // A third feature (role other): loads, but is not the beam's friction law.
    let mut three = cut(&plain, &[2], Activation::Tanh);
    let mut temperature = three.features[1].clone();
    temperature.name = "temperature".into();
    temperature.unit = "K".into();
    temperature.role = FeatureRole::Other;
    three.features.push(temperature);
    three.layer_sizes[0] = 3;
    for row in &mut three.layers[0].weights {
        row.push(0.25);
    }
    models.push(("plain-three-features", three));

    for (name, model) in models {
        let text = model.to_json().unwrap();
        NeuralLaw::from_json(&text, name).unwrap_or_else(|e| panic!("{name}: {e}"));
        write("weights", &format!("{name}.json"), text.as_bytes());
    }
    // One compact (single-line) file.
    let compact = serde_json::to_string(&cut(&signed, &[3], Activation::Tanh)).unwrap();
    NeuralLaw::from_json(&compact, "compact").unwrap();
    write("weights", "signed-compact.json", compact.as_bytes());
}

fn scenes() {
    let files: &[(&str, &str)] = &[
        ("empty.toml", ""),
        (
            "beam.toml",
            "# beam elements, coarse step\n[fidelity]\nlevel = \"beam\"\nbeam_elements = 20\n\n[time]\nstep = 1e-3\nend = 0.5\n",
        ),
        (
            "modal-moreau.toml",
            "[fidelity]\nlevel = \"modal\"\nmodes = 4\nmodal_basis = \"beam\"\nbeam_elements = 10\nstatic_correction = false\n\n[integrator]\nscheme = \"moreau-jean\"\ntheta = 0.7\n",
        ),
        (
            "plane-stress-options.toml",
            "[geometry]\nlength = 1.0\nheight = 0.05\nwidth = 0.5\n\n[material]\ndensity = 7800.0\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.25\n\n[fidelity]\nlevel = \"plane-stress\"\nelement_size = 0.1\nclamp = \"full\"\n\n[contact]\nholding_force = \"euler-bernoulli\"\nsliding_velocity = \"tip\"\ninitial_state = \"at-rest\"\n\n[friction]\nlaw = \"coulomb\"\nstatic_coefficient = 0.6\nkinetic_coefficient = 0.3\n\n[loading]\nbelt_speed = -0.05\nnormal_force = 50\n",
        ),
        (
            "neural.json",
            "{\"fidelity\": {\"level\": \"beam\", \"beam_elements\": 4}, \"friction\": {\"law\": \"neural\"}, \"damping\": {\"mass_proportional\": 0.1, \"stiffness_proportional\": 0.0}}\n",
        ),
        (
            "modal-plane-stress.json",
            "{\"fidelity\": {\"level\": \"modal\", \"modal_basis\": \"plane-stress\", \"element_size\": 0.25, \"modes\": 3}, \"integrator\": {\"rho_inf\": 0.5}, \"time\": {\"step\": 0.002, \"end\": 0.1}}\n",
        ),
        (
            "weights-path.toml",
            "[friction]\nlaw = \"neural\"\nweights = \"weights/paper-signed.json\"\n",
        ),
    ];
    let check = |name: &str, bytes: &[u8]| {
        let text = std::str::from_utf8(bytes).unwrap();
        let scene = if name.ends_with(".json") {
            Scene::from_json_str(text)
        } else {
            Scene::from_toml_str(text)
        };
        scene
            .and_then(Scene::check)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    };
    for (name, text) in files {
        check(name, text.as_bytes());
        write("scene", name, text.as_bytes());
    }
    // The paper's scene with every field written out, in both formats.
    let full_toml = toml::to_string(&Scene::default()).unwrap();
    check("paper-full.toml", full_toml.as_bytes());
    write("scene", "paper-full.toml", full_toml.as_bytes());
    let full_json = serde_json::to_string_pretty(&Scene::default()).unwrap();
    check("paper-full.json", full_json.as_bytes());
    write("scene", "paper-full.json", full_json.as_bytes());
}

fn training_csv() {
    let paper = ColumnSelection {
        features: vec!["sliding_velocity".into(), "normal_force".into()],
        target: "friction_force".into(),
        sliding_velocity: Some("sliding_velocity".into()),
        normal_force: Some("normal_force".into()),
    };
    let short = ColumnSelection {
        features: vec!["v".into(), "Fn".into(), "T".into()],
        target: "F".into(),
        sliding_velocity: Some("v".into()),
        normal_force: Some("Fn".into()),
    };
    // The synthetic data as `stickslip train --export-data` writes it, at two sizes
    // (the small one reaches the harness's training run).
    for samples in [20, 100] {
        let spec = SyntheticSpec {
            samples,
            ..SyntheticSpec::default()
        };
        let split = spec.generate_split(2).unwrap();
        let path = std::env::temp_dir().join(format!("stickslip-seeds-{samples}.csv"));
        split.train.write_csv(&path).unwrap();
        let text = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        write("training_csv", &format!("synthetic-{samples}.csv"), &text);
    }
    let measured = "\u{feff}time[s], F[N], Fn[N], v[m/s], T[K], note\n\
                    # measured on the test rig\n\
                    0, 1.5, 100, 0.1, 293.15, ok\n\
                    \n\
                    0.5, -2, 90, -0.2, 293.4, \"x\"\n\
                    1.0, 40.25, 110, 0.35, 294, \"\"\n\
                    1.5, 0.0, 95, 0, 294.5, stick\n";
    write("training_csv", "measured.csv", measured.as_bytes());
    let paper_columns = "sliding_velocity[m/s],normal_force[N],friction_force[N]\n\
                         0.1,100,24.1\n-0.1,100,-24.1\n0.3,90,19.8\n-0.02,110,-49.9\n0,105,0\n";
    write(
        "training_csv",
        "paper-columns.csv",
        paper_columns.as_bytes(),
    );

    // Every seed must read with one of the harness's selections.
    for entry in std::fs::read_dir(corpus("training_csv")).unwrap() {
        let path = entry.unwrap().path();
        if !path
            .file_name()
            .unwrap()
            .to_string_lossy()
            .starts_with("seed-")
        {
            continue;
        }
        let ok = [&paper, &short]
            .iter()
            .any(|s| read_csv_file(&path, s).is_ok());
        assert!(ok, "{} reads with no selection", path.display());
    }
}

/// Small networks in the forms PyTorch and skl2onnx export (`stickslip_tests::onnx`).
fn onnx() {
    for (name, bytes) in stickslip_tests::onnx::fuzz_seeds() {
        stickslip_formats::onnx::read_onnx(&bytes, &name).unwrap_or_else(|e| panic!("{name}: {e}"));
        write("onnx", &name, &bytes);
    }
}

fn main() {
    fmu_states();
    weights();
    onnx();
    scenes();
    training_csv();
}
