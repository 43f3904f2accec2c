//! The baseline of benches/reproducible.rs: the network's forward pass as it was before
//! issue 25 (src/physics/src/neural/forward.rs at ae5887c, its tests left out), whose
//! AVX2 build fuses every a b + c (FMA), so that its bits depend on the CPU. Kept only
//! here (f64 only), to measure what the fixed, unfused kernel costs against it in the
//! same run.
#![allow(dead_code)]

use std::fmt::Debug;
use std::ops::{Add, Div, Mul, MulAssign, Sub};

use stickslip::neural::Activation;

const VECTORS: usize = 5;

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
    const LANES: usize;
    const ZERO: Self;
    const ONE: Self;
    const HALF: Self;
    fn from_f64(x: f64) -> Self;
    fn to_f64(self) -> f64;
    fn multiply_add<const FUSED: bool>(a: Self, b: Self, c: Self) -> Self;
    fn tanh<const FUSED: bool>(self) -> Self;
    fn network<const FUSED: bool, const SLOPE: bool>(
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
    fn multiply_add<const FUSED: bool>(a: f64, b: f64, c: f64) -> f64 {
        if FUSED {
            a.mul_add(b, c)
        } else {
            a * b + c
        }
    }
    #[inline(always)]
    fn tanh<const FUSED: bool>(self) -> f64 {
        tanh::<FUSED>(self)
    }
    #[inline(always)]
    fn network<const FUSED: bool, const SLOPE: bool>(
        network: &Network<f64>,
        buffers: &mut Buffers<f64>,
    ) -> (f64, f64) {
        run_network::<f64, 4, FUSED, SLOPE>(network, buffers)
    }
}

#[derive(Clone, Debug)]
pub struct BlockedLayer<T> {
    inputs: usize,
    outputs: usize,
    padded: usize,
    weights: Vec<T>,
    biases: Vec<T>,
}

impl<T: Real> BlockedLayer<T> {
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

    pub fn padded_outputs(&self) -> usize {
        self.padded
    }
}

fn blocks(padded: usize, lanes: usize) -> impl Iterator<Item = (usize, usize)> {
    let block = VECTORS * lanes;
    let full = padded / block;
    let rest = padded - full * block;
    (0..full)
        .map(move |b| (b * block, block))
        .chain((rest > 0).then_some((full * block, rest)))
}

