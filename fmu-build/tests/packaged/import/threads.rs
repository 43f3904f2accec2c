//! d. Instances in parallel threads give the outputs of one instance alone.

use super::*;

// d. Instances in parallel threads.

fn run_alone(import: &Fmi2Import, name: &str, level: FidelityLevel) -> Vec<Outputs> {
    let vrs = BeamVrs::of(import);
    let mut beam = Beam::start(import, name, &[(vrs.fidelity, level.code())]);
    beam.run_from_start(STEPS)
}

#[test]
fn d_two_threads_give_the_same_outputs_as_one_instance_alone() {
    let shared = import(FmuKind::StickSlipBeam);
    let alone_beam = run_alone(&shared, "alone-beam", FidelityLevel::Beam);
    let alone_modal = run_alone(&shared, "alone-modal", FidelityLevel::Modal);
    assert_ne!(
        alone_beam[STEPS].tip_deflection.to_bits(),
        alone_modal[STEPS].tip_deflection.to_bits(),
        "beam and modal differ, so cross-talk would show"
    );

    // Each thread imports its own copy and instantiates there (InstanceCS is !Send).
    for levels in [
        [FidelityLevel::Beam, FidelityLevel::Beam],
        [FidelityLevel::Beam, FidelityLevel::Modal],
    ] {
        let results: Vec<Vec<Outputs>> = std::thread::scope(|s| {
            let handles: Vec<_> = levels
                .iter()
                .enumerate()
                .map(|(k, &level)| {
                    s.spawn(move || {
                        let own = import(FmuKind::StickSlipBeam);
                        run_alone(&own, &format!("thread-own-{k}-{}", level.code()), level)
                    })
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("thread"))
                .collect()
        });
        for (&level, result) in levels.iter().zip(&results) {
            let alone = if level == FidelityLevel::Beam {
                &alone_beam
            } else {
                &alone_modal
            };
            assert_bitwise("own import in a thread vs alone", result, alone);
        }
    }

    // Two threads with instances of ONE import share one loaded library.
    let results: Vec<Vec<Outputs>> = std::thread::scope(|s| {
        let shared = &shared;
        let a = s.spawn(move || run_alone(shared, "thread-shared-beam", FidelityLevel::Beam));
        let b = s.spawn(move || run_alone(shared, "thread-shared-modal", FidelityLevel::Modal));
        vec![a.join().expect("thread"), b.join().expect("thread")]
    });
    assert_bitwise(
        "shared import, beam thread vs alone",
        &results[0],
        &alone_beam,
    );
    assert_bitwise(
        "shared import, modal thread vs alone",
        &results[1],
        &alone_modal,
    );
}
