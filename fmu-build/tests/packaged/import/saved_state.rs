//! b. FMU state: get, set, serialize, deserialize into a fresh instance.

use super::*;

// b. FMU state: get, set, serialize, deserialize into a fresh instance.

/// Steps from 0.5 s to 0.8 s.
const STATE_AT: usize = 500;
const STATE_RUN: usize = 300;

#[test]
fn b_fmu_state_restores_bit_for_bit_also_in_a_fresh_instance() {
    let import1 = import(FmuKind::StickSlipBeam);
    let vrs = BeamVrs::of(&import1);
    let mut first = Beam::start(
        &import1,
        "state-first",
        &[(vrs.fidelity, FidelityLevel::Beam.code())],
    );
    first.run(STATE_AT);
    let t_saved = first.t;
    let at_saved = first.outputs();
    let state = first.inst.get_fmu_state().expect("fmi2GetFMUstate");
    let bytes = first
        .inst
        .serialize_fmu_state(&state)
        .expect("fmi2SerializeFMUstate");

    let run1 = first.run(STATE_RUN);
    // The interval holds real dynamics (a stick -> slip -> stick cycle), so a state
    // that lost anything would show.
    assert!(
        run1[STATE_RUN - 1].transitions > at_saved.transitions,
        "no transition between 0.5 and 0.8 s"
    );

    first
        .inst
        .set_fmu_state(&state)
        .ok()
        .expect("fmi2SetFMUstate");
    first.t = t_saved;
    assert_bitwise(
        "outputs right after fmi2SetFMUstate",
        &[first.outputs()],
        &[at_saved],
    );
    let run2 = first.run(STATE_RUN);
    assert_bitwise("re-run after fmi2SetFMUstate", &run1, &run2);

    // A fresh instance from a separate import (its own copy of the library), left at the
    // default fidelity (plane stress): the state carries the parameters, so restoring
    // rebuilds the beam model.
    let import2 = import(FmuKind::StickSlipBeam);
    let mut fresh = Beam::start(&import2, "state-fresh", &[]);
    assert_eq!(
        fresh.integer(vrs.fidelity),
        FidelityLevel::PlaneStress.code()
    );
    let restored = fresh
        .inst
        .deserialize_fmu_state(&bytes)
        .expect("fmi2DeSerializeFMUstate");
    fresh
        .inst
        .set_fmu_state(&restored)
        .ok()
        .expect("fmi2SetFMUstate of the deserialized state");
    assert_eq!(fresh.integer(vrs.fidelity), FidelityLevel::Beam.code());
    fresh.t = t_saved;
    assert_bitwise(
        "fresh instance at the restored point",
        &[fresh.outputs()],
        &[at_saved],
    );
    let run3 = fresh.run(STATE_RUN);
    assert_bitwise(
        "fresh instance (plane-stress before restore) vs first",
        &run1,
        &run3,
    );

    // A fresh instance already at the saved fidelity (the model is reused, not rebuilt).
    let mut same = Beam::start(
        &import2,
        "state-same",
        &[(vrs.fidelity, FidelityLevel::Beam.code())],
    );
    let restored = same
        .inst
        .deserialize_fmu_state(&bytes)
        .expect("fmi2DeSerializeFMUstate");
    same.inst
        .set_fmu_state(&restored)
        .ok()
        .expect("fmi2SetFMUstate");
    same.t = t_saved;
    let run4 = same.run(STATE_RUN);
    assert_bitwise(
        "fresh instance (beam before restore) vs first",
        &run1,
        &run4,
    );

    // And all of it is the library's own run.
    let (direct, _) = direct_advance_to(Some(FidelityLevel::Beam));
    assert_bitwise(
        "FMU state runs vs library",
        &run1,
        &direct[STATE_AT + 1..=STATE_AT + STATE_RUN],
    );
    println!(
        "state: {} bytes; 300 points bitwise equal in 4 runs (re-run, fresh plane-stress instance, fresh beam instance, library)",
        bytes.len()
    );
}
