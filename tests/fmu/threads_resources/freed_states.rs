//! Memory: the FMU states left at fmi2FreeInstance are freed, each by its own instance
//! (counted by `allocations`).

use super::*;

// Memory: FMU states left at fmi2FreeInstance (counted by `allocations`).

/// An initialised NeuralFriction instance with `left` FMU states (from fmi2GetFMUstate
/// and fmi2DeSerializeFMUstate) that the importer does not free, freed at once.
unsafe fn instance_leaving_states(left: usize) {
    let log = Log::default();
    let functions = callbacks(&log);
    let guid = CString::new(FmuKind::NeuralFriction.guid()).unwrap();
    let uri = CString::new(repository_uri()).unwrap();
    let c = fmi2Instantiate(
        c"states".as_ptr(),
        1,
        guid.as_ptr(),
        uri.as_ptr(),
        &functions,
        0,
        0,
    );
    assert!(!c.is_null());
    assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
    assert_eq!(fmi2EnterInitializationMode(c), OK);
    assert_eq!(fmi2ExitInitializationMode(c), OK);
    let mut bytes = Vec::new();
    for k in 0..left {
        let mut state = null_mut();
        if k % 2 == 0 {
            assert_eq!(fmi2GetFMUstate(c, &mut state), OK);
            let mut size = 0;
            assert_eq!(fmi2SerializedFMUstateSize(c, state, &mut size), OK);
            bytes = vec![0 as c_char; size];
            assert_eq!(
                fmi2SerializeFMUstate(c, state, bytes.as_mut_ptr(), size),
                OK
            );
        } else {
            assert_eq!(
                fmi2DeSerializeFMUstate(c, bytes.as_ptr(), bytes.len(), &mut state),
                OK
            );
        }
    }
    fmi2FreeInstance(c);
}

#[test]
fn fmi2_free_instance_frees_the_fmu_states_the_importer_did_not_free() {
    unsafe {
        // The first life sets up whatever this thread allocates once.
        instance_leaving_states(0);
        let before = live_bytes();
        instance_leaving_states(0);
        assert_eq!(live_bytes(), before, "an instance without states leaks");
        instance_leaving_states(4);
        assert_eq!(
            live_bytes() - before,
            0,
            "bytes left after fmi2FreeInstance of an instance with 4 unfreed FMU states"
        );
    }
}

#[test]
fn fmu_states_are_freed_by_their_own_instance_only() {
    let logs = [Log::default(), Log::default()];
    let functions = [callbacks(&logs[0]), callbacks(&logs[1])];
    let guid = CString::new(FmuKind::NeuralFriction.guid()).unwrap();
    let uri = CString::new(repository_uri()).unwrap();
    unsafe {
        let [a, b] = [0, 1].map(|k| {
            fmi2Instantiate(
                c"owner".as_ptr(),
                1,
                guid.as_ptr(),
                uri.as_ptr(),
                &functions[k],
                0,
                0,
            )
        });
        let mut state = null_mut();
        assert_eq!(fmi2GetFMUstate(a, &mut state), OK);
        let kept = state;
        assert_eq!(fmi2FreeFMUstate(b, &mut state), ERROR);
        assert_eq!(state, kept, "the pointer is left alone");
        let refused = logs[1].lock().unwrap();
        assert!(
            refused
                .iter()
                .any(|e| e.message.contains("not allocated by this instance")),
            "{refused:?}"
        );
        drop(refused);
        assert_eq!(fmi2FreeFMUstate(a, &mut state), OK);
        assert!(state.is_null());
        // Freed already: a second free is refused, not a double free.
        state = kept;
        assert_eq!(fmi2FreeFMUstate(a, &mut state), ERROR);
        fmi2FreeInstance(a);
        fmi2FreeInstance(b);
    }
}
