//! FMI 3.0 Float64 requests beyond scalars, through the C interface: NeuralFriction's
//! array variable `extra_feature` (value reference 16, four elements) and the
//! independent variable `time` (value reference 0).
//!
//! The array's values must reach a network that reads them: with a network of six
//! features (velocity, normal force and four more that every first-layer unit reads),
//! setting the array through fmi3SetFloat64 gives every output bit for bit what FMI 2.0
//! gives with the same four values set through the scalars `extra_feature[1..4]`, and
//! other values give other outputs.

use super::ffi3::{do_step3, instantiate_logging, Messages};
use std::ffi::CString;
use stickslip::choice::Choice;
use stickslip_fmi::ffi3::*;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::friction::{NeuralFriction, EXTRA_FEATURE_ARRAY};
use stickslip_fmi::instance::Instance;
use stickslip_fmi::model_description::TIME_VALUE_REFERENCE;
use stickslip_fmi::FmuKind;
use stickslip_tests::six_feature_weights;
use stickslip_tests::vr;

const OK: fmi3Status = 0;
const ERROR: fmi3Status = 3;

/// An FMI 3.0 instance of `kind` with logging on (resources: the workspace's `weights/`).
fn instantiate(kind: FmuKind, name: &str, messages: &Messages) -> fmi3Instance {
    let instance = unsafe { instantiate_logging(kind, name, messages, true, false, false) };
    assert!(!instance.is_null());
    instance
}

fn get(c: fmi3Instance, vrs: &[u32], n_values: usize) -> (fmi3Status, Vec<f64>) {
    let mut out = vec![f64::NAN; n_values];
    let status = unsafe { fmi3GetFloat64(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), n_values) };
    (status, out)
}

fn set(c: fmi3Instance, vrs: &[u32], values: &[f64]) -> fmi3Status {
    unsafe { fmi3SetFloat64(c, vrs.as_ptr(), vrs.len(), values.as_ptr(), values.len()) }
}

fn enter_initialization(c: fmi3Instance, start: f64) {
    assert_eq!(
        unsafe { fmi3EnterInitializationMode(c, 0, 0.0, start, 0, 0.0) },
        OK
    );
}

fn last_message(messages: &Messages) -> String {
    messages
        .lock()
        .unwrap()
        .last()
        .map(|(_, m)| m.clone())
        .unwrap_or_default()
}

/// The outputs that a law's inputs reach (force, magnitude, coefficient, slope).
fn law_outputs() -> [u32; 4] {
    [
        vr::<NeuralFriction>("friction_force"),
        vr::<NeuralFriction>("friction_force_magnitude"),
        vr::<NeuralFriction>("friction_coefficient"),
        vr::<NeuralFriction>("friction_force_slope"),
    ]
}

const FEATURES: [f64; 4] = [0.3, -0.6, 0.8, -0.1];
const VELOCITY: f64 = 0.05;
const NORMAL_FORCE: f64 = 100.0;

/// NeuralFriction through FMI 3.0 with the six-feature network, in Step Mode with
/// the extra features set through the array (in one mixed request with the velocity
/// and the normal force: 1 + 4 + 1 values).
fn friction3(weights: &str, features: [f64; 4], messages: &Messages) -> fmi3Instance {
    let c = instantiate(FmuKind::NeuralFriction, "array", messages);
    let weights = CString::new(weights).unwrap();
    let weights_ptr = weights.as_ptr();
    unsafe {
        assert_eq!(
            fmi3SetString(c, &vr::<NeuralFriction>("weights"), 1, &weights_ptr, 1),
            OK
        );
        assert_eq!(
            fmi3SetInt32(
                c,
                &vr::<NeuralFriction>("law"),
                1,
                &NeuralFrictionLaw::NEURAL.code(),
                1
            ),
            OK
        );
    }
    enter_initialization(c, 0.0);
    assert_eq!(unsafe { fmi3ExitInitializationMode(c) }, OK);
    let vrs = [
        vr::<NeuralFriction>("sliding_velocity"),
        EXTRA_FEATURE_ARRAY,
        vr::<NeuralFriction>("normal_force"),
    ];
    let mut values = vec![VELOCITY];
    values.extend(features);
    values.push(NORMAL_FORCE);
    assert_eq!(set(c, &vrs, &values), OK, "{}", last_message(messages));
    c
}

/// The same through the FMI 2.0 table: the four scalars.
fn friction2_outputs(weights: &str, features: [f64; 4]) -> Vec<f64> {
    let mut fmu: Instance<NeuralFriction> = Instance::new(
        "scalars",
        Some(&stickslip_tests::weights_dir()),
        false,
        Box::new(|_, _, _| {}),
    )
    .unwrap();
    fmu.set_string(&[vr::<NeuralFriction>("weights")], &[weights])
        .unwrap();
    fmu.set_integer(
        &[vr::<NeuralFriction>("law")],
        &[NeuralFrictionLaw::NEURAL.code()],
    )
    .unwrap();
    fmu.setup_experiment(0.0, None).unwrap();
    fmu.enter_initialization_mode().unwrap();
    fmu.exit_initialization_mode().unwrap();
    let scalars: Vec<u32> = (1..=4)
        .map(|k| vr::<NeuralFriction>(&format!("extra_feature[{k}]")))
        .collect();
    fmu.set_real(&scalars, &features).unwrap();
    fmu.set_real(
        &[
            vr::<NeuralFriction>("sliding_velocity"),
            vr::<NeuralFriction>("normal_force"),
        ],
        &[VELOCITY, NORMAL_FORCE],
    )
    .unwrap();
    let mut out = vec![0.0; 4];
    fmu.get_real(&law_outputs(), &mut out).unwrap();
    out
}

