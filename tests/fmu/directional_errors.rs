//! Directional derivatives that must be refused, through both C interfaces: each gives
//! fmi2Error/fmi3Error with a logged reason, never a panic or a silent NaN, and the
//! instance recovers by reset. StickSlipBeam provides none.

use crate::directional::{outputs, Fmu, ERROR, OK};
use std::ptr::{null, null_mut};
use stickslip_fmi::ffi2::*;
use stickslip_fmi::ffi3::*;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::friction::EXTRA_FEATURE_ARRAY;
use stickslip_fmi::FmuKind;

/// (unknowns, knowns, seed, what the log must say).
type Request = (&'static [u32], &'static [u32], &'static [f64], &'static str);

/// Requests refused in both versions.
const BAD: [Request; 6] = [
    (&[10], &[10], &[1.0], "is not an output"),
    (&[20], &[20], &[1.0], "is not an input"),
    // static_coefficient: a parameter, not differentiated.
    (&[20], &[2], &[1.0], "is not an input"),
    (&[20], &[999], &[1.0], "999"),
    (&[999], &[10], &[1.0], "999"),
    (&[20], &[10], &[f64::NAN], "seeds must be finite"),
];

#[test]
fn wrong_references_and_seeds_are_refused_with_a_reason() {
    for three in [false, true] {
        for (unknowns, knowns, seed, reason) in BAD {
            let fmu =
                unsafe { Fmu::new(three, "paper-plain.json", NeuralFrictionLaw::NEURAL, true) };
            let (status, out) = unsafe { fmu.derivative(unknowns, knowns, seed) };
            assert_eq!(status, ERROR, "{unknowns:?} {knowns:?} {seed:?}");
            assert!(fmu.logged(reason), "{reason}: {:?}", fmu.log());
            assert!(out.iter().all(|v| v.is_nan()), "the buffer was written");
        }
    }
}

#[test]
fn before_initialisation_it_is_an_illegal_call_and_reset_recovers() {
    for three in [false, true] {
        let fmu = unsafe { Fmu::new(three, "paper-plain.json", NeuralFrictionLaw::NEURAL, false) };
        let (status, _) = unsafe { fmu.derivative(&[20], &[10], &[1.0]) };
        assert_eq!(status, ERROR);
        assert!(fmu.logged("illegal call sequence"), "{:?}", fmu.log());
        let reset = unsafe {
            match &fmu {
                Fmu::V2(c, ..) => fmi2Reset(*c),
                Fmu::V3(c, _) => fmi3Reset(*c),
            }
        };
        assert_eq!(reset, OK);
    }
}

#[test]
fn null_pointers_with_elements_are_refused_and_empty_requests_succeed() {
    let two = unsafe { Fmu::new(false, "paper-plain.json", NeuralFrictionLaw::NEURAL, true) };
    let Fmu::V2(c, ..) = &two else { unreachable!() };
    let mut d = 0.0;
    unsafe {
        assert_eq!(
            fmi2GetDirectionalDerivative(*c, null(), 0, null(), 0, null(), null_mut()),
            OK
        );
        assert_eq!(
            fmi2GetDirectionalDerivative(*c, [20].as_ptr(), 1, [10].as_ptr(), 1, null(), &mut d),
            ERROR
        );
        assert_eq!(
            fmi2GetDirectionalDerivative(*c, null(), 1, [10].as_ptr(), 1, &1.0, &mut d),
            ERROR
        );
        assert_eq!(
            fmi2GetDirectionalDerivative(*c, [20].as_ptr(), 1, [10].as_ptr(), 1, &1.0, null_mut()),
            ERROR
        );
    }
    assert!(two.logged("is NULL"));
    let three = unsafe { Fmu::new(true, "paper-plain.json", NeuralFrictionLaw::NEURAL, true) };
    let Fmu::V3(c, _) = &three else {
        unreachable!()
    };
    unsafe {
        assert_eq!(
            fmi3GetDirectionalDerivative(*c, null(), 0, null(), 0, null(), 0, null_mut(), 0),
            OK
        );
        assert_eq!(
            fmi3GetDirectionalDerivative(
                *c,
                [20].as_ptr(),
                1,
                [10].as_ptr(),
                1,
                null(),
                1,
                &mut d,
                1
            ),
            ERROR
        );
    }
    assert!(three.logged("is NULL"));
}

