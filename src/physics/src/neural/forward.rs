//! The single-sample forward pass of the time-step loop: a network laid out for
//! vectorised matrix-vector products, a vectorisable tanh, the force's derivative by
//! forward mode in the same pass, and no allocation.
//!
//! # Layout
//! A hidden layer z = W x + b is computed as a sum of columns, z = b + sum_i W[:, i] x_i,
//! in blocks of [`BLOCK`] outputs: the block's partial sums stay in vector registers
//! (5 AVX2 registers of 4 doubles, 10 with the tangent z' = W x'), each weight is loaded
//! once (and used twice for the tangent), and the weights of a block are stored column
//! after column, so that they stream in order. A layer whose width is not a multiple of
//! [`BLOCK`] ends in blocks of [`LANES`] outputs, padded with zero weights. The output
//! layer (one unit) is a dot product with eight partial sums. The shipped networks'
//! 100 units make five blocks per layer.
//!
//! # Vector width
//! The code is plain Rust written for the auto-vectoriser; it is compiled twice: for the
//! x86_64 baseline (SSE2) and, behind run-time detection, for AVX2 + FMA (fused
//! multiply-adds, 4 doubles per register). No target feature is assumed at build time,
//! so the FMU loads on any x86_64.
//!
//! # tanh
//! [`tanh`]: tanh(|z|) = m / (m + 2) with m = expm1(2|z|), the sign copied from z.
//! expm1 by Cody-Waite reduction 2|z| = n ln2 + r, |r| <= ln2 / 2, and a degree-13
//! Taylor polynomial in r (truncation below 1e-17 relative):
//! expm1(2|z|) = 2^n expm1(r) + (2^n - 1), with no cancellation since n >= 0. The
//! polynomial goes by Estrin's scheme (depth 4 instead of Horner's 11). Branch-free (the
//! clamp of 2|z| to 40, where tanh rounds to 1, is a select), so a loop of it
//! vectorises. Relative error against libm's tanh: at most 2 ulp over 17 000 points from
//! 1e-300 to 24, fused or not (3 asserted), where the trainer's 1 - 2 / (exp(2z) + 1) is
//! within 1e-16 absolute but loses the relative accuracy near 0. 300 of them take about
//! a third of the time of 300 with libm's exp.

use super::network::Activation;

/// Outputs per block of a hidden layer: 5 vectors of [`LANES`].
pub const BLOCK: usize = 20;
/// Doubles per AVX2 register; the granularity of the padding.
pub const LANES: usize = 4;

/// One layer, its weights in blocks of outputs (see the module notes).
#[derive(Clone, Debug)]
pub struct BlockedLayer {
    inputs: usize,
    /// Outputs of the layer (unpadded).
    outputs: usize,
    /// Outputs rounded up to a multiple of [`LANES`].
    padded: usize,
    /// Per block of width w starting at output o: w x inputs weights, column i at
    /// [i w, (i + 1) w), W[o + j, i] at i w + j; blocks one after the other.
    weights: Vec<f64>,
    /// Biases, padded with zeros.
    biases: Vec<f64>,
}

impl BlockedLayer {
    /// The layer with row-major weights `rows[o][i]` (outputs x inputs) and `biases`.
    pub fn new(rows: &[Vec<f64>], biases: &[f64]) -> BlockedLayer {
        let outputs = rows.len();
        let inputs = rows.first().map_or(0, Vec::len);
        let padded = outputs.div_ceil(LANES) * LANES;
        let mut weights = Vec::with_capacity(padded * inputs);
        for (start, width) in blocks(padded) {
            for i in 0..inputs {
                for o in start..start + width {
                    weights.push(rows.get(o).map_or(0.0, |row| row[i]));
                }
            }
        }
        let mut padded_biases = biases.to_vec();
        padded_biases.resize(padded, 0.0);
        BlockedLayer {
            inputs,
            outputs,
            padded,
            weights,
            biases: padded_biases,
        }
    }

    pub fn inputs(&self) -> usize {
        self.inputs
    }

    pub fn outputs(&self) -> usize {
        self.outputs
    }

    /// Outputs rounded up to a multiple of [`LANES`]: the room its output buffer needs.
    pub fn padded_outputs(&self) -> usize {
        self.padded
    }
}