#[test]
fn the_array_reaches_the_network_as_the_fmi2_scalars_do() {
    let weights = six_feature_weights("values3");
    let weights = weights.to_str().unwrap().to_string();
    let messages = Messages::default();
    let c = friction3(&weights, FEATURES, &messages);
    let (status, three) = get(c, &law_outputs(), 4);
    assert_eq!(status, OK, "{}", last_message(&messages));
    let two = friction2_outputs(&weights, FEATURES);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits(&three),
        bits(&two),
        "FMI 3.0 array {three:?} vs FMI 2.0 scalars {two:?}"
    );
    // The features matter: other values (all inside the trained range [-1, 1]) move the
    // force, so equal outputs above are not equal by indifference.
    let zeros = friction2_outputs(&weights, [0.0; 4]);
    println!(
        "friction_force: {} N with the features {FEATURES:?} (FMI 3.0 array = FMI 2.0 scalars), {} N with zeros",
        three[0], zeros[0]
    );
    assert!(
        (three[0] - zeros[0]).abs() > 1e-3 * zeros[0].abs(),
        "force with features {} N, without {} N",
        three[0],
        zeros[0]
    );
    // The array reads back in element order, alone and in a mixed request.
    assert_eq!(get(c, &[EXTRA_FEATURE_ARRAY], 4), (OK, FEATURES.to_vec()));
    let velocity = vr::<NeuralFriction>("sliding_velocity");
    let (status, mixed) = get(c, &[velocity, EXTRA_FEATURE_ARRAY], 5);
    assert_eq!(status, OK);
    assert_eq!(mixed, [&[VELOCITY][..], &FEATURES[..]].concat());
    unsafe { fmi3FreeInstance(c) };
    let _ = std::fs::remove_file(&weights);
}

#[test]
fn a_wrong_number_of_values_or_an_element_reference_is_refused_with_the_reason() {
    let messages = Messages::default();
    let velocity = vr::<NeuralFriction>("sliding_velocity");
    // Per request, the expected text of the reason. Each refusal puts the instance in
    // the Error state, so each gets a fresh instance.
    let cases: [(&[u32], usize, &str); 4] = [
        (&[EXTRA_FEATURE_ARRAY], 1, "nValues = 1"),
        (&[EXTRA_FEATURE_ARRAY, velocity], 4, "stand for 5 values"),
        (&[velocity], 2, "nValues = 2"),
        (
            &[13],
            1,
            "element 2 of the array extra_feature (value reference 16",
        ),
    ];
    for (vrs, n, reason) in cases {
        for setting in [false, true] {
            let c = instantiate(FmuKind::NeuralFriction, "refused", &messages);
            enter_initialization(c, 0.0);
            let status = if setting {
                set(c, vrs, &vec![0.1; n])
            } else {
                get(c, vrs, n).0
            };
            assert_eq!(status, ERROR, "{vrs:?} with nValues = {n}");
            let message = last_message(&messages);
            let call = if setting {
                "fmi3SetFloat64"
            } else {
                "fmi3GetFloat64"
            };
            assert!(
                message.contains(reason) && message.starts_with(call),
                "{vrs:?}, {n}: {message}"
            );
            unsafe { fmi3FreeInstance(c) };
        }
    }
}

#[test]
fn time_reads_as_the_instances_clock_and_cannot_be_set() {
    let messages = Messages::default();
    let c = instantiate(FmuKind::StickSlipBeam, "time", &messages);
    let start = 0.25;
    enter_initialization(c, start);
    assert_eq!(get(c, &[TIME_VALUE_REFERENCE], 1), (OK, vec![start]));
    assert_eq!(unsafe { fmi3ExitInitializationMode(c) }, OK);
    let h = 1e-3;
    let mut t = start;
    for _ in 0..3 {
        let (status, _, _, last) = unsafe { do_step3(c, t, h) };
        assert_eq!(status, OK);
        t = last;
        // The time, with an output in the same request.
        let deflection = vr::<stickslip_fmi::beam::StickSlipBeam>("tip_deflection");
        let (status, values) = get(c, &[TIME_VALUE_REFERENCE, deflection], 2);
        assert_eq!(status, OK);
        assert_eq!(values[0], last, "time after the step to {last} s");
        assert!(values[1].is_finite());
    }
    assert_eq!(set(c, &[TIME_VALUE_REFERENCE], &[0.0]), ERROR);
    let message = last_message(&messages);
    assert!(
        message.starts_with("fmi3SetFloat64") && message.contains("independent variable"),
        "{message}"
    );
    unsafe { fmi3FreeInstance(c) };
}
