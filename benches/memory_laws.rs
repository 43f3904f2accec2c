//! Run time of the friction laws with state (LuGre, rate-and-state) over the
//! exponential law's, on the paper scene (1.2 s, dt = 1e-4 s, default parameters) at
//! modal (10 modes of 100 beam elements) and beam (100 elements) fidelity, all in the
//! same run (docs/friction-with-memory.md).
//!
//! Run: `cargo bench -p stickslip-tests --bench memory_laws`.

use std::time::Duration;

use criterion::{Criterion, SamplingMode};
use stickslip::choice::Choice;
use stickslip::law_source::LawSource;
use stickslip::run::run_scene;
use stickslip::scene::{FidelityLevel, FrictionLawKind, Scene};
use stickslip_tests::bench::{ratio, shown, table_note, Samples};

const SAMPLE_SIZE: usize = 10;

fn main() {
    let mut c = Criterion::default().without_plots().configure_from_args();
    let times = Samples::new(SAMPLE_SIZE);
    let levels = [FidelityLevel::Modal, FidelityLevel::Beam];
    let laws = [
        FrictionLawKind::Exponential,
        FrictionLawKind::Lugre,
        FrictionLawKind::RateAndState,
    ];
    let id =
        |level: FidelityLevel, law: FrictionLawKind| format!("{} {}", level.name(), law.name());
    let mut group = c.benchmark_group("memory_laws");
    group
        .sample_size(SAMPLE_SIZE)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(2));
    for level in levels {
        for law in laws {
            let mut scene = Scene::default();
            scene.fidelity.level = level;
            scene.friction.law = law;
            let checked = scene.check().unwrap();
            let source = LawSource::resolve(&checked).unwrap();
            let name = id(level, law);
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
        let baseline = times.median(&id(level, FrictionLawKind::Exponential));
        for law in laws {
            let seconds = times.median(&id(level, law));
            println!(
                "{:<32} {:>12} {:>16}",
                id(level, law),
                shown(seconds, 1.0, 4),
                ratio(seconds, baseline, 2)
            );
        }
    }
}