/// The blocks (start, width) of `padded` outputs: of [`BLOCK`], then of [`LANES`].
fn blocks(padded: usize) -> impl Iterator<Item = (usize, usize)> {
    let full = padded / BLOCK;
    (0..full)
        .map(|b| (b * BLOCK, BLOCK))
        .chain((full * BLOCK..padded).step_by(LANES).map(|s| (s, LANES)))
}

/// a b + c, fused (one rounding) where the CPU has FMA and this code is compiled for it.
#[inline(always)]
fn multiply_add<const FUSED: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FUSED {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// z (and with `SLOPE` the tangent z' = W x') of one block of `V` x [`LANES`] outputs,
/// from the block's weights `w` (column after column) and biases `b`. The partial sums
/// are `V` groups of [`LANES`], one vector register each.
#[inline(always)]
fn block<const V: usize, const FUSED: bool, const SLOPE: bool>(
    w: &[f64],
    b: &[f64],
    x: &[f64],
    dx: &[f64],
    z: &mut [f64],
    dz: &mut [f64],
) {
    let mut value = [[0.0; LANES]; V];
    for (group, bias) in value.iter_mut().zip(b.chunks_exact(LANES)) {
        group.copy_from_slice(bias);
    }
    let mut tangent = [[0.0; LANES]; V];
    for (i, column) in w.chunks_exact(V * LANES).enumerate() {
        let xi = x[i];
        let dxi = if SLOPE { dx[i] } else { 0.0 };
        for (g, weights) in column.chunks_exact(LANES).enumerate() {
            for l in 0..LANES {
                value[g][l] = multiply_add::<FUSED>(weights[l], xi, value[g][l]);
                if SLOPE {
                    tangent[g][l] = multiply_add::<FUSED>(weights[l], dxi, tangent[g][l]);
                }
            }
        }
    }
    for (g, group) in value.iter().enumerate() {
        z[g * LANES..(g + 1) * LANES].copy_from_slice(group);
    }
    if SLOPE {
        for (g, group) in tangent.iter().enumerate() {
            dz[g * LANES..(g + 1) * LANES].copy_from_slice(group);
        }
    }
}

/// a = phi(z) of a hidden layer, in place, and with `SLOPE` a' = phi'(z) z'.
#[inline(always)]
fn activate<const FUSED: bool, const SLOPE: bool>(
    activation: Activation,
    z: &mut [f64],
    dz: &mut [f64],
) {
    match activation {
        Activation::Tanh => {
            for (v, t) in z.iter_mut().zip(dz.iter_mut()) {
                let a = tanh::<FUSED>(*v);
                *v = a;
                if SLOPE {
                    *t *= 1.0 - a * a;
                }
            }
        }
        Activation::Sigmoid => {
            // sigma(z) = (1 + tanh(z / 2)) / 2, sigma' = sigma (1 - sigma).
            for (v, t) in z.iter_mut().zip(dz.iter_mut()) {
                let s = 0.5 + 0.5 * tanh::<FUSED>(0.5 * *v);
                *v = s;
                if SLOPE {
                    *t *= s * (1.0 - s);
                }
            }
        }
        Activation::Relu => {
            for (v, t) in z.iter_mut().zip(dz.iter_mut()) {
                let positive = *v > 0.0;
                *v = if positive { *v } else { 0.0 };
                if SLOPE && !positive {
                    *t = 0.0;
                }
            }
        }
    }
}

/// Hidden layer: y = phi(W x + b) and with `SLOPE` y' = phi'(W x + b) W x'. `x`, `dx`
/// hold at least `layer.inputs()` values, `y`, `dy` room for `layer.padded_outputs()`
/// (the padding gets phi(0)).
#[inline(always)]
fn hidden<const FUSED: bool, const SLOPE: bool>(
    layer: &BlockedLayer,
    activation: Activation,
    x: &[f64],
    dx: &[f64],
    y: &mut [f64],
    dy: &mut [f64],
) {
    let n = layer.inputs;
    let (x, dx) = (&x[..n], &dx[..n]);
    let mut offset = 0;
    for (start, width) in blocks(layer.padded) {
        let w = &layer.weights[offset..offset + width * n];
        let b = &layer.biases[start..start + width];
        let (z, dz) = (&mut y[start..start + width], &mut dy[start..start + width]);
        if width == BLOCK {
            block::<{ BLOCK / LANES }, FUSED, SLOPE>(w, b, x, dx, z, dz);
        } else {
            block::<1, FUSED, SLOPE>(w, b, x, dx, z, dz);
        }
        // Right away, while the next block's weights stream in: the activation's
        // arithmetic overlaps the loads (measured: 10 % faster than after the layer).
        activate::<FUSED, SLOPE>(activation, z, dz);
        offset += width * n;
    }
}

/// Dot product with eight independent partial sums (a single running sum would chain
/// every addition; eight keep several vector additions in flight).
#[inline(always)]
fn dot<const FUSED: bool>(a: &[f64], b: &[f64]) -> f64 {
    let mut partial = [0.0; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f64 = a8
        .remainder()
        .iter()
        .zip(b8.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            partial[k] = multiply_add::<FUSED>(x[k], y[k], partial[k]);
        }
    }
    let [p0, p1, p2, p3, p4, p5, p6, p7] = partial;
    ((p0 + p4) + (p1 + p5)) + ((p2 + p6) + (p3 + p7)) + tail
}

/// The network's standardised output z and with `SLOPE` its tangent z', from the
/// standardised inputs in `buffers.value[0]` and their tangents in `buffers.tangent[0]`.
#[inline(always)]
fn network<const FUSED: bool, const SLOPE: bool>(
    layers: &[BlockedLayer],
    output: &[f64],
    output_bias: f64,
    activation: Activation,
    buffers: &mut Buffers,
) -> (f64, f64) {
    let Buffers { value, tangent } = buffers;
    let [x, y] = value;
    let [dx, dy] = tangent;
    let (mut x, mut y) = (x.as_mut_slice(), y.as_mut_slice());
    let (mut dx, mut dy) = (dx.as_mut_slice(), dy.as_mut_slice());
    for layer in layers {
        hidden::<FUSED, SLOPE>(layer, activation, x, dx, y, dy);
        std::mem::swap(&mut x, &mut y);
        std::mem::swap(&mut dx, &mut dy);
    }
    let n = output.len();
    let z = dot::<FUSED>(output, &x[..n]) + output_bias;
    let dz = if SLOPE {
        dot::<FUSED>(output, &dx[..n])
    } else {
        0.0
    };
    (z, dz)
}

/// `network` for AVX2 + FMA. Called only after run-time detection.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn network_avx2_fma<const SLOPE: bool>(
    layers: &[BlockedLayer],
    output: &[f64],
    output_bias: f64,
    activation: Activation,
    buffers: &mut Buffers,
) -> (f64, f64) {
    network::<true, SLOPE>(layers, output, output_bias, activation, buffers)
}

