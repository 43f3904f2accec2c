//! The single-sample forward pass of the time-step loop: a network laid out for
//! vectorised matrix-vector products, a vectorisable tanh, the force's derivative by
//! forward mode in the same pass, and no allocation.
//!
//! # Layout
//! A hidden layer z = W x + b is computed as a sum of columns, z = b + sum_i W[:, i] x_i,
//! in blocks of [`VECTORS`] vector registers of outputs (20 doubles, 40 floats in
//! AVX2): the block's partial sums stay in registers (10 with the tangent z' = W x'),
//! each weight is loaded once (and used twice for the tangent), and the weights of a
//! block are stored column after column, so that they stream in order. A layer whose
//! width is not a multiple of the block ends in one narrower block, padded with zero
//! weights to whole vectors. The output layer (one unit) is a dot product with eight
//! partial sums. The shipped networks' 100 units make five blocks per layer in f64, two
//! and one of 24 in f32.
//!
//! # Vector width, precision and the same bits everywhere
//! The code is plain Rust written for the auto-vectoriser, generic over the precision
//! ([`Real`]: f64, and f32 for `Inference::F32`, 8 floats per AVX2 register, blocks of
//! 40). Every product and sum is a separate IEEE operation (a b + c, never fused) in a
//! fixed order: the lanes of a vector are independent outputs, and the only reduction,
//! [`dot`], adds its eight partial sums in a written-out tree. So the result is the same
//! bits at any vector width and on any CPU (issue 25). It is compiled twice: for the
//! x86_64 baseline (SSE2) and, behind run-time detection, for AVX2 (twice the width,
//! the same operations; FMA is deliberately not enabled, and Rust never contracts
//! a b + c by itself). `same_bits_from_both_builds` checks the two builds bit for bit.
//! No target feature is assumed at build time, so the FMU loads on any x86_64. What the
//! fused AVX2 + FMA build this replaces saved is measured in benches/neural_scene.rs
//! (docs/decisions.md, "The same bits on every CPU").
//!
//! # tanh
//! [`tanh`]: tanh(|z|) = m / (m + 2) with m = expm1(2|z|), the sign copied from z.
//! expm1 by Cody-Waite reduction 2|z| = n ln2 + r, |r| <= ln2 / 2, and a degree-13
//! Taylor polynomial in r (truncation below 1e-17 relative):
//! expm1(2|z|) = 2^n expm1(r) + (2^n - 1), with no cancellation since n >= 0. The
//! polynomial goes by Estrin's scheme (depth 4 instead of Horner's 11). Branch-free (the
//! clamp of 2|z| to 40, where tanh rounds to 1, is a select), so a loop of it
//! vectorises. Relative error against libm's tanh: at most 2 ulp over 17 000 points from
//! 1e-300 to 24 (3 asserted), where the trainer's 1 - 2 / (exp(2z) + 1) is
//! within 1e-16 absolute but loses the relative accuracy near 0. 300 of them take about
//! a third of the time of 300 with libm's exp.

use std::fmt::Debug;
use std::ops::{Add, Div, Mul, MulAssign, Sub};

use super::network::Activation;

/// Vector registers per block of a hidden layer's outputs: 5 (20 doubles or 40 floats
/// in AVX2; 10 registers with the tangent).
const VECTORS: usize = 5;

/// The precision of a forward pass: f64 (exact) or f32.
pub trait Real:
    Copy
    + Default
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + MulAssign
    + Div<Output = Self>
    + Send
    + Sync
    + 'static
{
    /// Values per AVX2 register: the padding of a layer's outputs.
    const LANES: usize;
    const ZERO: Self;
    const ONE: Self;
    const HALF: Self;
    fn from_f64(x: f64) -> Self;
    fn to_f64(self) -> f64;
    /// tanh in this precision (see [`tanh`], [`tanh_f32`]).
    fn tanh(self) -> Self;
    /// The whole forward pass, instantiated with this type's vector width.
    fn network<const SLOPE: bool>(
        network: &Network<Self>,
        buffers: &mut Buffers<Self>,
    ) -> (Self, Self);
}

