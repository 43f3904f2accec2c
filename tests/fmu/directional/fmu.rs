//! NeuralFriction through either C interface, initialised, with its log: the importer
//! side of the directional-derivative tests.

use std::ffi::{c_void, CString};
use stickslip::choice::Choice;
use stickslip_fmi::ffi2::*;
use stickslip_fmi::ffi3::*;
use stickslip_fmi::friction::NeuralFrictionLaw;
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
    pub(crate) unsafe fn new(
        three: bool,
        weights: &str,
        law: NeuralFrictionLaw,
        initialise: bool,
    ) -> Fmu {
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
                    assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 0, 0.0), OK);
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
