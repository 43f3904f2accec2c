//! An imported network runs at the speed of a native one (issue 23): the shipped plain
//! network (2-100-100-100-1, tanh) from our JSON weights file against the same network
//! imported from ONNX, in the forms PyTorch (`torch.onnx.export`: Gemm, f64 and f32) and
//! scikit-learn (skl2onnx: Scaler, MatMul + Add, f32) write it, measured in the same run.
//!
//! Every file is written to a temporary folder (the ONNX ones by the test suite's writer,
//! `stickslip_tests::onnx`) and read the way a scene reads `friction.weights`
//! (`LawSource::resolve`, which takes JSON or ONNX by the file), so each law is the
//! `FrictionLaw` the time loop and the FMUs get. Each is timed over one force-and-slope
//! evaluation per input (what the slip solve calls), 20 000 inputs over the slip range,
//! for each inference (exact, f32, table). The table at the end gives the time per call
//! and the ratio imported / native from this run; it is a report, not an assertion. A
//! second copy of the native file is timed too: its ratio shows how far two identical
//! laws differ within one run.
//!
//! Run: `cargo bench -p stickslip-tests --bench onnx_import`.

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Duration;

use criterion::{Criterion, Throughput};
use stickslip::choice::Choice;
use stickslip::friction::FrictionLaw;
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::LawSource;
use stickslip::neural::inference::Inference;
use stickslip::neural::NeuralModel;
use stickslip::scene::Scene;
use stickslip_tests::bench::{ratio, shown, table_note, Samples};
use stickslip_tests::onnx::{export, Exporter};

const SAMPLE_SIZE: usize = 20;
const NATIVE: &str = "native JSON";

/// The files compared: (label, the file's bytes, file name).
fn files(model: &NeuralModel) -> Vec<(&'static str, Vec<u8>, &'static str)> {
    vec![
        (
            NATIVE,
            model.to_json().expect("json").into_bytes(),
            "native.json",
        ),
        // The same file read again: how far two identical laws' times differ in one run
        // (allocation, alignment, the load of a shared machine), the ratios' noise.
        (
            "native JSON, a copy",
            model.to_json().expect("json").into_bytes(),
            "native-copy.json",
        ),
        (
            "ONNX torch f64",
            export(model, Exporter::Torch, false).encode(),
            "torch-f64.onnx",
        ),
        (
            "ONNX torch f32",
            export(model, Exporter::Torch, true).encode(),
            "torch-f32.onnx",
        ),
        (
            "ONNX skl f32",
            export(model, Exporter::Skl, true).encode(),
            "skl-f32.onnx",
        ),
    ]
}

/// The law a scene with `friction.weights = path` and `inference` runs with.
fn law(path: &Path, inference: Inference) -> Box<dyn FrictionLaw> {
    let mut scene = Scene::default();
    scene.friction.law = FrictionLawKind::Neural;
    scene.friction.weights = Some(path.display().to_string());
    scene.friction.inference = inference;
    let checked = scene.check().expect("scene");
    LawSource::resolve(&checked)
        .and_then(|source| source.law())
        .expect("a friction law")
}

fn id(label: &str, inference: Inference) -> String {
    format!("{label}, {}", inference.name())
}

fn main() {
    let mut c = Criterion::default().without_plots().configure_from_args();
    let times = Samples::new(SAMPLE_SIZE);
    let model = NeuralModel::from_json(stickslip::neural::PAPER_PLAIN_JSON, "shipped")
        .expect("shipped plain weights");
    let folder: PathBuf =
        std::env::temp_dir().join(format!("stickslip-onnx-bench-{}", std::process::id()));
    std::fs::create_dir_all(&folder).expect("temporary folder");
    let written: Vec<(&str, PathBuf)> = files(&model)
        .into_iter()
        .map(|(label, bytes, name)| {
            let path = folder.join(name);
            std::fs::write(&path, bytes).expect("write");
            (label, path)
        })
        .collect();
    // Slip-range velocities of both signs at the normal forces of the training range.
    let inputs: Vec<(f64, f64)> = (0..20_000)
        .map(|i| {
            let t = i as f64 / 20_000.0;
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            (sign * (0.001 + 0.05 * t), 99.0 + 2.0 * t)
        })
        .collect();

    let mut group = c.benchmark_group("onnx_import");
    group
        .sample_size(SAMPLE_SIZE)
        .throughput(Throughput::Elements(inputs.len() as u64))
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    // Largest force difference to the native law per inference (N): the same network.
    let mut gaps = Vec::new();
    for inference in Inference::ALL {
        let mut native = law(&written[0].1, *inference);
        for (label, path) in &written {
            let mut imported = law(path, *inference);
            let gap = inputs
                .iter()
                .map(|&(v, f_n)| {
                    (imported.sliding_force(v, f_n) - native.sliding_force(v, f_n)).abs()
                })
                .fold(0.0_f64, f64::max);
            gaps.push((id(label, *inference), gap));
            let id = id(label, *inference);
            group.bench_function(&id, |b| {
                b.iter_custom(|iters| {
                    times.time(&id, iters, || {
                        let mut sum = 0.0;
                        for &(v, f_n) in &inputs {
                            let (force, slope) =
                                imported.sliding_force_and_slope(black_box(v), black_box(f_n));
                            sum += force + slope;
                        }
                        sum
                    })
                })
            });
        }
    }
    group.finish();
    c.final_summary();
    std::fs::remove_dir_all(&folder).ok();

    let per_call = |id: &str| times.median(id).map(|t| t / inputs.len() as f64);
    println!();
    println!(
        "force and slope per call ({}), over {} inputs; imported / native per inference:",
        table_note(&times),
        inputs.len()
    );
    for inference in Inference::ALL {
        let baseline = per_call(&id(NATIVE, *inference));
        for (label, _) in &written {
            let id = id(label, *inference);
            let gap = gaps.iter().find(|(g, _)| *g == id).map_or(0.0, |(_, g)| *g);
            println!(
                "  {id:<28}{:>9} ns   {}x native   (largest force difference {gap:.1e} N)",
                shown(per_call(&id), 1e9, 1),
                ratio(per_call(&id), baseline, 3),
            );
        }
    }
}
