//! `valgrind_driver_loop` (ignored): the loop that `scripts/valgrind.sh` runs under
//! valgrind.

use super::*;

// The valgrind driver.

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
static RELEASES: AtomicUsize = AtomicUsize::new(0);

unsafe extern "C" fn counting_calloc(n: libc::size_t, size: libc::size_t) -> *mut c_void {
    ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    libc::calloc(n, size)
}

unsafe extern "C" fn counting_free(p: *mut c_void) {
    RELEASES.fetch_add(1, Ordering::Relaxed);
    libc::free(p)
}

#[derive(Clone, Copy, Debug)]
enum Callbacks {
    Logger,
    NullLogger,
    LoggerAndMemory,
}

/// One instance through its whole life: parameters, initialisation, steps, reads, FMU
/// state through pointers and bytes, an error and the recovery from it, reset, and free.
/// One FMU state is deliberately left for fmi2FreeInstance to free (FMI 2.0.x section
/// 2.1.6: fmi2FreeInstance "frees all the allocated memory ... allocated by the functions
/// of the FMU interface").
unsafe fn life(kind: FmuKind, callbacks_kind: Callbacks, steps: usize) {
    let log = Box::new(Log::default());
    let mut functions = callbacks(&log);
    match callbacks_kind {
        Callbacks::Logger => {}
        Callbacks::NullLogger => functions.logger = None,
        Callbacks::LoggerAndMemory => {
            functions.allocateMemory = Some(counting_calloc);
            functions.freeMemory = Some(counting_free);
        }
    }
    let logging_on = matches!(callbacks_kind, Callbacks::Logger) as fmi2Boolean;
    let guid = CString::new(kind.guid()).unwrap();
    let uri = CString::new(repository_uri()).unwrap();
    let c = fmi2Instantiate(
        c"life".as_ptr(),
        1,
        guid.as_ptr(),
        uri.as_ptr(),
        &functions,
        0,
        logging_on,
    );
    assert!(!c.is_null());
    let ok = |status: fmi2Status, what: &str| assert_eq!(status, OK, "{what}");
    let vrs = BeamVrs::get();
    let (output, input, string_vr) = match kind {
        FmuKind::StickSlipBeam => {
            ok(
                fmi2SetInteger(
                    c,
                    [vrs.fidelity, vrs.friction_law].as_ptr(),
                    2,
                    [FidelityLevel::Modal.code(), FrictionLawKind::Neural.code()].as_ptr(),
                ),
                "fmi2SetInteger",
            );
            (
                vrs.real_outputs[0],
                vr::<StickSlipBeam>("belt_speed"),
                vrs.weights,
            )
        }
        FmuKind::NeuralFriction => (
            vr::<NeuralFriction>("friction_force"),
            vr::<NeuralFriction>("sliding_velocity"),
            vr::<NeuralFriction>("weights"),
        ),
    };
    let all = [
        c"logStatusError".as_ptr(),
        c"logEvents".as_ptr(),
        c"logCalls".as_ptr(),
    ];
    ok(
        fmi2SetDebugLogging(c, logging_on, 3, all.as_ptr()),
        "fmi2SetDebugLogging",
    );
    let weights = c"paper-plain.json";
    ok(
        fmi2SetString(c, &string_vr, 1, &weights.as_ptr()),
        "fmi2SetString",
    );
    let initialize = || {
        ok(
            fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 10.0),
            "fmi2SetupExperiment",
        );
        ok(
            fmi2EnterInitializationMode(c),
            "fmi2EnterInitializationMode",
        );
        let mut y = 0.0;
        ok(
            fmi2GetReal(c, &output, 1, &mut y),
            "fmi2GetReal in initialization mode",
        );
        ok(fmi2ExitInitializationMode(c), "fmi2ExitInitializationMode");
    };
    initialize();
    let mut t = 0.0;
    let step = |t: &mut f64, n: usize| {
        for k in 0..n {
            let v = 0.02 * (1.0 + (k % 7) as f64 * 0.01);
            ok(fmi2SetReal(c, &input, 1, &v), "fmi2SetReal");
            ok(fmi2DoStep(c, *t, 1e-3, 1), "fmi2DoStep");
            *t += 1e-3;
            let mut y = 0.0;
            ok(fmi2GetReal(c, &output, 1, &mut y), "fmi2GetReal");
            assert!(y.is_finite());
            let mut s = null();
            ok(fmi2GetString(c, &string_vr, 1, &mut s), "fmi2GetString");
            assert!(!s.is_null());
        }
    };
    step(&mut t, steps);

    let mut state = null_mut();
    ok(fmi2GetFMUstate(c, &mut state), "fmi2GetFMUstate");
    ok(
        fmi2GetFMUstate(c, &mut state),
        "fmi2GetFMUstate (overwrite)",
    );
    let t_saved = t;
    let mut size = 0;
    ok(fmi2SerializedFMUstateSize(c, state, &mut size), "size");
    let mut bytes = vec![0 as c_char; size];
    ok(
        fmi2SerializeFMUstate(c, state, bytes.as_mut_ptr(), size),
        "serialize",
    );
    let mut copy = null_mut();
    ok(
        fmi2DeSerializeFMUstate(c, bytes.as_ptr(), size, &mut copy),
        "deserialize",
    );
    step(&mut t, steps / 4);

    // Errors, and the way back.
    assert_eq!(fmi2DoStep(c, t + 1.0, 1e-3, 1), ERROR);
    let mut bad = null_mut();
    assert_eq!(
        fmi2DeSerializeFMUstate(c, bytes.as_ptr(), size / 2, &mut bad),
        ERROR
    );
    assert!(bad.is_null());
    // Unknown and known swapped: an input is no unknown (NeuralFriction), and
    // StickSlipBeam has no directional derivatives at all.
    let mut d = 0.0;
    assert_eq!(
        fmi2GetDirectionalDerivative(c, &input, 1, &output, 1, &1.0, &mut d),
        ERROR
    );
    ok(fmi2SetFMUstate(c, copy), "fmi2SetFMUstate (deserialized)");
    t = t_saved;
    step(&mut t, steps / 4);
    ok(fmi2SetFMUstate(c, state), "fmi2SetFMUstate");
    t = t_saved;
    step(&mut t, steps / 4);
    ok(fmi2FreeFMUstate(c, &mut state), "fmi2FreeFMUstate");

    ok(fmi2Terminate(c), "fmi2Terminate");
    ok(fmi2Reset(c), "fmi2Reset");
    if kind == FmuKind::StickSlipBeam {
        ok(
            fmi2SetInteger(
                c,
                [vrs.fidelity, vrs.friction_law].as_ptr(),
                2,
                [
                    FidelityLevel::Modal.code(),
                    FrictionLawKind::Exponential.code(),
                ]
                .as_ptr(),
            ),
            "fmi2SetInteger",
        );
    }
    initialize();
    t = 0.0;
    step(&mut t, steps / 4);
    ok(fmi2Terminate(c), "fmi2Terminate");
    // `copy` is still allocated: fmi2FreeInstance frees it.
    fmi2FreeInstance(c);

    // Refused instantiations.
    let bad_guid = fmi2Instantiate(
        c"life".as_ptr(),
        1,
        c"{not-this-fmu}".as_ptr(),
        uri.as_ptr(),
        &functions,
        0,
        logging_on,
    );
    assert!(bad_guid.is_null());
    let nowhere = fmi2Instantiate(
        c"life".as_ptr(),
        1,
        guid.as_ptr(),
        c"file:///nonexistent/resources".as_ptr(),
        &functions,
        0,
        logging_on,
    );
    assert!(nowhere.is_null());
    if matches!(callbacks_kind, Callbacks::Logger) {
        assert!(!log.lock().unwrap().is_empty());
    }
}

/// Run by scripts/valgrind.sh under valgrind. STICKSLIP_VALGRIND_ROUNDS (default 2)
/// lives of each FMU with each kind of callbacks.
#[test]
#[ignore = "run by scripts/valgrind.sh"]
fn valgrind_driver_loop() {
    let rounds: usize = std::env::var("STICKSLIP_VALGRIND_ROUNDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2);
    for callbacks_kind in [
        Callbacks::Logger,
        Callbacks::NullLogger,
        Callbacks::LoggerAndMemory,
    ] {
        for _ in 0..rounds {
            for kind in FmuKind::ALL {
                unsafe { life(kind, callbacks_kind, 40) };
            }
        }
    }
    // The FMU declares canNotUseMemoryManagementFunctions = true and never calls them.
    assert_eq!(ALLOCATIONS.load(Ordering::Relaxed), 0);
    assert_eq!(RELEASES.load(Ordering::Relaxed), 0);
    println!("{rounds} rounds x 3 kinds of callbacks x 2 FMUs done");
}
