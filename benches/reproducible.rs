//! The price of the same bits everywhere (issue 25), in one run:
//!
//! - the network's forward pass with its slope (the shipped plain network, f64), as the
//!   time-step loop runs it (`stickslip::neural::forward::Forward`: unfused, AVX2 where
//!   detected), against the fused AVX2 + FMA kernel it replaced, kept here only as the
//!   baseline (`fused`: forward.rs as it was, benches/reproducible/fused_forward.rs);
//! - the paper scene with the analytical law (1.2 s, stepping only, modal and plane
//!   stress), whose `exp` is now the `libm` crate's, against the same law with the
//!   platform's `f64::exp` (glibc's, FMA kernel on this CPU) written here
//!   ([`PlatformExp`]);
//! - the paper scene with the neural law (plane stress): its time now, and what the fused
//!   kernel would save on it: its law evaluations (counted) times the difference per
//!   forward pass measured above.
//!
//! Run: `cargo bench -p stickslip-tests --bench reproducible` (about a minute built).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode};
use stickslip::choice::Choice;
use stickslip::elementary::signum_or_zero;
use stickslip::friction::FrictionLawKind;
use stickslip::friction::{exponential::ExponentialLaw, FrictionLaw};
use stickslip::neural::forward::Forward;
use stickslip::neural::NeuralLaw;
use stickslip::scene::{CheckedScene, FidelityLevel, Scene};
use stickslip::simulation::Simulator;
use stickslip_tests::bench::{ratio, shown, table_note, Samples};

const SAMPLE_SIZE: usize = 10;
const INPUTS: usize = 2_000;

/// The forward pass before issue 25, fused on AVX2 + FMA CPUs (the baseline).
#[path = "reproducible/fused_forward.rs"]
mod fused;

/// Eq. 6 with the platform's `exp`: `ExponentialLaw` as it was before issue 25.
struct PlatformExp(ExponentialLaw);

impl PlatformExp {
    #[allow(clippy::disallowed_methods)] // the baseline: the platform's exp on purpose
    fn coefficient_and_slope(&self, speed: f64) -> (f64, f64) {
        let law = &self.0;
        let drop =
            (law.static_coefficient - law.kinetic_coefficient) * (-law.decay * speed.abs()).exp();
        (law.kinetic_coefficient + drop, -law.decay * drop)
    }
}

impl FrictionLaw for PlatformExp {
    fn name(&self) -> &str {
        FrictionLawKind::Exponential.name()
    }
    fn sliding_force(&mut self, v: f64, normal_force: f64) -> f64 {
        self.sliding_force_and_slope(v, normal_force).0
    }
    fn sliding_force_and_slope(&mut self, v: f64, normal_force: f64) -> (f64, f64) {
        let (mu, slope) = self.coefficient_and_slope(v);
        (signum_or_zero(v) * mu * normal_force, slope * normal_force)
    }
}

fn scene(level: FidelityLevel, law: FrictionLawKind) -> CheckedScene {
    let mut scene = Scene::default();
    scene.fidelity.level = level;
    scene.friction.law = law;
    scene.check().expect("paper scene")
}

/// Seconds of stepping through the whole scene (the simulator is built outside).
fn stepping(scene: &CheckedScene, law: Box<dyn FrictionLaw>) -> (f64, usize) {
    let mut sim = Simulator::new(scene.clone(), law).expect("simulator");
    let steps = (scene.time.end / scene.time.step).round() as usize;
    let mut evaluations = 0;
    let start = Instant::now();
    for _ in 0..steps {
        sim.step().expect("step");
        evaluations += sim.last_slip_solve().map_or(0, |s| s.evaluations);
    }
    black_box(sim.sample());
    (start.elapsed().as_secs_f64(), evaluations)
}