/// FMI 3.0's serialized buffers: nSeed and nSensitivity must count an array's elements;
/// an element's FMI 2.0 value reference and time are no knowns.
#[test]
fn fmi3_buffer_lengths_elements_and_time_are_checked() {
    let cases: [(&[u32], &[u32], usize, &str); 4] = [
        (&[20], &[EXTRA_FEATURE_ARRAY], 1, "nValues = 1"),
        (&[20], &[12], 1, "element 1 of the array extra_feature"),
        (&[20], &[0], 1, "time (value reference 0)"),
        (&[0], &[10], 1, "time (value reference 0)"),
    ];
    for (unknowns, knowns, n_seed, reason) in cases {
        let fmu = unsafe { Fmu::new(true, "paper-plain.json", NeuralFrictionLaw::NEURAL, true) };
        let seed = vec![1.0; n_seed];
        let (status, _) = unsafe { fmu.derivative(unknowns, knowns, &seed) };
        assert_eq!(status, ERROR, "{knowns:?}");
        assert!(fmu.logged(reason), "{reason}: {:?}", fmu.log());
    }
    // nSensitivity must match too.
    let fmu = unsafe { Fmu::new(true, "paper-plain.json", NeuralFrictionLaw::NEURAL, true) };
    let Fmu::V3(c, _) = &fmu else { unreachable!() };
    let mut out = [0.0; 2];
    let status = unsafe {
        fmi3GetDirectionalDerivative(
            *c,
            [20].as_ptr(),
            1,
            [10].as_ptr(),
            1,
            [1.0].as_ptr(),
            1,
            out.as_mut_ptr(),
            2,
        )
    };
    assert_eq!(status, ERROR);
    assert!(fmu.logged("nSensitivity"));
    // The six law outputs, the step-consistent pair, the three state outputs and the
    // table coupling's 22.
    assert_eq!(outputs().len(), 33);
}

/// StickSlipBeam declares no directional derivatives: both versions answer Error and
/// name the flag, in every mode (here initialised).
#[test]
fn the_beam_refuses_with_its_flag() {
    let messages = crate::ffi3::Messages::default();
    unsafe {
        let c = crate::ffi3::instantiate_logging(
            FmuKind::StickSlipBeam,
            "b",
            &messages,
            false,
            false,
            false,
        );
        assert!(!c.is_null());
        let mut d = 0.0;
        let status = fmi3GetDirectionalDerivative(
            c,
            [20].as_ptr(),
            1,
            [10].as_ptr(),
            1,
            [1.0].as_ptr(),
            1,
            &mut d,
            1,
        );
        assert_eq!(status, ERROR);
        fmi3FreeInstance(c);
    }
    assert!(messages
        .lock()
        .unwrap()
        .iter()
        .any(|(_, m)| m.contains("providesDirectionalDerivatives is false")));
}

/// Arbitrary requests (value references 0 to 29, lengths 0 to 3, seeds among 1, -0.5,
/// NaN, infinity) through both interfaces, each on an initialised instance: every
/// answer is OK with finite sensitivities or Error with a logged reason; no panic
/// (which would also answer Error, so the log is checked not to say "panic").
#[test]
fn arbitrary_requests_answer_ok_or_error_with_a_reason() {
    let seeds = [1.0, -0.5, f64::NAN, f64::INFINITY];
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = |n: u64| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 33) % n
    };
    let (mut answered, mut refused) = (0, 0);
    for three in [false, true] {
        for _ in 0..150 {
            let unknowns: Vec<u32> = (0..next(4)).map(|_| next(30) as u32).collect();
            let knowns: Vec<u32> = (0..next(4)).map(|_| next(30) as u32).collect();
            let seed: Vec<f64> = (0..knowns.len() + next(2) as usize * three as usize)
                .map(|_| seeds[next(4) as usize])
                .collect();
            let fmu =
                unsafe { Fmu::new(three, "paper-signed.json", NeuralFrictionLaw::NEURAL, true) };
            let (status, out) = unsafe { fmu.derivative(&unknowns, &knowns, &seed) };
            let log = fmu.log();
            assert!(!log.iter().any(|m| m.contains("panic")), "{log:?}");
            match status {
                OK => {
                    let finite = out.iter().all(|v| v.is_finite());
                    assert!(finite, "{unknowns:?} {knowns:?} {seed:?}: {out:?}");
                    answered += 1;
                }
                ERROR => {
                    assert!(!log.is_empty(), "{unknowns:?} {knowns:?}: no reason");
                    refused += 1;
                }
                other => panic!("status {other}"),
            }
        }
    }
    println!("{answered} answered, {refused} refused");
    assert!(
        answered >= 10 && refused >= 100,
        "{answered} answered, {refused} refused"
    );
}