/// Whether this CPU runs the AVX2 + FMA build of the forward pass.
fn cpu_has_avx2_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Two value and two tangent buffers, each as wide as the widest padded layer.
#[derive(Clone, Debug)]
pub struct Buffers {
    value: [Vec<f64>; 2],
    tangent: [Vec<f64>; 2],
}

/// A network in the layout of the time-step loop, with its scratch buffers.
#[derive(Clone, Debug)]
pub struct Forward {
    /// Hidden layers.
    layers: Vec<BlockedLayer>,
    /// Output layer: one unit's weights and bias.
    output: Vec<f64>,
    output_bias: f64,
    activation: Activation,
    avx2_fma: bool,
    buffers: Buffers,
}

impl Forward {
    /// Runs the x86_64-baseline build even where AVX2 + FMA is there (to test it).
    #[cfg(test)]
    fn baseline_only(mut self) -> Forward {
        self.avx2_fma = false;
        self
    }

    /// From the row-major layers (`weights[o][i]`, biases) of a network with one
    /// output; `inputs` features.
    pub fn new(
        inputs: usize,
        layers: &[(Vec<Vec<f64>>, Vec<f64>)],
        activation: Activation,
    ) -> Forward {
        let (last, hidden) = layers.split_last().expect("a network has an output layer");
        let hidden: Vec<BlockedLayer> = hidden
            .iter()
            .map(|(rows, biases)| BlockedLayer::new(rows, biases))
            .collect();
        let widest = hidden
            .iter()
            .map(BlockedLayer::padded_outputs)
            .chain([inputs])
            .max()
            .unwrap_or(inputs);
        let buffer = vec![0.0; widest];
        Forward {
            layers: hidden,
            output: last.0[0].clone(),
            output_bias: last.1[0],
            activation,
            avx2_fma: cpu_has_avx2_fma(),
            buffers: Buffers {
                value: [buffer.clone(), buffer.clone()],
                tangent: [buffer.clone(), buffer],
            },
        }
    }

