//! Corrupted serialized FMU states are refused: every single-bit flip of every byte,
//! every truncation and appended bytes, for both FMUs in FMI 2.0 and 3.0. The checksum
//! (state version 5) catches them before anything is parsed; without it (the same
//! state written as version 4) the value checks alone catch fewer, which the test
//! prints for comparison.

use std::sync::{Arc, Mutex};
use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;
use stickslip::scene::FidelityLevel;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::instance::{FmiVersion, Instance, SavedState, STATE_VERSION};
use stickslip_fmi::model::Model;
use stickslip_tests::vr;

pub(crate) type Log = Arc<Mutex<Vec<String>>>;

/// An instance of `M` in `version` that logs into the returned list.
pub(crate) fn logged<M: Model>(version: FmiVersion) -> (Instance<M>, Log) {
    let log: Log = Arc::default();
    let sink = log.clone();
    let logger = Box::new(move |_, _: &str, message: &str| {
        sink.lock().unwrap().push(message.to_string());
    });
    let dir = stickslip_tests::weights_dir();
    let instance = Instance::instantiate(version, "probe", Some(&dir), false, logger).unwrap();
    (instance, log)
}

pub(crate) fn step<M: Model>(instance: &mut Instance<M>, version: FmiVersion, t: f64, h: f64) {
    match version {
        FmiVersion::V2 => instance.do_step(t, h).unwrap(),
        FmiVersion::V3 => {
            instance.do_step3(t, h).unwrap();
        }
    }
}

/// A modal StickSlipBeam with `law`, run in 10 ms steps to `to` (s).
pub(crate) fn beam_at(
    version: FmiVersion,
    law: FrictionLawKind,
    to: f64,
) -> (Instance<StickSlipBeam>, Log) {
    let (mut b, log) = logged::<StickSlipBeam>(version);
    b.setup_experiment(0.0, Some(1.2)).unwrap();
    b.set_integer(
        &[
            vr::<StickSlipBeam>("fidelity.level"),
            vr::<StickSlipBeam>("friction.law"),
        ],
        &[FidelityLevel::Modal.code(), law.code()],
    )
    .unwrap();
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    let h = 1e-2;
    let n = (to / h).round() as usize;
    for k in 0..n {
        step(&mut b, version, k as f64 * h, h);
    }
    (b, log)
}

/// NeuralFriction with `law` (and `weights`, if given), 30 steps of 1 ms sliding at
/// 20 mm/s.
pub(crate) fn friction_at(
    version: FmiVersion,
    law: NeuralFrictionLaw,
    weights: Option<&str>,
) -> (Instance<NeuralFriction>, Log) {
    let (mut f, log) = logged::<NeuralFriction>(version);
    f.set_integer(&[vr::<NeuralFriction>("law")], &[law.code()])
        .unwrap();
    if let Some(w) = weights {
        f.set_string(&[vr::<NeuralFriction>("weights")], &[w])
            .unwrap();
    }
    f.setup_experiment(0.0, None).unwrap();
    f.enter_initialization_mode().unwrap();
    f.exit_initialization_mode().unwrap();
    f.set_real(&[vr::<NeuralFriction>("sliding_velocity")], &[0.02])
        .unwrap();
    for k in 0..30 {
        step(&mut f, version, k as f64 * 1e-3, 1e-3);
    }
    (f, log)
}

/// How many of `variants` `instance` refuses to deserialize, and the first accepted.
fn refused<M: Model>(
    instance: &mut Instance<M>,
    variants: impl Iterator<Item = Vec<u8>>,
) -> (usize, usize, Option<Vec<u8>>) {
    let (mut refused, mut total, mut accepted) = (0, 0, None);
    for bytes in variants {
        total += 1;
        if instance.deserialize_state(&bytes).is_err() {
            refused += 1;
        } else if accepted.is_none() {
            accepted = Some(bytes);
        }
    }
    (refused, total, accepted)
}

fn bit_flips(bytes: &[u8]) -> impl Iterator<Item = Vec<u8>> + '_ {
    (0..bytes.len() * 8).map(move |k| {
        let mut flipped = bytes.to_vec();
        flipped[k / 8] ^= 1 << (k % 8);
        flipped
    })
}

fn truncations(bytes: &[u8]) -> impl Iterator<Item = Vec<u8>> + '_ {
    (0..bytes.len()).map(move |n| bytes[..n].to_vec())
}

fn appended(bytes: &[u8]) -> impl Iterator<Item = Vec<u8>> + '_ {
    let tails: [&[u8]; 6] = [b" ", b"\n", b"0", b"\x00", b"}", b"\ncrc32:00000000"];
    tails.into_iter().map(move |tail| [bytes, tail].concat())
}

/// Every corruption of `state` through `instance`: asserts that all are refused and
/// returns the table row. `legacy` is the same state written as version 4 (no checksum).
fn probe<M: Model>(instance: &mut Instance<M>, label: &str, state: &SavedState) -> String {
    let bytes = state.to_bytes();
    assert_eq!(state.version, STATE_VERSION);
    assert!(instance.deserialize_state(&bytes).is_ok(), "{label}");
    let mut row = format!("| {label} | {} |", bytes.len());
    for (kind, variants) in [
        ("bit flips", bit_flips(&bytes).collect::<Vec<_>>()),
        ("truncations", truncations(&bytes).collect()),
        ("appended", appended(&bytes).collect()),
    ] {
        let (refused, total, accepted) = refused(instance, variants.into_iter());
        assert_eq!(
            refused,
            total,
            "{label}: {kind}: accepted {:?}",
            accepted.map(|b| String::from_utf8_lossy(&b).into_owned())
        );
        row += &format!(" {refused} / {total} |");
    }
    // For comparison, not asserted: the same state without its checksum (version 4),
    // where a flip that keeps the JSON valid and its values legal is accepted.
    let legacy = SavedState {
        version: 4,
        ..state.clone()
    }
    .to_bytes();
    let (refused, total, _) = refused(instance, bit_flips(&legacy));
    row += &format!(" {refused} / {total} |");
    row
}

#[test]
fn every_single_bit_flip_truncation_and_appendix_of_a_state_is_refused() {
    let mut table = vec![
        "| state | bytes | bit flips refused | truncations refused | appended refused | bit flips refused without checksum (version 4) |".to_string(),
        "| --- | ---: | ---: | ---: | ---: | ---: |".to_string(),
    ];
    for (tag, version) in [("FMI 2.0", FmiVersion::V2), ("FMI 3.0", FmiVersion::V3)] {
        let (mut b, _) = beam_at(version, FrictionLawKind::Lugre, 0.45);
        let state = b.get_state().unwrap();
        table.push(probe(
            &mut b,
            &format!("StickSlipBeam, LuGre, modal, t = 0.45 s, {tag}"),
            &state,
        ));
        let (mut f, _) = friction_at(version, NeuralFrictionLaw::RATE_AND_STATE, None);
        let state = f.get_state().unwrap();
        table.push(probe(
            &mut f,
            &format!("NeuralFriction, rate-and-state, {tag}"),
            &state,
        ));
    }
    println!("{}", table.join("\n"));
}
