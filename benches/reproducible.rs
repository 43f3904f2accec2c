//! The price of the same bits everywhere (issue 25), in one run:
//!
//! - the network's forward pass with its slope (the shipped plain network, f64), as the
//!   time-step loop runs it (`stickslip::neural::forward::Forward`: unfused, AVX2 where
//!   detected), against the fused AVX2 + FMA kernel it replaced, kept here only as the
//!   baseline ([`fused`], the same blocked layout and tanh with every a b + c fused);
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
use stickslip::friction::{signum_or_zero, ExponentialLaw, FrictionLaw};
use stickslip::neural::forward::Forward;
use stickslip::neural::NeuralLaw;
use stickslip::scene::{CheckedScene, FidelityLevel, FrictionLawKind, Scene};
use stickslip::simulation::Simulator;
use stickslip_tests::bench::{ratio, shown, table_note, Samples};

const SAMPLE_SIZE: usize = 10;
const INPUTS: usize = 2_000;

/// The forward pass before issue 25: the blocked layout of `neural::forward` (blocks of
/// 20 outputs, column after column), compiled for AVX2 + FMA with every a b + c fused.
/// f64 and tanh only (the shipped networks).
mod fused {
    const BLOCK: usize = 20;

    pub struct Layer {
        inputs: usize,
        padded: usize,
        weights: Vec<f64>,
        biases: Vec<f64>,
    }

    impl Layer {
        pub fn new(rows: &[Vec<f64>], biases: &[f64]) -> Layer {
            let inputs = rows[0].len();
            let padded = rows.len().div_ceil(BLOCK) * BLOCK;
            let mut weights = Vec::with_capacity(padded * inputs);
            for start in (0..padded).step_by(BLOCK) {
                for i in 0..inputs {
                    for o in start..start + BLOCK {
                        weights.push(rows.get(o).map_or(0.0, |row| row[i]));
                    }
                }
            }
            let mut biases = biases.to_vec();
            biases.resize(padded, 0.0);
            Layer {
                inputs,
                padded,
                weights,
                biases,
            }
        }
    }

    /// The old kernel's tanh: expm1 by Cody-Waite reduction and a degree-13 polynomial
    /// by Estrin's scheme, fused.
    #[inline(always)]
    fn tanh(z: f64) -> f64 {
        const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
        const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
        const ROUND: f64 = 6_755_399_441_055_744.0;
        // 1 / k! for k = 2..13.
        const C: [f64; 12] = [
            1.0 / 2.0,
            1.0 / 6.0,
            1.0 / 24.0,
            1.0 / 120.0,
            1.0 / 720.0,
            1.0 / 5_040.0,
            1.0 / 40_320.0,
            1.0 / 362_880.0,
            1.0 / 3_628_800.0,
            1.0 / 39_916_800.0,
            1.0 / 479_001_600.0,
            1.0 / 6_227_020_800.0,
        ];
        let magnitude = z.abs();
        let x = if 2.0 * magnitude > 40.0 {
            40.0
        } else {
            2.0 * magnitude
        };
        let shifted = x.mul_add(std::f64::consts::LOG2_E, ROUND);
        let n = shifted - ROUND;
        let r = (-n).mul_add(LN2_LO, (-n).mul_add(LN2_HI, x));
        let r2 = r * r;
        let r4 = r2 * r2;
        let pair = |k: usize| C[k + 1].mul_add(r, C[k]);
        let q0 = pair(2).mul_add(r2, pair(0));
        let q1 = pair(6).mul_add(r2, pair(4));
        let q2 = pair(10).mul_add(r2, pair(8));
        let q = q2.mul_add(r4 * r4, q1.mul_add(r4, q0));
        let expm1_r = r2.mul_add(q, r);
        let bits = shifted.to_bits().wrapping_sub(ROUND.to_bits());
        let scale = f64::from_bits(bits.wrapping_add(1023) << 52);
        let m = scale.mul_add(expm1_r, scale - 1.0);
        (m / (m + 2.0)).copysign(z)
    }

