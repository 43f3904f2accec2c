//! NeuralFriction's directional derivatives through both C interfaces, as an importer
//! calls them: the Jacobian of every output with respect to every input against central
//! differences of the outputs read with fmi2GetReal / fmi3GetFloat64, at random points
//! of the training domain, for the shipped plain and signed networks, a network that
//! reads all four extra features, and the exponential law; the clamp (derivative 0
//! outside the domain); and the declared dependencies. The refusals are in
//! `directional_errors`.
//!
//! # Tolerance
//! D_h = (y(x + h) - y(x - h)) / 2h differs from y' by the truncation h^2 y'''/6 +
//! O(h^4) and by the rounding of the two outputs, 2 r / 2h for an output error r.
//! h = 1e-4 standard deviations of the input (the network's standardised unit).
//! Truncation: D_2h - D_h = 3 h^2 y'''/6 + O(h^4), so |D_2h - D_h| bounds three times the
//! truncation of D_h where y is smooth over the stencil (a stencil on which the force
//! changes sign or is 0 crosses the jump at v = 0, the kink of |F| or the signed cut,
//! and is skipped). Rounding: r <= 1000 eps Y, Y = max(|y| over the stencil, 1), far
//! above what a 3 x 100 network's sums lose. Asserted: |exact - D_h| <= |D_2h - D_h| +
//! 1000 eps Y / h, output by output.

use std::ffi::{c_void, CString};
use stickslip::choice::Choice;
use stickslip::friction::LawChoice;
use stickslip::neural::NeuralModel;
use stickslip_fmi::ffi2::*;
use stickslip_fmi::ffi3::*;
use stickslip_fmi::friction::{NeuralFriction, EXTRA_FEATURE_ARRAY};
use stickslip_fmi::model::Model;
use stickslip_fmi::variables::Causality;
use stickslip_fmi::FmuKind;
use stickslip_tests::fmi_log::{record, Log};

use crate::ffi3::{instantiate_logging, Messages};

pub(crate) const OK: i32 = 0;
pub(crate) const ERROR: i32 = 3;
/// sliding_velocity, normal_force, extra_feature[1..4] (FMI 2.0 value references).
pub(crate) const INPUTS: [u32; 6] = [10, 11, 12, 13, 14, 15];

/// NeuralFriction's outputs (all Real).
pub(crate) fn outputs() -> Vec<u32> {
    NeuralFriction::variables()
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .map(|v| v.value_reference)
        .collect()
}

/// An initialised NeuralFriction instance of either FMI version, with its log.
pub(crate) enum Fmu {
    V2(
        fmi2Component,
        Box<Log>,
        // Only kept alive: FMI 2.0 lets the FMU keep the pointer to the callbacks.
        #[allow(dead_code)] Box<fmi2CallbackFunctions>,
    ),
    V3(fmi3Instance, Box<Messages>),
}

impl Fmu {
    /// Instantiated (weights and law set), and initialised unless `initialise` is false.
    pub(crate) unsafe fn new(three: bool, weights: &str, law: LawChoice, initialise: bool) -> Fmu {
        let weights = CString::new(weights).unwrap();
        let (weights_vr, law_vr) = ([5u32], [1u32]);
        unsafe {
            if three {
                let messages = Box::new(Messages::default());
                let c = instantiate_logging(
                    FmuKind::NeuralFriction,
                    "d3",
                    &messages,
                    false,
                    false,
                    false,
                );
                assert!(!c.is_null());
                assert_eq!(
                    fmi3SetString(c, weights_vr.as_ptr(), 1, &weights.as_ptr(), 1),
                    OK
                );
                assert_eq!(fmi3SetInt32(c, law_vr.as_ptr(), 1, &law.code(), 1), OK);
                if initialise {
                    assert_eq!(
                        fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
                        OK
                    );
                    assert_eq!(fmi3ExitInitializationMode(c), OK);
                }
                Fmu::V3(c, messages)
            } else {
                let log = Box::new(Log::default());
                type Fixed = extern "C" fn(
                    *mut c_void,
                    fmi2String,
                    fmi2Status,
                    fmi2String,
                    fmi2String,
                    *const std::ffi::c_char,
                );
                // SAFETY: see `stickslip_tests::fmi_log::record`.
                let logger = std::mem::transmute::<Fixed, fmi2CallbackLogger>(record);
                let functions = Box::new(fmi2CallbackFunctions {
                    logger: Some(logger),
                    allocateMemory: None,
                    freeMemory: None,
                    stepFinished: None,
                    componentEnvironment: &*log as *const Log as *mut c_void,
                });
                let name = CString::new("d2").unwrap();
                let guid = CString::new(FmuKind::NeuralFriction.guid()).unwrap();
                let uri = CString::new(format!(
                    "file://{}",
                    stickslip_tests::weights_dir().display()
                ))
                .unwrap();
                let c = fmi2Instantiate(
                    name.as_ptr(),
                    1,
                    guid.as_ptr(),
                    uri.as_ptr(),
                    &*functions,
                    0,
                    0,
                );
                assert!(!c.is_null());
                assert_eq!(
                    fmi2SetString(c, weights_vr.as_ptr(), 1, &weights.as_ptr()),
                    OK
                );
                assert_eq!(fmi2SetInteger(c, law_vr.as_ptr(), 1, &law.code()), OK);
                if initialise {
                    assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
                    assert_eq!(fmi2EnterInitializationMode(c), OK);
                    assert_eq!(fmi2ExitInitializationMode(c), OK);
                }
                Fmu::V2(c, log, functions)
            }
        }
    }