#[inline(always)]
fn block<T: Real, const L: usize, const V: usize, const FUSED: bool, const SLOPE: bool>(
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
                value[g][l] = T::multiply_add::<FUSED>(weights[l], xi, value[g][l]);
                if SLOPE {
                    tangent[g][l] = T::multiply_add::<FUSED>(weights[l], dxi, tangent[g][l]);
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

#[inline(always)]
fn activate<T: Real, const FUSED: bool, const SLOPE: bool>(
    activation: Activation,
    z: &mut [T],
    dz: &mut [T],
) {
    match activation {
        Activation::Tanh => {
            for (v, t) in z.iter_mut().zip(dz.iter_mut()) {
                let a = v.tanh::<FUSED>();
                *v = a;
                if SLOPE {
                    *t *= T::ONE - a * a;
                }
            }
        }
        Activation::Sigmoid => {
            for (v, t) in z.iter_mut().zip(dz.iter_mut()) {
                let s = T::HALF + T::HALF * (T::HALF * *v).tanh::<FUSED>();
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

#[inline(always)]
fn hidden<T: Real, const L: usize, const FUSED: bool, const SLOPE: bool>(
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
            1 => block::<T, L, 1, FUSED, SLOPE>(w, b, x, dx, z, dz),
            2 => block::<T, L, 2, FUSED, SLOPE>(w, b, x, dx, z, dz),
            3 => block::<T, L, 3, FUSED, SLOPE>(w, b, x, dx, z, dz),
            4 => block::<T, L, 4, FUSED, SLOPE>(w, b, x, dx, z, dz),
            _ => block::<T, L, VECTORS, FUSED, SLOPE>(w, b, x, dx, z, dz),
        }
        activate::<T, FUSED, SLOPE>(activation, z, dz);
        offset += width * n;
    }
}

#[inline(always)]
fn dot<T: Real, const FUSED: bool>(a: &[T], b: &[T]) -> T {
    let mut partial = [T::ZERO; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let mut tail = T::ZERO;
    for (x, y) in a8.remainder().iter().zip(b8.remainder()) {
        tail = tail + *x * *y;
    }
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            partial[k] = T::multiply_add::<FUSED>(x[k], y[k], partial[k]);
        }
    }
    let [p0, p1, p2, p3, p4, p5, p6, p7] = partial;
    ((p0 + p4) + (p1 + p5)) + ((p2 + p6) + (p3 + p7)) + tail
}

#[inline(always)]
fn run_network<T: Real, const L: usize, const FUSED: bool, const SLOPE: bool>(
    network: &Network<T>,
    buffers: &mut Buffers<T>,
) -> (T, T) {
    let Buffers { value, tangent } = buffers;
    let [x, y] = value;
    let [dx, dy] = tangent;
    let (mut x, mut y) = (x.as_mut_slice(), y.as_mut_slice());
    let (mut dx, mut dy) = (dx.as_mut_slice(), dy.as_mut_slice());
    for layer in &network.layers {
        hidden::<T, L, FUSED, SLOPE>(layer, network.activation, x, dx, y, dy);
        std::mem::swap(&mut x, &mut y);
        std::mem::swap(&mut dx, &mut dy);
    }
    let n = network.output.len();
    let z = dot::<T, FUSED>(&network.output, &x[..n]) + network.output_bias;
    let dz = if SLOPE {
        dot::<T, FUSED>(&network.output, &dx[..n])
    } else {
        T::ZERO
    };
    (z, dz)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn network_avx2_fma<T: Real, const SLOPE: bool>(
    network: &Network<T>,
    buffers: &mut Buffers<T>,
) -> (T, T) {
    T::network::<true, SLOPE>(network, buffers)
}

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

#[derive(Clone, Debug)]
pub struct Buffers<T> {
    value: [Vec<T>; 2],
    tangent: [Vec<T>; 2],
}

#[derive(Clone, Debug)]
pub struct Network<T> {
    layers: Vec<BlockedLayer<T>>,
    output: Vec<T>,
    output_bias: T,
    activation: Activation,
}

#[derive(Clone, Debug)]
pub struct Forward<T> {
    network: Network<T>,
    avx2_fma: bool,
    buffers: Buffers<T>,
}

impl<T: Real> Forward<T> {
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
            avx2_fma: cpu_has_avx2_fma(),
            buffers: Buffers {
                value: [buffer.clone(), buffer.clone()],
                tangent: [buffer.clone(), buffer],
            },
        }
    }

    pub fn inputs_mut(&mut self) -> (&mut [T], &mut [T]) {
        let Buffers { value, tangent } = &mut self.buffers;
        (&mut value[0], &mut tangent[0])
    }

    #[inline]
    pub fn run<const SLOPE: bool>(&mut self) -> (f64, f64) {
        let Forward {
            network,
            avx2_fma,
            buffers,
        } = self;
        #[cfg(target_arch = "x86_64")]
        if *avx2_fma {
            let (z, dz) = unsafe { network_avx2_fma::<T, SLOPE>(network, buffers) };
            return (z.to_f64(), dz.to_f64());
        }
        let _ = avx2_fma;
        let (z, dz) = T::network::<false, SLOPE>(network, buffers);
        (z.to_f64(), dz.to_f64())
    }
}

#[inline(always)]
pub fn tanh<const FUSED: bool>(z: f64) -> f64 {
    const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
    const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
    const LOG2_E: f64 = std::f64::consts::LOG2_E;
    const ROUND: f64 = 6_755_399_441_055_744.0;
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
    let fma = <f64 as Real>::multiply_add::<FUSED>;
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
    let r8 = r4 * r4;
    let pair = |k: usize| fma(C[k + 1], r, C[k]);
    let q0 = fma(pair(2), r2, pair(0));
    let q1 = fma(pair(6), r2, pair(4));
    let q2 = fma(pair(10), r2, pair(8));
    let q = fma(q2, r8, fma(q1, r4, q0));
    let expm1_r = fma(r2, q, r);
    let n_bits = shifted.to_bits().wrapping_sub(ROUND.to_bits());
    let scale = f64::from_bits(n_bits.wrapping_add(1023) << 52);
    let m = fma(scale, expm1_r, scale - 1.0);
    let t = m / (m + 2.0);
    t.copysign(z)
}
