//! A whole life of each FMU through the FMI 3.0 C interface: bit-identical FMU state
//! round trips, and instances in two threads equal to one alone.

use super::*;

#[test]
fn fmi3_state_round_trips_are_bit_identical_through_the_c_interface() {
    for kind in FmuKind::ALL {
        let (straight, again) = unsafe { life(kind, 600, &format!("{kind:?}-life")) };
        assert_eq!(straight, again, "{kind:?}");
        // The window is not trivial: the outputs change along it.
        assert_ne!(straight.first(), straight.last(), "{kind:?}");
    }
}

/// Instances in two threads at once give the same bits as one instance alone: no state
/// is shared between FMI 3.0 instances (canBeInstantiatedOnlyOncePerProcess = false).
#[test]
fn fmi3_instances_in_two_threads_equal_one_alone() {
    for kind in FmuKind::ALL {
        let alone = unsafe { life(kind, 200, "alone") };
        let together: Vec<_> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..2)
                .map(|k| scope.spawn(move || unsafe { life(kind, 200, &format!("thread-{k}")) }))
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for run in together {
            assert_eq!(run, alone, "{kind:?}");
        }
    }
}