impl Real for f64 {
    const LANES: usize = 4;
    const ZERO: f64 = 0.0;
    const ONE: f64 = 1.0;
    const HALF: f64 = 0.5;
    fn from_f64(x: f64) -> f64 {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn tanh(self) -> f64 {
        tanh(self)
    }
    #[inline(always)]
    fn network<const SLOPE: bool>(
        network: &Network<f64>,
        buffers: &mut Buffers<f64>,
    ) -> (f64, f64) {
        run_network::<f64, 4, SLOPE>(network, buffers)
    }
}

impl Real for f32 {
    const LANES: usize = 8;
    const ZERO: f32 = 0.0;
    const ONE: f32 = 1.0;
    const HALF: f32 = 0.5;
    fn from_f64(x: f64) -> f32 {
        x as f32
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    #[inline(always)]
    fn tanh(self) -> f32 {
        tanh_f32(self)
    }
    #[inline(always)]
    fn network<const SLOPE: bool>(
        network: &Network<f32>,
        buffers: &mut Buffers<f32>,
    ) -> (f32, f32) {
        run_network::<f32, 8, SLOPE>(network, buffers)
    }
}

/// One layer, its weights in blocks of outputs (see the module notes).
#[derive(Clone, Debug)]
pub struct BlockedLayer<T> {
    inputs: usize,
    /// Outputs of the layer (unpadded).
    outputs: usize,
    /// Outputs rounded up to a multiple of `T::LANES`.
    padded: usize,
    /// Per block of width w starting at output o: w x inputs weights, column i at
    /// [i w, (i + 1) w), W[o + j, i] at i w + j; blocks one after the other.
    weights: Vec<T>,
    /// Biases, padded with zeros.
    biases: Vec<T>,
}

impl<T: Real> BlockedLayer<T> {
    /// The layer with row-major weights `rows[o][i]` (outputs x inputs) and `biases`,
    /// rounded to `T`.
    pub fn new(rows: &[Vec<f64>], biases: &[f64]) -> BlockedLayer<T> {
        let outputs = rows.len();
        let inputs = rows.first().map_or(0, Vec::len);
        let padded = outputs.div_ceil(T::LANES) * T::LANES;
        let mut weights = Vec::with_capacity(padded * inputs);
        for (start, width) in blocks(padded, T::LANES) {
            for i in 0..inputs {
                for o in start..start + width {
                    weights.push(T::from_f64(rows.get(o).map_or(0.0, |row| row[i])));
                }
            }
        }
        let mut padded_biases: Vec<T> = biases.iter().map(|b| T::from_f64(*b)).collect();
        padded_biases.resize(padded, T::ZERO);
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

    /// Outputs rounded up to a multiple of `T::LANES`: the room its output buffer needs.
    pub fn padded_outputs(&self) -> usize {
        self.padded
    }
}

/// The blocks (start, width) of `padded` outputs: of [`VECTORS`] x `lanes`, then one of
/// the rest (fewer vectors: one block keeps several independent sums in flight where
/// blocks of one vector would each wait on a single chain of additions).
fn blocks(padded: usize, lanes: usize) -> impl Iterator<Item = (usize, usize)> {
    let block = VECTORS * lanes;
    let full = padded / block;
    let rest = padded - full * block;
    (0..full)
        .map(move |b| (b * block, block))
        .chain((rest > 0).then_some((full * block, rest)))
}

/// z (and with `SLOPE` the tangent z' = W x') of one block of `V` x `L` outputs, from
/// the block's weights `w` (column after column) and biases `b`. The partial sums are
/// `V` groups of `L`, one vector register each.
#[inline(always)]
fn block<T: Real, const L: usize, const V: usize, const SLOPE: bool>(
    w: &[T],
    b: &[T],
    x: &[T],
    dx: &[T],
    z: &mut [T],
    dz: &mut [T],
) {
    let mut value = [[T::ZERO; L]; V];
    for (group, bias) in value.iter_mut().zip(b.chunks_exact(L)) {
        group.copy_from_slice(bias);
    }
    let mut tangent = [[T::ZERO; L]; V];
    for (i, column) in w.chunks_exact(V * L).enumerate() {
        let xi = x[i];
        let dxi = if SLOPE { dx[i] } else { T::ZERO };
        for (g, weights) in column.chunks_exact(L).enumerate() {
            for l in 0..L {
                value[g][l] = weights[l] * xi + value[g][l];
                if SLOPE {
                    tangent[g][l] = weights[l] * dxi + tangent[g][l];
                }
            }
        }
    }
    for (g, group) in value.iter().enumerate() {
        z[g * L..(g + 1) * L].copy_from_slice(group);
    }
    if SLOPE {
        for (g, group) in tangent.iter().enumerate() {
            dz[g * L..(g + 1) * L].copy_from_slice(group);
        }
    }
}

/// a = phi(z) of a hidden layer, in place, and with `SLOPE` a' = phi'(z) z'.
#[inline(always)]
fn activate<T: Real, const SLOPE: bool>(activation: Activation, z: &mut [T], dz: &mut [T]) {
    match activation {
        Activation::Tanh => {
            for (v, t) in z.iter_mut().zip(dz.iter_mut()) {
                let a = v.tanh();
                *v = a;
                if SLOPE {
                    *t *= T::ONE - a * a;
                }
            }
        }
        Activation::Sigmoid => {
            // sigma(z) = (1 + tanh(z / 2)) / 2, sigma' = sigma (1 - sigma).
            for (v, t) in z.iter_mut().zip(dz.iter_mut()) {
                let s = T::HALF + T::HALF * (T::HALF * *v).tanh();
                *v = s;
                if SLOPE {
                    *t *= s * (T::ONE - s);
                }
            }
        }
        Activation::Relu => {
            for (v, t) in z.iter_mut().zip(dz.iter_mut()) {
                let positive = *v > T::ZERO;
                *v = if positive { *v } else { T::ZERO };
                if SLOPE && !positive {
                    *t = T::ZERO;
                }
            }
        }
    }
}

/// Hidden layer: y = phi(W x + b) and with `SLOPE` y' = phi'(W x + b) W x'. `x`, `dx`
/// hold at least `layer.inputs()` values, `y`, `dy` room for `layer.padded_outputs()`
/// (the padding gets phi(0)).
#[inline(always)]
fn hidden<T: Real, const L: usize, const SLOPE: bool>(
    layer: &BlockedLayer<T>,
    activation: Activation,
    x: &[T],
    dx: &[T],
    y: &mut [T],
    dy: &mut [T],
) {
    let n = layer.inputs;
    let (x, dx) = (&x[..n], &dx[..n]);
    let mut offset = 0;
    for (start, width) in blocks(layer.padded, L) {
        let w = &layer.weights[offset..offset + width * n];
        let b = &layer.biases[start..start + width];
        let (z, dz) = (&mut y[start..start + width], &mut dy[start..start + width]);
        match width / L {
            1 => block::<T, L, 1, SLOPE>(w, b, x, dx, z, dz),
            2 => block::<T, L, 2, SLOPE>(w, b, x, dx, z, dz),
            3 => block::<T, L, 3, SLOPE>(w, b, x, dx, z, dz),
            4 => block::<T, L, 4, SLOPE>(w, b, x, dx, z, dz),
            _ => block::<T, L, VECTORS, SLOPE>(w, b, x, dx, z, dz),
        }
        // Right away, while the next block's weights stream in: the activation's
        // arithmetic overlaps the loads (measured: 10 % faster than after the layer).
        activate::<T, SLOPE>(activation, z, dz);
        offset += width * n;
    }
}

/// Dot product with eight independent partial sums (a single running sum would chain
/// every addition; eight keep several vector additions in flight).
#[inline(always)]
fn dot<T: Real>(a: &[T], b: &[T]) -> T {
    let mut partial = [T::ZERO; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let mut tail = T::ZERO;
    for (x, y) in a8.remainder().iter().zip(b8.remainder()) {
        tail = tail + *x * *y;
    }
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            partial[k] = x[k] * y[k] + partial[k];
        }
    }
    let [p0, p1, p2, p3, p4, p5, p6, p7] = partial;
    ((p0 + p4) + (p1 + p5)) + ((p2 + p6) + (p3 + p7)) + tail
}

/// The network's standardised output z and with `SLOPE` its tangent z', from the
/// standardised inputs in `buffers.value[0]` and their tangents in `buffers.tangent[0]`.
#[inline(always)]
fn run_network<T: Real, const L: usize, const SLOPE: bool>(
    network: &Network<T>,
    buffers: &mut Buffers<T>,
) -> (T, T) {
    let Buffers { value, tangent } = buffers;
    let [x, y] = value;
    let [dx, dy] = tangent;
    let (mut x, mut y) = (x.as_mut_slice(), y.as_mut_slice());
    let (mut dx, mut dy) = (dx.as_mut_slice(), dy.as_mut_slice());
    for layer in &network.layers {
        hidden::<T, L, SLOPE>(layer, network.activation, x, dx, y, dy);
        std::mem::swap(&mut x, &mut y);
        std::mem::swap(&mut dx, &mut dy);
    }
    let n = network.output.len();
    let z = dot::<T>(&network.output, &x[..n]) + network.output_bias;
    let dz = if SLOPE {
        dot::<T>(&network.output, &dx[..n])
    } else {
        T::ZERO
    };
    (z, dz)
}

/// The forward pass compiled for AVX2 (not FMA: the same operations as the baseline
/// build, four doubles a register). Called only after run-time detection.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn network_avx2<T: Real, const SLOPE: bool>(
    network: &Network<T>,
    buffers: &mut Buffers<T>,
) -> (T, T) {
    T::network::<SLOPE>(network, buffers)
}

/// Whether this CPU runs the AVX2 build of the forward pass.
fn cpu_has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Two value and two tangent buffers, each as wide as the widest padded layer.
#[derive(Clone, Debug)]
pub struct Buffers<T> {
    value: [Vec<T>; 2],
    tangent: [Vec<T>; 2],
}

/// The layers of a network with one output, in the time-step loop's layout.
#[derive(Clone, Debug)]
pub struct Network<T> {
    /// Hidden layers.
    layers: Vec<BlockedLayer<T>>,
    /// Output layer: one unit's weights and bias.
    output: Vec<T>,
    output_bias: T,
    activation: Activation,
}

/// A network in the layout of the time-step loop, with its scratch buffers.
#[derive(Clone, Debug)]
pub struct Forward<T> {
    network: Network<T>,
    avx2: bool,
    buffers: Buffers<T>,
}

impl<T: Real> Forward<T> {
    /// Runs the x86_64-baseline build even where AVX2 is there (to test it).
    #[cfg(test)]
    fn baseline_only(mut self) -> Forward<T> {
        self.avx2 = false;
        self
    }

