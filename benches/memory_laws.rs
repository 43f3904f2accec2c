//! Run time of the friction laws with state (LuGre, rate-and-state, and the shipped
//! learned law with memory, `weights/rate-and-state-learned.json`) over the exponential
//! law's, on the paper scene (1.2 s, dt = 1e-4 s, default parameters) at
//! modal (10 modes of 100 beam elements) and beam (100 elements) fidelity, all in the
//! same run (docs/friction-with-memory.md).
//!
//! Run: `cargo bench -p stickslip-tests --bench memory_laws`.

use std::time::Duration;

use criterion::{Criterion, SamplingMode};
use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::LawSource;
use stickslip::run::run_scene;
use stickslip::scene::{FidelityLevel, Scene};
use stickslip_tests::bench::{ratio, shown, table_note, Samples};

const SAMPLE_SIZE: usize = 10;

fn main() {
    let mut c = Criterion::default().without_plots().configure_from_args();
    let times = Samples::new(SAMPLE_SIZE);
    let levels = [FidelityLevel::Modal, FidelityLevel::Beam];
    // (label, law, weights file): the learned law is a neural law told by its file.
    let learned = stickslip_tests::weights_dir().join("rate-and-state-learned.json");
    let learned = learned.to_string_lossy().into_owned();
    let laws = [
        ("exponential", FrictionLawKind::Exponential, None),
        ("lugre", FrictionLawKind::Lugre, None),
        ("rate-and-state", FrictionLawKind::RateAndState, None),
        (
            "learned with memory",
            FrictionLawKind::Neural,
            Some(learned),
        ),
    ];
    let id = |level: FidelityLevel, label: &str| format!("{} {label}", level.name());
    let mut group = c.benchmark_group("memory_laws");
    group
        .sample_size(SAMPLE_SIZE)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(2));
    for level in levels {
        for (label, law, weights) in &laws {
            let mut scene = Scene::default();
            scene.fidelity.level = level;
            scene.friction.law = *law;
            scene.friction.weights = weights.clone();
            let checked = scene.check().unwrap();
            let source = LawSource::resolve(&checked).unwrap();
            let name = id(level, label);
            group.bench_function(&name, |b| {
                b.iter_custom(|iters| {
                    times.time(&name, iters, || {
                        run_scene(checked.clone(), &source, 1).unwrap()
                    })
                })
            });
        }
    }
    group.finish();
    c.final_summary();

    println!();
    println!(
        "paper scene, 12 000 steps of 1e-4 s ({})",
        table_note(&times)
    );
    println!(
        "{:<32} {:>12} {:>16}",
        "fidelity, law", "wall (s)", "x exponential"
    );
    for level in levels {
        let baseline = times.median(&id(level, "exponential"));
        for (label, _, _) in &laws {
            let seconds = times.median(&id(level, label));
            println!(
                "{:<32} {:>12} {:>16}",
                id(level, label),
                shown(seconds, 1.0, 4),
                ratio(seconds, baseline, 2)
            );
        }
    }
}