    /// The network with its scratch buffers (no allocation per call, as in the old one).
    pub struct Network {
        layers: Vec<Layer>,
        output: Vec<f64>,
        bias: f64,
        buffers: [Vec<f64>; 4],
    }

    impl Network {
        pub fn new(layers: Vec<Layer>, output: Vec<f64>, bias: f64) -> Network {
            let widest = layers
                .iter()
                .map(|l| l.padded.max(l.inputs))
                .max()
                .unwrap_or(0);
            let buffers = std::array::from_fn(|_| vec![0.0; widest]);
            Network {
                layers,
                output,
                bias,
                buffers,
            }
        }

        /// Value and slope of the network at `x` along `dx` (standardised units).
        #[target_feature(enable = "avx2,fma")]
        pub fn run(&mut self, x: &[f64], dx: &[f64]) -> (f64, f64) {
            let [a, b, da, db] = &mut self.buffers;
            let (mut x_in, mut y) = (a.as_mut_slice(), b.as_mut_slice());
            let (mut dx_in, mut dy) = (da.as_mut_slice(), db.as_mut_slice());
            x_in[..x.len()].copy_from_slice(x);
            dx_in[..dx.len()].copy_from_slice(dx);
            for layer in &self.layers {
                let n = layer.inputs;
                for (b, start) in (0..layer.padded).step_by(BLOCK).enumerate() {
                    let mut value: [f64; BLOCK] =
                        layer.biases[start..start + BLOCK].try_into().unwrap();
                    let mut tangent = [0.0; BLOCK];
                    let block = &layer.weights[b * BLOCK * n..(b + 1) * BLOCK * n];
                    for (i, column) in block.chunks_exact(BLOCK).enumerate() {
                        let (xi, dxi) = (x_in[i], dx_in[i]);
                        for l in 0..BLOCK {
                            value[l] = column[l].mul_add(xi, value[l]);
                            tangent[l] = column[l].mul_add(dxi, tangent[l]);
                        }
                    }
                    for l in 0..BLOCK {
                        let a = tanh(value[l]);
                        y[start + l] = a;
                        dy[start + l] = tangent[l] * (1.0 - a * a);
                    }
                }
                std::mem::swap(&mut x_in, &mut y);
                std::mem::swap(&mut dx_in, &mut dy);
            }
            let output = &self.output;
            let dot = |v: &[f64]| {
                let mut partial = [0.0; 8];
                let (w8, v8) = (output.chunks_exact(8), v.chunks_exact(8));
                let mut tail = 0.0;
                for (w, v) in w8.remainder().iter().zip(v8.remainder()) {
                    tail += w * v;
                }
                for (w, v) in w8.zip(v8) {
                    for k in 0..8 {
                        partial[k] = w[k].mul_add(v[k], partial[k]);
                    }
                }
                partial.iter().sum::<f64>() + tail
            };
            let n = output.len();
            (dot(&x_in[..n]) + self.bias, dot(&dx_in[..n]))
        }
    }
}

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
    let (last, hidden) = model.layers.split_last().unwrap();
    let rows: Vec<(Vec<Vec<f64>>, Vec<f64>)> = model
        .layers
        .iter()
        .map(|l| (l.weights.clone(), l.biases.clone()))
        .collect();
    let mut ours = Forward::<f64>::new(features, &rows, model.activation);
    let layers = hidden
        .iter()
        .map(|l| fused::Layer::new(&l.weights, &l.biases))
        .collect();
    let mut old = fused::Network::new(layers, last.weights[0].clone(), last.biases[0]);
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
    // SAFETY: AVX2 and FMA were detected above.
    let mut run_old = |x: &[f64]| unsafe { old.run(x, &tangent) };
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
                    total += stepping(&scene, Box::new(ExponentialLaw::of(&scene.friction))).0;
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
                    let law = PlatformExp(ExponentialLaw::of(&scene.friction));
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