    /// From the row-major layers (`weights[o][i]`, biases) of a network with one
    /// output; `inputs` features. The weights are rounded to `T`.
    pub fn new(
        inputs: usize,
        layers: &[(Vec<Vec<f64>>, Vec<f64>)],
        activation: Activation,
    ) -> Forward<T> {
        let (last, hidden) = layers.split_last().expect("a network has an output layer");
        let hidden: Vec<BlockedLayer<T>> = hidden
            .iter()
            .map(|(rows, biases)| BlockedLayer::new(rows, biases))
            .collect();
        let widest = hidden
            .iter()
            .map(BlockedLayer::padded_outputs)
            .chain([inputs])
            .max()
            .unwrap_or(inputs);
        let buffer = vec![T::ZERO; widest];
        Forward {
            network: Network {
                layers: hidden,
                output: last.0[0].iter().map(|w| T::from_f64(*w)).collect(),
                output_bias: T::from_f64(last.1[0]),
                activation,
            },
            avx2: cpu_has_avx2(),
            buffers: Buffers {
                value: [buffer.clone(), buffer.clone()],
                tangent: [buffer.clone(), buffer],
            },
        }
    }

    /// The input buffers to fill before [`Forward::run`]: the standardised inputs and,
    /// for the slope, their derivatives.
    pub fn inputs_mut(&mut self) -> (&mut [T], &mut [T]) {
        let Buffers { value, tangent } = &mut self.buffers;
        (&mut value[0], &mut tangent[0])
    }