fn main() {
    if !(std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma"))
    {
        println!("this CPU has no AVX2 + FMA: the fused baseline cannot run here");
        return;
    }
    let mut c = Criterion::default().without_plots().configure_from_args();
    let times = Samples::new(SAMPLE_SIZE);

    // The shipped plain network, in both kernels, at standardised inputs in [-2, 2].
    let model = NeuralLaw::paper_default()
        .expect("shipped weights")
        .model()
        .clone();
    let features = model.features.len();
    let rows: Vec<(Vec<Vec<f64>>, Vec<f64>)> = model
        .layers
        .iter()
        .map(|l| (l.weights.clone(), l.biases.clone()))
        .collect();
    let mut ours = Forward::<f64>::new(features, &rows, model.activation);
    let mut old = fused::Forward::<f64>::new(features, &rows, model.activation);
    let points: Vec<Vec<f64>> = (0..INPUTS)
        .map(|i| {
            (0..features)
                .map(|k| 4.0 * (((i * 7 + k * 3) % 101) as f64 / 100.0) - 2.0)
                .collect()
        })
        .collect();
    let tangent: Vec<f64> = (0..features)
        .map(|k| if k == 0 { 1.0 } else { 0.0 })
        .collect();
    let mut run_ours = |x: &[f64]| {
        let (values, tangents) = ours.inputs_mut();
        values[..features].copy_from_slice(x);
        tangents[..features].copy_from_slice(&tangent);
        ours.run::<true>()
    };
    let mut run_old = |x: &[f64]| {
        let (values, tangents) = old.inputs_mut();
        values[..features].copy_from_slice(x);
        tangents[..features].copy_from_slice(&tangent);
        old.run::<true>()
    };
    // The baseline is the same network: fusing moves the last bits only.
    let worst = points
        .iter()
        .map(|x| {
            let ((a, da), (b, db)) = (run_ours(x), run_old(x));
            ((a - b).abs() / (1.0 + a.abs())).max((da - db).abs() / (1.0 + da.abs()))
        })
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-12,
        "the fused baseline is another network: {worst:e}"
    );

    let mut group = c.benchmark_group("reproducible");
    group
        .sample_size(SAMPLE_SIZE)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    group.bench_function("forward, fixed", |b| {
        b.iter_custom(|iters| {
            times.time("forward, fixed", iters, || {
                points.iter().map(|x| run_ours(x).0).sum::<f64>()
            })
        })
    });
    group.bench_function("forward, fused", |b| {
        b.iter_custom(|iters| {
            times.time("forward, fused", iters, || {
                points.iter().map(|x| run_old(x).0).sum::<f64>()
            })
        })
    });
    let levels = [FidelityLevel::Modal, FidelityLevel::PlaneStress];
    for level in levels {
        let scene = scene(level, FrictionLawKind::Exponential);
        let libm_id = format!("{level:?}, analytical, libm exp");
        group.bench_function(&libm_id, |b| {
            b.iter_custom(|iters| {
                let mut total = 0.0;
                for _ in 0..iters {
                    total += stepping(&scene, Box::new(scene.friction.exponential_law())).0;
                }
                times.record(&libm_id, total / iters.max(1) as f64);
                Duration::from_secs_f64(total)
            })
        });
        let platform_id = format!("{level:?}, analytical, platform exp");
        group.bench_function(&platform_id, |b| {
            b.iter_custom(|iters| {
                let mut total = 0.0;
                for _ in 0..iters {
                    let law = PlatformExp(scene.friction.exponential_law());
                    total += stepping(&scene, Box::new(law)).0;
                }
                times.record(&platform_id, total / iters.max(1) as f64);
                Duration::from_secs_f64(total)
            })
        });
    }
    let mut neural_scene = Scene::default();
    neural_scene.fidelity.level = FidelityLevel::PlaneStress;
    neural_scene.friction.law = FrictionLawKind::Neural;
    let neural = neural_scene.clone().check().expect("paper scene");
    let neural_law = || stickslip_tests::law_of(&neural_scene).law().expect("law");
    let mut evaluations = 0;
    group.bench_function("PlaneStress, neural plain", |b| {
        b.iter_custom(|iters| {
            let mut total = 0.0;
            for _ in 0..iters {
                let (t, n) = stepping(&neural, neural_law());
                total += t;
                evaluations = n;
            }
            times.record("PlaneStress, neural plain", total / iters.max(1) as f64);
            Duration::from_secs_f64(total)
        })
    });
    group.finish();
    c.final_summary();

    println!(
        "\nthe price of the same bits everywhere ({})",
        table_note(&times)
    );
    let per = |id: &str| times.median(id).map(|t| t / INPUTS as f64);
    let (fixed, fused) = (per("forward, fixed"), per("forward, fused"));
    println!(
        "forward pass + slope, shipped plain network: fixed {} ns, fused {} ns: fixed / fused = {}",
        shown(fixed, 1e9, 1),
        shown(fused, 1e9, 1),
        ratio(fixed, fused, 3)
    );
    for level in levels {
        let libm = times.median(&format!("{level:?}, analytical, libm exp"));
        let platform = times.median(&format!("{level:?}, analytical, platform exp"));
        println!(
            "paper scene 1.2 s, {level:?}, analytical: libm exp {} s, platform exp {} s: libm / platform = {}",
            shown(libm, 1.0, 4),
            shown(platform, 1.0, 4),
            ratio(libm, platform, 3)
        );
    }
    let run = times.median("PlaneStress, neural plain");
    let saved = fixed.zip(fused).map(|(a, b)| (a - b) * evaluations as f64);
    println!(
        "paper scene 1.2 s, PlaneStress, neural plain: {} s with {evaluations} forward passes; the fused kernel would take {} s of it: fixed / fused = {}",
        shown(run, 1.0, 4),
        shown(run.zip(saved).map(|(r, s)| r - s), 1.0, 4),
        ratio(run, run.zip(saved).map(|(r, s)| r - s), 3)
    );
}