    /// Sets the six inputs (FMI 3.0: the extra features as the array).
    pub(crate) unsafe fn set(&self, inputs: &[f64; 6]) {
        unsafe {
            match self {
                Fmu::V2(c, ..) => {
                    assert_eq!(fmi2SetReal(*c, INPUTS.as_ptr(), 6, inputs.as_ptr()), OK)
                }
                Fmu::V3(c, _) => {
                    let vrs = [10, 11, EXTRA_FEATURE_ARRAY];
                    assert_eq!(fmi3SetFloat64(*c, vrs.as_ptr(), 3, inputs.as_ptr(), 6), OK)
                }
            }
        }
    }

    pub(crate) unsafe fn outputs(&self) -> Vec<f64> {
        let vrs = outputs();
        let mut y = vec![0.0; vrs.len()];
        unsafe {
            let status = match self {
                Fmu::V2(c, ..) => fmi2GetReal(*c, vrs.as_ptr(), vrs.len(), y.as_mut_ptr()),
                Fmu::V3(c, _) => {
                    fmi3GetFloat64(*c, vrs.as_ptr(), vrs.len(), y.as_mut_ptr(), y.len())
                }
            };
            assert_eq!(status, OK);
        }
        y
    }

    /// The raw call: (status, sensitivities). FMI 3.0 value references as given.
    pub(crate) unsafe fn derivative(
        &self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
    ) -> (i32, Vec<f64>) {
        unsafe {
            match self {
                Fmu::V2(c, ..) => {
                    let mut out = vec![f64::NAN; unknowns.len()];
                    let status = fmi2GetDirectionalDerivative(
                        *c,
                        unknowns.as_ptr(),
                        unknowns.len(),
                        knowns.as_ptr(),
                        knowns.len(),
                        seed.as_ptr(),
                        out.as_mut_ptr(),
                    );
                    (status, out)
                }
                Fmu::V3(c, _) => {
                    let mut out = vec![f64::NAN; unknowns.len()];
                    let status = fmi3GetDirectionalDerivative(
                        *c,
                        unknowns.as_ptr(),
                        unknowns.len(),
                        knowns.as_ptr(),
                        knowns.len(),
                        seed.as_ptr(),
                        seed.len(),
                        out.as_mut_ptr(),
                        out.len(),
                    );
                    (status, out)
                }
            }
        }
    }

    /// Column j of the Jacobian (every output along input j): FMI 2.0 seeds the input
    /// itself, FMI 3.0 an extra feature through the array with a unit seed element.
    pub(crate) unsafe fn column(&self, j: usize) -> Vec<f64> {
        let unknowns = outputs();
        let (knowns, seed): (Vec<u32>, Vec<f64>) = match self {
            Fmu::V3(..) if j >= 2 => (
                vec![EXTRA_FEATURE_ARRAY],
                (0..4).map(|e| (e + 2 == j) as u8 as f64).collect(),
            ),
            _ => (vec![INPUTS[j]], vec![1.0]),
        };
        let (status, column) = unsafe { self.derivative(&unknowns, &knowns, &seed) };
        assert_eq!(status, OK, "{:?}", self.log());
        column
    }

    /// The messages logged so far.
    pub(crate) fn log(&self) -> Vec<String> {
        match self {
            Fmu::V2(_, log, _) => log
                .lock()
                .unwrap()
                .iter()
                .map(|e| e.message.clone())
                .collect(),
            Fmu::V3(_, messages) => messages
                .lock()
                .unwrap()
                .iter()
                .map(|(_, m)| m.clone())
                .collect(),
        }
    }