    /// The standardised output z and with `SLOPE` its derivative along the input
    /// tangent (0 without), in f64.
    #[inline]
    pub fn run<const SLOPE: bool>(&mut self) -> (f64, f64) {
        let Forward {
            network,
            avx2,
            buffers,
        } = self;
        #[cfg(target_arch = "x86_64")]
        if *avx2 {
            // SAFETY: avx2 is true only if the running CPU has AVX2
            // (is_x86_feature_detected at construction), the feature this function is
            // compiled for. It has no other safety requirement.
            let (z, dz) = unsafe { network_avx2::<T, SLOPE>(network, buffers) };
            return (z.to_f64(), dz.to_f64());
        }
        let _ = avx2;
        let (z, dz) = T::network::<SLOPE>(network, buffers);
        (z.to_f64(), dz.to_f64())
    }
}

/// tanh(z), vectorisable (see the module notes): within 2 ulp of libm's tanh, exactly
/// +-1 for |z| >= 20, odd (tanh(-0) = -0), NaN for NaN. Products and sums unfused, in
/// the written order: the same bits on every CPU.
#[inline(always)]
pub fn tanh(z: f64) -> f64 {
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
    let fma = |a: f64, b: f64, c: f64| a * b + c; // unfused, see above
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

/// tanh(z) in f32, the same construction as [`tanh`] with f32 constants: ln 2 split as
/// 0.693359375 (9 significant bits, so n LN2_HI is exact for n <= 58) plus the rest, and
/// a degree-7 Taylor polynomial for expm1(r) (truncation 1.3e-8 relative, below f32's
/// 6e-8). Within 3 ulp (f32) of tanh (tested).
#[inline(always)]
pub fn tanh_f32(z: f32) -> f32 {
    const LN2_HI: f32 = 0.693_359_4;
    const LN2_LO: f32 = -2.121_944_4e-4;
    const LOG2_E: f32 = std::f32::consts::LOG2_E;
    // 1.5 2^23: adding it rounds to an integer, which lands in the low mantissa bits.
    const ROUND: f32 = 12_582_912.0;
    // 1 / k! for k = 2..7.
    const C: [f32; 6] = [
        1.0 / 2.0,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        1.0 / 720.0,
        1.0 / 5_040.0,
    ];
    let fma = |a: f32, b: f32, c: f32| a * b + c; // unfused, see above
    let magnitude = z.abs();
    let x = if 2.0 * magnitude > 40.0 {
        40.0
    } else {
        2.0 * magnitude
    };
    let shifted = fma(x, LOG2_E, ROUND);
    let n = shifted - ROUND;
    let r = fma(-n, LN2_LO, fma(-n, LN2_HI, x));
    let r2 = r * r;
    let r4 = r2 * r2;
    let q = fma(
        fma(C[5], r, C[4]),
        r4,
        fma(fma(C[3], r, C[2]), r2, fma(C[1], r, C[0])),
    );
    let expm1_r = fma(r2, q, r);
    let n_bits = shifted.to_bits().wrapping_sub(ROUND.to_bits());
    let scale = f32::from_bits(n_bits.wrapping_add(127) << 23);
    let m = fma(scale, expm1_r, scale - 1.0);
    let t = m / (m + 2.0);
    t.copysign(z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elementary;

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
                let (fast, exact) = (tanh(z), elementary::tanh(z));
                let distance = ulps(fast, exact);
                assert!(
                    distance <= 3,
                    "tanh({z}): {fast} vs {exact}, {distance} ulp"
                );
                worst = worst.max(distance);
            }
        }
        println!("worst distance from libm's tanh: {worst} ulp");
        assert!(
            worst >= 1,
            "a formula this different from libm's differs somewhere"
        );
        assert_eq!(tanh(20.0), 1.0);
        assert_eq!(tanh(-1e300), -1.0);
        assert_eq!(tanh(0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(tanh(-0.0).to_bits(), (-0.0f64).to_bits());
        assert!(tanh(f64::NAN).is_nan());
    }

    /// A fixed pseudo-random sequence in [-1, 1) (xorshift64*), so that the test is the
    /// same on every run.
    fn uniform(state: &mut u64) -> f64 {
        *state ^= *state >> 12;
        *state ^= *state << 25;
        *state ^= *state >> 27;
        let bits = state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
        bits as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// A random network: `sizes` units per layer, weights in [-s, s) with s = 2 / sqrt(n)
    /// for n inputs (so the hidden units are neither all linear nor all saturated).
    fn random_layers(sizes: &[usize], state: &mut u64) -> Vec<(Vec<Vec<f64>>, Vec<f64>)> {
        sizes
            .windows(2)
            .map(|pair| {
                let scale = 2.0 / (pair[0] as f64).sqrt();
                let rows = (0..pair[1])
                    .map(|_| (0..pair[0]).map(|_| scale * uniform(state)).collect())
                    .collect();
                (rows, (0..pair[1]).map(|_| 0.5 * uniform(state)).collect())
            })
            .collect()
    }

    /// The baseline (SSE2) and the AVX2 builds give the same bits, value and slope, in
    /// f64 and f32, for random networks (widths that fill whole blocks and widths that
    /// do not) at random inputs far into saturation: no tolerance, since the claim is
    /// that the operations and their order do not depend on the vector width. On a CPU
    /// without AVX2 both are the baseline and the test says so.
    #[test]
    fn same_bits_from_both_builds() {
        fn compare<T: Real>(
            layers: &[(Vec<Vec<f64>>, Vec<f64>)],
            activation: Activation,
            state: &mut u64,
        ) {
            let inputs = layers[0].0[0].len();
            let mut detected = Forward::<T>::new(inputs, layers, activation);
            let mut baseline = Forward::<T>::new(inputs, layers, activation).baseline_only();
            for _ in 0..200 {
                let x: Vec<T> = (0..inputs)
                    .map(|_| T::from_f64(4.0 * uniform(state)))
                    .collect();
                let dx: Vec<T> = (0..inputs).map(|_| T::from_f64(uniform(state))).collect();
                let run = |forward: &mut Forward<T>| {
                    let (values, tangents) = forward.inputs_mut();
                    values[..inputs].copy_from_slice(&x);
                    tangents[..inputs].copy_from_slice(&dx);
                    (forward.run::<true>(), forward.run::<false>())
                };
                let (a, b) = (run(&mut detected), run(&mut baseline));
                let bits = |r: ((f64, f64), (f64, f64))| {
                    [r.0 .0.to_bits(), r.0 .1.to_bits(), r.1 .0.to_bits()]
                };
                assert_eq!(bits(a), bits(b), "{activation:?} {x:?}: {a:?} vs {b:?}");
            }
        }
        println!("this CPU runs the AVX2 build: {}", cpu_has_avx2());
        let mut state = 0x9e37_79b9_7f4a_7c15;
        for sizes in [&[2, 100, 100, 100, 1][..], &[6, 37, 41, 1], &[3, 8, 1]] {
            let layers = random_layers(sizes, &mut state);
            for activation in [Activation::Tanh, Activation::Sigmoid, Activation::Relu] {
                compare::<f64>(&layers, activation, &mut state);
                compare::<f32>(&layers, activation, &mut state);
            }
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
            let layer = BlockedLayer::<f64>::new(&rows, &biases);
            let x: Vec<f64> = (0..inputs).map(|i| elementary::sin(i as f64)).collect();
            let dx: Vec<f64> = (0..inputs).map(|i| elementary::cos(i as f64)).collect();
            let mut y = vec![f64::NAN; layer.padded_outputs()];
            let mut dy = vec![f64::NAN; layer.padded_outputs()];
            hidden::<f64, 4, true>(&layer, Activation::Relu, &x, &dx, &mut y, &mut dy);
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
