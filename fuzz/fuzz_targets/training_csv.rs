//! A training CSV file, read as `stickslip train --data FILE.csv --features ...
//! --target ...` reads it: `neural::cli::load_split` (which calls `read_csv_file`, then
//! splits the samples). Each input is read with three column selections: the paper's
//! columns (`sliding_velocity,normal_force` -> `friction_force`, the form `train
//! --export-data` writes), three short names with explicit roles, and a single feature.
//!
//! What loads is then used: the split's feature ranges, a round trip through
//! `Dataset::write_csv` (the `--export-data` writer) and back through the reader, and,
//! for small files, a tiny training run (one hidden layer of 3, 3 L-BFGS iterations,
//! both variants) as `stickslip train` would start it.
//!
//! Checked properties (a panic is a finding):
//! - nothing panics, whatever the bytes, the selection or the training that follows;
//! - a split is complete and both sides are non-empty;
//! - a data set written by `write_csv` reads back identical.

#![no_main]

use libfuzzer_sys::fuzz_target;
use stickslip_cli::train::{load_split, DataArgs};
use stickslip_train::csv::{read_csv_file, ColumnSelection};
use stickslip_train::train::DataSource;
use stickslip::neural::{FeatureRole, Variant};
use stickslip_train::{train, Dataset, TrainConfig};
use stickslip_fuzz::scratch_file;

/// Most training samples for which the tiny training run is done.
const MAX_TRAINING_SAMPLES: usize = 64;

fn presets(path: &std::path::Path) -> [DataArgs; 3] {
    let strings = |names: &[&str]| names.iter().map(|s| s.to_string()).collect();
    let args =
        |features: Vec<String>, target: &str, roles: [Option<&str>; 2], test: f64| DataArgs {
            data: Some(path.to_path_buf()),
            features,
            target: Some(target.to_string()),
            velocity_feature: roles[0].map(str::to_string),
            normal_force_feature: roles[1].map(str::to_string),
            test_fraction: test,
            test_data: None,
            samples: 5000,
            generator: Default::default(),
            seed: 2,
        };
    [
        args(
            strings(&["sliding_velocity", "normal_force"]),
            "friction_force",
            [None, None],
            0.3,
        ),
        args(
            strings(&["v", "Fn", "T"]),
            "F",
            [Some("v"), Some("Fn")],
            0.5,
        ),
        args(
            strings(&["sliding_velocity"]),
            "friction_force",
            [None, None],
            0.2,
        ),
    ]
}

fuzz_target!(|data: &[u8]| {
    let path = scratch_file("training_csv", "csv");
    std::fs::write(&path, data).expect("cannot write the scratch CSV file");
    for args in presets(&path) {
        let Ok((split, source)) = load_split(&args) else {
            continue;
        };
        use_split(&args, &split.train, &split.test, &source);
    }
});

fn use_split(args: &DataArgs, train_set: &Dataset, test_set: &Dataset, source: &DataSource) {
    assert!(
        !train_set.is_empty() && !test_set.is_empty(),
        "an empty side"
    );
    for k in 0..train_set.features.len() {
        let (lo, hi) = train_set.feature_range(k);
        assert!(lo <= hi, "feature range [{lo}, {hi}] of finite samples");
    }

    // write_csv and read back, with the selection that names what was written.
    let written = scratch_file("training_csv-written", "csv");
    train_set
        .write_csv(&written)
        .expect("cannot write the scratch CSV file");
    let name_with = |role: FeatureRole| {
        train_set
            .feature_with_role(role)
            .map(|k| train_set.features[k].name.clone())
    };
    let selection = ColumnSelection {
        features: train_set.features.iter().map(|q| q.name.clone()).collect(),
        target: train_set.target.name.clone(),
        sliding_velocity: name_with(FeatureRole::SlidingVelocity),
        normal_force: name_with(FeatureRole::NormalForce),
    };
    let back = read_csv_file(&written, &selection)
        .unwrap_or_else(|e| panic!("write_csv wrote a file that does not read back: {e}"));
    assert_eq!(&back, train_set, "write_csv round trip changed the data");

    if train_set.len() > MAX_TRAINING_SAMPLES {
        return;
    }
    let split = stickslip_train::Split {
        train: train_set.clone(),
        test: test_set.clone(),
    };
    for variant in [Variant::Plain, Variant::Signed] {
        let config = TrainConfig {
            hidden_layers: vec![3],
            variant,
            max_iterations: 3,
            blocks: 1,
            seed: args.seed,
            ..TrainConfig::default()
        };
        if let Ok((model, _report)) = train(&split, &config, source, |_| {}) {
            // What `stickslip train` does next: validate and write the weights.
            let _ = model.validate("trained");
            let _ = model.to_json();
        }
    }
}