    pub(crate) fn logged(&self, needle: &str) -> bool {
        self.log().iter().any(|m| m.contains(needle))
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        unsafe {
            match self {
                Fmu::V2(c, ..) => fmi2FreeInstance(*c),
                Fmu::V3(c, _) => fmi3FreeInstance(*c),
            }
        }
    }
}

/// xorshift64*: reproducible uniform numbers in [0, 1).
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Per input: the sampling range and the standardised unit (from the network; the
/// exponential law uses the shipped plain network's domain), unused inputs (0, 0, 1).
fn domain(model: &NeuralModel, inputs: usize) -> Vec<(f64, f64, f64)> {
    (0..6)
        .map(|j| match model.features.get(j).filter(|_| j < inputs) {
            Some(f) => (f.min, f.max, f.input_std),
            None => (0.0, 0.0, 1.0),
        })
        .collect()
}

/// Checks the Jacobian against central differences at `samples` random points;
/// returns how many derivatives were compared and the largest error / tolerance.
unsafe fn check(
    fmu: &Fmu,
    model: &NeuralModel,
    inputs: usize,
    samples: usize,
    seed: u64,
) -> (usize, f64) {
    let box_ = domain(model, inputs);
    let mut uniform = Uniform(seed);
    let (mut compared, mut worst) = (0, 0.0f64);
    for _ in 0..samples {
        let mut x = [0.0; 6];
        for (j, (lo, hi, std)) in box_.iter().enumerate() {
            let margin = 3e-4 * std;
            x[j] = if hi > lo {
                lo + margin + (hi - lo - 2.0 * margin) * uniform.next()
            } else {
                0.0
            };
        }
        unsafe { fmu.set(&x) };
        let columns: Vec<Vec<f64>> = (0..inputs).map(|j| unsafe { fmu.column(j) }).collect();
        for j in 0..inputs {
            let h = 1e-4 * box_[j].2;
            let stencil: Vec<Vec<f64>> = [-2.0, -1.0, 1.0, 2.0]
                .iter()
                .map(|t| {
                    let mut p = x;
                    p[j] += t * h;
                    unsafe {
                        fmu.set(&p);
                        fmu.outputs()
                    }
                })
                .collect();
            unsafe { fmu.set(&x) };
            let force_signs: Vec<f64> = stencil
                .iter()
                .map(|y| y[0].signum() * (y[0] != 0.0) as u8 as f64)
                .collect();
            if force_signs
                .iter()
                .any(|s| *s != force_signs[0] || *s == 0.0)
            {
                continue;
            }
            for (o, exact) in columns[j].iter().enumerate() {
                let scale = stencil.iter().map(|y| y[o].abs()).fold(1.0, f64::max);
                let d_h = (stencil[2][o] - stencil[1][o]) / (2.0 * h);
                let d_2h = (stencil[3][o] - stencil[0][o]) / (4.0 * h);
                let tolerance = (d_2h - d_h).abs() + 1000.0 * f64::EPSILON * scale / h;
                let error = (exact - d_h).abs();
                assert!(
                    error <= tolerance,
                    "output {} along input {} at {x:?}: exact {exact}, central {d_h} (2h {d_2h}), tolerance {tolerance}",
                    outputs()[o],
                    INPUTS[j]
                );
                worst = worst.max(error / tolerance);
                compared += 1;
            }
        }
    }
    (compared, worst)
}

fn shipped(name: &str) -> NeuralModel {
    NeuralModel::load(&stickslip_tests::weights_dir().join(name)).unwrap()
}

#[test]
fn shipped_networks_match_central_differences_in_both_versions() {
    for (weights, seed) in [("paper-plain.json", 5), ("paper-signed.json", 9)] {
        let model = shipped(weights);
        for three in [false, true] {
            let fmu = unsafe { Fmu::new(three, weights, LawChoice::Neural, true) };
            let (compared, worst) = unsafe { check(&fmu, &model, 2, 100, seed) };
            println!(
                "{weights} FMI {}: {compared} derivatives, worst error / tolerance {worst:.3}",
                if three { "3.0" } else { "2.0" }
            );
            // 6 outputs x 2 inputs at most points (a few stencils cross v = 0).
            assert!(compared > 1000, "{compared}");
        }
    }
}

#[test]
fn every_extra_feature_and_the_exponential_law_match_central_differences() {
    let path = stickslip_tests::six_feature_weights("directional");
    let model = NeuralModel::load(&path).unwrap();
    for three in [false, true] {
        let fmu = unsafe { Fmu::new(three, path.to_str().unwrap(), LawChoice::Neural, true) };
        let (compared, _) = unsafe { check(&fmu, &model, 6, 30, 13) };
        assert!(compared > 900, "{compared}");
        let fmu = unsafe { Fmu::new(three, "paper-plain.json", LawChoice::Exponential, true) };
        let (compared, _) = unsafe { check(&fmu, &shipped("paper-plain.json"), 2, 30, 17) };
        assert!(compared > 300, "{compared}");
    }
    std::fs::remove_file(path).ok();
}

/// Both versions give the same numbers, and an FMI 3.0 seed over several knowns (a
/// scalar and the array) is the matching combination of the columns (linearity).
#[test]
fn both_versions_agree_and_seeds_combine_linearly() {
    let path = stickslip_tests::six_feature_weights("directional-linear");
    let weights = path.to_str().unwrap();
    let (two, three) = unsafe {
        (
            Fmu::new(false, weights, LawChoice::Neural, true),
            Fmu::new(true, weights, LawChoice::Neural, true),
        )
    };
    let x = [0.07, 101.0, 0.3, -0.2, 0.5, 0.1];
    unsafe {
        two.set(&x);
        three.set(&x);
        for (j, input) in INPUTS.iter().enumerate() {
            assert_eq!(two.column(j), three.column(j), "input {input}");
        }
        let seed = [0.5, 2.0, -1.0, 0.25, 3.0];
        let (status, combined) = three.derivative(&outputs(), &[10, EXTRA_FEATURE_ARRAY], &seed);
        assert_eq!(status, OK);
        let columns: Vec<Vec<f64>> = [0, 2, 3, 4, 5].iter().map(|&j| two.column(j)).collect();
        for (o, value) in combined.iter().enumerate() {
            let expected: f64 = columns.iter().zip(seed).map(|(c, s)| c[o] * s).sum();
            assert!(
                (value - expected).abs() <= 1e-12 * (1.0 + expected.abs()),
                "{value} {expected}"
            );
        }
    }
    std::fs::remove_file(path).ok();
}

/// Outside the training domain the clamped input has derivative 0; what does not go
/// through the network keeps its own derivative (the coefficient's -|F| / F_n^2, the
/// static limit's mu_s). Every non-zero derivative is a declared dependency.
#[test]
fn clamped_inputs_and_declared_dependencies() {
    let model = shipped("paper-plain.json");
    let fmu = unsafe { Fmu::new(false, "paper-plain.json", LawChoice::Neural, true) };
    let column = |x: [f64; 6], j: usize| unsafe {
        fmu.set(&x);
        fmu.column(j)
    };
    let fast = column([model.features[0].max + 1.0, 100.0, 0.0, 0.0, 0.0, 0.0], 0);
    assert_eq!(
        (fast[0], fast[4]),
        (0.0, 0.0),
        "force and slope along v beyond the domain"
    );
    let heavy = column([0.1, model.features[1].max + 50.0, 0.0, 0.0, 0.0, 0.0], 1);
    let y = unsafe { fmu.outputs() };
    assert_eq!(heavy[0], 0.0, "force along F_n beyond the domain");
    let normal = model.features[1].max + 50.0;
    assert!((heavy[2] + y[0].abs() / (normal * normal)).abs() < 1e-15);
    assert_eq!(heavy[3], 0.5, "static limit: mu_s");
    let path = stickslip_tests::six_feature_weights("directional-deps");
    let all = unsafe { Fmu::new(false, path.to_str().unwrap(), LawChoice::Neural, true) };
    unsafe { all.set(&[0.05, 99.0, 0.1, 0.2, -0.3, 0.4]) };
    for (j, &input) in INPUTS.iter().enumerate() {
        let column = unsafe { all.column(j) };
        for (variable, d) in NeuralFriction::variables()
            .iter()
            .filter(|v| v.causality == Causality::Output)
            .zip(column)
        {
            let declared = variable
                .depends_on
                .as_ref()
                .unwrap()
                .inputs
                .iter()
                .any(|(i, _)| *i == input);
            assert!(
                declared || d == 0.0,
                "{} along {input}: {d}, not declared",
                variable.name
            );
        }
    }
    std::fs::remove_file(path).ok();
}