    /// The input buffers to fill before [`Forward::run`]: the standardised inputs and,
    /// for the slope, their derivatives.
    pub fn inputs_mut(&mut self) -> (&mut [f64], &mut [f64]) {
        let Buffers { value, tangent } = &mut self.buffers;
        (&mut value[0], &mut tangent[0])
    }

    /// The standardised output z and with `SLOPE` its derivative along the input
    /// tangent (0 without).
    #[inline]
    pub fn run<const SLOPE: bool>(&mut self) -> (f64, f64) {
        let Forward {
            layers,
            output,
            output_bias,
            activation,
            avx2_fma,
            buffers,
        } = self;
        #[cfg(target_arch = "x86_64")]
        if *avx2_fma {
            // SAFETY: avx2_fma is true only if the running CPU has AVX2 and FMA
            // (is_x86_feature_detected at construction), the features this function is
            // compiled for. It has no other safety requirement.
            return unsafe {
                network_avx2_fma::<SLOPE>(layers, output, *output_bias, *activation, buffers)
            };
        }
        let _ = avx2_fma;
        network::<false, SLOPE>(layers, output, *output_bias, *activation, buffers)
    }
}

/// tanh(z), vectorisable (see the module notes): within 2 ulp of libm's tanh, exactly
/// +-1 for |z| >= 20, odd (tanh(-0) = -0), NaN for NaN. With `FUSED` (compiled for FMA)
/// the products and sums are fused.
#[inline(always)]
pub fn tanh<const FUSED: bool>(z: f64) -> f64 {
    // fdlibm's split of ln 2 = LN2_HI + LN2_LO: LN2_HI (0.693147180369...) has 32
    // trailing zero bits, so n LN2_HI is exact for the n here.
    const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
    const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
    const LOG2_E: f64 = std::f64::consts::LOG2_E;
    // 1.5 2^52: adding it rounds to an integer, which lands in the low mantissa bits.
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
    let fma = multiply_add::<FUSED>;
    let magnitude = z.abs();
    // 2|z| <= 40, where tanh = 1 - 2 / (e^40 + 1) already rounds to 1. The comparison
    // is false for NaN, which goes on as NaN.
    let x = if 2.0 * magnitude > 40.0 {
        40.0
    } else {
        2.0 * magnitude
    };
    let shifted = fma(x, LOG2_E, ROUND);
    let n = shifted - ROUND;
    let r = fma(-n, LN2_LO, fma(-n, LN2_HI, x));
    // expm1(r) = r + r^2 q(r), q = sum_k C[k] r^k, by Estrin's scheme (depth 4 instead
    // of Horner's 11).
    let r2 = r * r;
    let r4 = r2 * r2;
    let r8 = r4 * r4;
    let pair = |k: usize| fma(C[k + 1], r, C[k]);
    let q0 = fma(pair(2), r2, pair(0));
    let q1 = fma(pair(6), r2, pair(4));
    let q2 = fma(pair(10), r2, pair(8));
    let q = fma(q2, r8, fma(q1, r4, q0));
    let expm1_r = fma(r2, q, r);
    // 2^n from the integer in `shifted`'s low bits (0 <= n <= 58).
    let n_bits = shifted.to_bits().wrapping_sub(ROUND.to_bits());
    let scale = f64::from_bits(n_bits.wrapping_add(1023) << 52);
    let m = fma(scale, expm1_r, scale - 1.0);
    let t = m / (m + 2.0);
    t.copysign(z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place between two doubles of the same sign.
    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    #[test]
    fn tanh_is_within_three_ulp_of_libm() {
        let mut worst = 0;
        // Dense near 0 (relative accuracy), over the range a network meets, and past
        // saturation.
        let points = (-2000..=2000)
            .map(|i| i as f64 * 1e-3)
            .chain((1..=400).map(|i| 1e-300 * 1.5f64.powi(i)))
            .chain((0..=4000).map(|i| i as f64 * 0.0061));
        for z in points {
            for z in [z, -z] {
                // Fused or not (mul_add is correctly rounded either way, in hardware on
                // the AVX2 + FMA path).
                for fast in [tanh::<false>(z), tanh::<true>(z)] {
                    let exact = z.tanh();
                    let distance = ulps(fast, exact);
                    assert!(
                        distance <= 3,
                        "tanh({z}): {fast} vs {exact}, {distance} ulp"
                    );
                    worst = worst.max(distance);
                }
            }
        }
        println!("worst distance from libm's tanh: {worst} ulp");
        assert!(
            worst >= 1,
            "a formula this different from libm's differs somewhere"
        );
        assert_eq!(tanh::<false>(20.0), 1.0);
        assert_eq!(tanh::<false>(-1e300), -1.0);
        assert_eq!(tanh::<false>(0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(tanh::<false>(-0.0).to_bits(), (-0.0f64).to_bits());
        assert!(tanh::<false>(f64::NAN).is_nan());
    }

    /// The baseline (SSE2, unfused) and the AVX2 + FMA builds of a 2-100-100-100-1 tanh
    /// network agree to rounding: the fused products change the last bits only.
    #[test]
    fn both_builds_agree() {
        let weight =
            |l: usize, o: usize, i: usize| ((l * 31 + o * 7 + i * 3) % 13) as f64 * 0.02 - 0.12;
        let sizes = [2, 100, 100, 100, 1];
        let layers: Vec<(Vec<Vec<f64>>, Vec<f64>)> = sizes
            .windows(2)
            .enumerate()
            .map(|(l, pair)| {
                let rows = (0..pair[1])
                    .map(|o| (0..pair[0]).map(|i| weight(l, o, i)).collect())
                    .collect();
                (rows, (0..pair[1]).map(|o| 0.01 * o as f64 - 0.3).collect())
            })
            .collect();
        let mut detected = Forward::new(2, &layers, Activation::Tanh);
        let mut baseline = Forward::new(2, &layers, Activation::Tanh).baseline_only();
        for (v, f) in [(0.3, -1.2), (-2.0, 0.5), (0.0, 0.0)] {
            let run = |forward: &mut Forward| {
                let (inputs, tangents) = forward.inputs_mut();
                inputs[..2].copy_from_slice(&[v, f]);
                tangents[..2].copy_from_slice(&[1.0, 0.0]);
                forward.run::<true>()
            };
            let (a, b) = (run(&mut detected), run(&mut baseline));
            assert!(
                (a.0 - b.0).abs() <= 1e-12 * (1.0 + a.0.abs()),
                "{a:?} {b:?}"
            );
            assert!(
                (a.1 - b.1).abs() <= 1e-12 * (1.0 + a.1.abs()),
                "{a:?} {b:?}"
            );
        }
    }

    /// The blocked layer computes W x + b for widths that are and are not multiples of
    /// the block, against the plain row sums.
    #[test]
    fn blocked_layers_compute_the_affine_map() {
        for (inputs, outputs) in [(2, 100), (3, 7), (100, 20), (5, 41), (1, 1)] {
            let rows: Vec<Vec<f64>> = (0..outputs)
                .map(|o| {
                    (0..inputs)
                        .map(|i| ((o * 7 + i * 3) % 11) as f64 * 0.1 - 0.5)
                        .collect()
                })
                .collect();
            let biases: Vec<f64> = (0..outputs).map(|o| o as f64 * 0.01).collect();
            let layer = BlockedLayer::new(&rows, &biases);
            let x: Vec<f64> = (0..inputs).map(|i| (i as f64).sin()).collect();
            let dx: Vec<f64> = (0..inputs).map(|i| (i as f64).cos()).collect();
            let mut y = vec![f64::NAN; layer.padded_outputs()];
            let mut dy = vec![f64::NAN; layer.padded_outputs()];
            hidden::<false, true>(&layer, Activation::Relu, &x, &dx, &mut y, &mut dy);
            for o in 0..outputs {
                let z: f64 = biases[o] + rows[o].iter().zip(&x).map(|(w, x)| w * x).sum::<f64>();
                let dz: f64 = rows[o].iter().zip(&dx).map(|(w, x)| w * x).sum();
                assert!(
                    (y[o] - z.max(0.0)).abs() < 1e-13,
                    "{inputs} x {outputs}, {o}"
                );
                let expected = if z > 0.0 { dz } else { 0.0 };
                assert!(
                    (dy[o] - expected).abs() < 1e-13,
                    "{inputs} x {outputs}, {o}"
                );
            }
            assert!(y[outputs..].iter().all(|v| *v == 0.0));
        }
    }
}
