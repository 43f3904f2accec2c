//! Helpers shared by the test binaries (`physics`, `fmu`, `neural`, `cli`) and the
//! benchmarks.

use std::path::PathBuf;
use stickslip_fmi::model::Model;

pub mod bench;
pub mod fmi_log;
pub mod onnx;

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(".."))
}

/// The shipped networks, `weights/` (the FMUs' `resources/` folder holds the same files).
pub fn weights_dir() -> PathBuf {
    workspace_root().join("weights")
}

/// A copy of the paper's network with four more features (role `other`, trained range
/// [-1, 1]) that every hidden unit of the first layer reads: a network that uses all of
/// NeuralFriction's inputs. Written to a temporary file named after `tag` and the
/// process (tests run in parallel, and each removes its file).
pub fn six_feature_weights(tag: &str) -> PathBuf {
    let mut model =
        stickslip::neural::NeuralModel::load(&weights_dir().join("paper-plain.json")).unwrap();
    for k in 1..=4 {
        model
            .features
            .push(stickslip::neural::weights::FeatureSpec {
                name: format!("extra{k}"),
                unit: String::new(),
                role: stickslip::neural::FeatureRole::Other,
                input_mean: 0.0,
                input_std: 1.0,
                min: -1.0,
                max: 1.0,
            });
    }
    model.layer_sizes[0] = 6;
    for (o, row) in model.layers[0].weights.iter_mut().enumerate() {
        for k in 0..4 {
            row.push(0.2 + 0.05 * ((o + k) % 5) as f64);
        }
    }
    let path = std::env::temp_dir().join(format!(
        "stickslip-six-features-{tag}-{}.json",
        std::process::id()
    ));
    model.save(&path).unwrap();
    path
}

/// The JSON text of serialized FMU state bytes: without the checksum that ends them from
/// state version 5 on (`stickslip_fmi::instance::CHECKSUM_MARK`).
pub fn state_json(bytes: &[u8]) -> &[u8] {
    use stickslip_fmi::instance::CHECKSUM_MARK;
    let trailer = CHECKSUM_MARK.len() + 8;
    match bytes.len().checked_sub(trailer) {
        Some(split) if bytes[split..].starts_with(CHECKSUM_MARK) => &bytes[..split],
        _ => bytes,
    }
}

/// The value reference of `M`'s variable `name`, read from its variable table (which the
/// modelDescription.xml is generated from), so that tests name variables instead of
/// retyping their numbers.
pub fn vr<M: Model>(name: &str) -> u32 {
    M::variables()
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("{} has no variable {name}", M::INFO.model_identifier))
        .value_reference
}

/// The shipped plain network with a third input, `temperature` (role other, range 20 to
/// 40 C), that it ignores (zero weights): a network with more inputs than the beam
/// supplies, as a weights file's text.
pub fn three_input_weights() -> String {
    use stickslip::neural::{FeatureRole, NeuralModel, PAPER_PLAIN_JSON};
    let mut model = NeuralModel::from_json(PAPER_PLAIN_JSON, "shipped").expect("shipped weights");
    let mut temperature = model.features[0].clone();
    temperature.name = "temperature".into();
    temperature.unit = "C".into();
    temperature.role = FeatureRole::Other;
    temperature.input_mean = 30.0;
    temperature.input_std = 5.0;
    temperature.min = 20.0;
    temperature.max = 40.0;
    model.features.push(temperature);
    model.layer_sizes[0] = 3;
    for row in &mut model.layers[0].weights {
        row.push(0.0);
    }
    model.to_json().expect("weights text")
}

/// The law source of `scene` (checked first), as a stand-alone run resolves it.
pub fn law_of(scene: &stickslip::scene::Scene) -> stickslip::law_source::LawSource {
    stickslip::law_source::LawSource::resolve(&scene.clone().check().expect("a valid scene"))
        .expect("the scene's law")
}
