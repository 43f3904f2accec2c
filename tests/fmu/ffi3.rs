//! The FMI 3.0 C interface (`stickslip_fmi::ffi3`) called as an importer calls it:
//! a whole life of each FMU (instantiate, initialise, steps with reads and writes, FMU
//! state get/serialize/deserialize/set/free, an illegal call and the recovery by
//! fmi3Reset, free), checked for bit-identical state round trips, and the ignored loop
//! `valgrind_driver_loop3` that `scripts/valgrind.sh` runs under valgrind.

use std::ffi::{c_char, c_void, CStr, CString};
use std::ptr::{null, null_mut};
use std::sync::Mutex;
use stickslip::choice::Choice;
use stickslip::scene::FidelityLevel;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::ffi3::*;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::model::Model;
use stickslip_fmi::variables::{BaseType, Causality};
use stickslip_fmi::FmuKind;
use stickslip_tests::vr;

const OK: fmi3Status = 0;
const ERROR: fmi3Status = 3;

pub(crate) type Messages = Mutex<Vec<(fmi3Status, String)>>;

pub(crate) unsafe extern "C" fn log3(
    environment: fmi3InstanceEnvironment,
    status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the environment is the &Messages passed at instantiation; the FMU passes
    // NUL-terminated strings.
    let messages = unsafe { &*(environment as *const Messages) };
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    if let Ok(mut m) = messages.lock() {
        m.push((status, text));
    }
}

/// The messages logged so far, without their statuses.
fn texts(messages: &Messages) -> Vec<String> {
    messages
        .lock()
        .unwrap()
        .iter()
        .map(|(_, m)| m.clone())
        .collect()
}

unsafe fn instantiate(kind: FmuKind, name: &str, messages: &Messages) -> fmi3Instance {
    unsafe { instantiate_with(kind, name, messages, false, false) }
}

/// The output value references of `M` by type: (Float64, Int32, Boolean).
fn outputs_of<M: Model>() -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    let of = |base: BaseType| {
        M::variables()
            .iter()
            .filter(|v| v.causality == Causality::Output && v.access.base_type() == base)
            .map(|v| v.value_reference)
            .collect::<Vec<u32>>()
    };
    (
        of(BaseType::Real),
        of(BaseType::Integer),
        of(BaseType::Boolean),
    )
}

/// Every output as bits.
unsafe fn read(c: fmi3Instance, vrs: &(Vec<u32>, Vec<u32>, Vec<u32>)) -> Vec<u64> {
    let mut reals = vec![0.0; vrs.0.len()];
    let mut integers = vec![0i32; vrs.1.len()];
    let mut booleans = vec![0u8; vrs.2.len()];
    unsafe {
        assert_eq!(
            fmi3GetFloat64(
                c,
                vrs.0.as_ptr(),
                vrs.0.len(),
                reals.as_mut_ptr(),
                reals.len()
            ),
            OK
        );
        assert_eq!(
            fmi3GetInt32(
                c,
                vrs.1.as_ptr(),
                vrs.1.len(),
                integers.as_mut_ptr(),
                integers.len()
            ),
            OK
        );
        assert_eq!(
            fmi3GetBoolean(
                c,
                vrs.2.as_ptr(),
                vrs.2.len(),
                booleans.as_mut_ptr(),
                booleans.len()
            ),
            OK
        );
    }
    reals
        .iter()
        .map(|r| r.to_bits())
        .chain(integers.iter().map(|&i| i as u64))
        .chain(booleans.iter().map(|&b| b as u64))
        .collect()
}

unsafe fn step(c: fmi3Instance, t: f64, h: f64) {
    let (mut event, mut terminate, mut early, mut last) = (1u8, 1u8, 1u8, 0.0);
    let status = unsafe {
        fmi3DoStep(
            c,
            t,
            h,
            0,
            &mut event,
            &mut terminate,
            &mut early,
            &mut last,
        )
    };
    assert_eq!(status, OK, "fmi3DoStep at {t} s");
    assert_eq!((event, terminate, early), (0, 0, 0));
    assert_eq!(last, t + h);
}

/// One life of an FMU through the FMI 3.0 C interface; `steps` communication steps
/// of 1 ms. Returns what the importer would check: the outputs after the saved
/// point, run twice (straight on, and again after restoring the state deserialized
/// into the same instance).
unsafe fn life(kind: FmuKind, steps: usize, name: &str) -> (Vec<Vec<u64>>, Vec<Vec<u64>>) {
    let messages = Messages::default();
    let h = 1e-3;
    unsafe {
        let c = instantiate(kind, name, &messages);
        assert!(!c.is_null(), "{:?}", messages.lock().unwrap());
        // A step before initialisation is refused and logged; fmi3Reset recovers.
        let (mut e, mut t_, mut r, mut l) = (0u8, 0u8, 0u8, 0.0);
        assert_eq!(
            fmi3DoStep(c, 0.0, h, 0, &mut e, &mut t_, &mut r, &mut l),
            ERROR
        );
        assert_eq!(fmi3Reset(c), OK);

        assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 1, 1.0), OK);
        let vrs = match kind {
            FmuKind::StickSlipBeam => {
                let fidelity = [vr::<StickSlipBeam>("fidelity.level")];
                let modal = [FidelityLevel::Modal.code()];
                assert_eq!(fmi3SetInt32(c, fidelity.as_ptr(), 1, modal.as_ptr(), 1), OK);
                outputs_of::<StickSlipBeam>()
            }
            FmuKind::NeuralFriction => outputs_of::<NeuralFriction>(),
        };
        assert_eq!(fmi3ExitInitializationMode(c), OK);
        let input = [vr::<NeuralFriction>("sliding_velocity")];
        let mut t = 0.0;
        let advance = |t: &mut f64, k: usize| {
            if kind == FmuKind::NeuralFriction {
                let v = [0.05 * stickslip::elementary::sin(k as f64 * 0.1)];
                assert_eq!(fmi3SetFloat64(c, input.as_ptr(), 1, v.as_ptr(), 1), OK);
            }
            step(c, *t, h);
            *t += h;
            read(c, &vrs)
        };
        for k in 0..steps / 2 {
            advance(&mut t, k);
        }
        let mut state: fmi3FMUState = null_mut();
        assert_eq!(fmi3GetFMUState(c, &mut state), OK);
        let mut size = 0;
        assert_eq!(fmi3SerializedFMUStateSize(c, state, &mut size), OK);
        let mut bytes = vec![0u8; size];
        assert_eq!(
            fmi3SerializeFMUState(c, state, bytes.as_mut_ptr(), size),
            OK
        );
        let saved_t = t;
        let straight: Vec<Vec<u64>> = (steps / 2..steps).map(|k| advance(&mut t, k)).collect();

        let mut restored: fmi3FMUState = null_mut();
        assert_eq!(
            fmi3DeserializeFMUState(c, bytes.as_ptr(), size, &mut restored),
            OK
        );
        assert_eq!(fmi3SetFMUState(c, restored), OK);
        t = saved_t;
        let again: Vec<Vec<u64>> = (steps / 2..steps).map(|k| advance(&mut t, k)).collect();
        assert_eq!(fmi3FreeFMUState(c, &mut restored), OK);
        assert!(restored.is_null());

        // This instance was instantiated without event mode: fmi3EnterEventMode is
        // fmi3Error with the reason, then the Error state refuses steps until
        // fmi3SetFMUState brings the saved state back.
        assert_eq!(fmi3EnterEventMode(c), ERROR);
        let (mut e, mut t_, mut r, mut l) = (0u8, 0u8, 0u8, 0.0);
        assert_eq!(
            fmi3DoStep(c, t, h, 0, &mut e, &mut t_, &mut r, &mut l),
            ERROR
        );
        assert_eq!(fmi3SetFMUState(c, state), OK);
        step(c, saved_t, h);
        // `state` is left for fmi3FreeInstance to free.
        assert_eq!(fmi3Terminate(c), OK);
        fmi3FreeInstance(c);
        let log = messages.lock().unwrap();
        assert!(
            log.iter()
                .any(|(s, m)| *s == ERROR && m.starts_with("fmi3DoStep: illegal call sequence")),
            "{log:?}"
        );
        assert!(
            log.iter().any(|(s, m)| *s == ERROR
                && m.starts_with(
                    "fmi3EnterEventMode: the instance was instantiated with eventModeUsed = false"
                )),
            "{log:?}"
        );
        (straight, again)
    }
}

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

#[test]
fn fmi3_instantiation_refuses_what_the_fmu_does_not_offer() {
    let messages = Messages::default();
    let name = CString::new("refused").unwrap();
    let token = CString::new(FmuKind::NeuralFriction.guid()).unwrap();
    let uri = CString::new(format!(
        "file://{}/",
        stickslip_tests::weights_dir().display()
    ))
    .unwrap();
    let environment = &messages as *const Messages as *mut c_void;
    let required = [1u32];
    let refused = |intermediate: bool, resources: &CString| unsafe {
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token.as_ptr(),
            resources.as_ptr(),
            0,
            0,
            1,
            1,
            if intermediate {
                required.as_ptr()
            } else {
                null()
            },
            usize::from(intermediate),
            environment,
            Some(log3),
            None,
        )
        .is_null()
    };
    assert!(refused(false, &uri));
    let path = CString::new(format!("{}/", stickslip_tests::weights_dir().display())).unwrap();
    assert!(refused(true, &path));
    let me = unsafe {
        fmi3InstantiateModelExchange(
            name.as_ptr(),
            token.as_ptr(),
            path.as_ptr(),
            0,
            0,
            environment,
            Some(log3),
        )
    };
    assert!(me.is_null());
    let log = texts(&messages);
    for expected in [
        "is a URI",
        "providesIntermediateUpdate = false",
        "co-simulation only",
    ] {
        assert!(
            log.iter().any(|m| m.contains(expected)),
            "{expected}: {log:?}"
        );
    }
}

/// An FMI 3.0 instance logs what it was told and found as it is: a reason, path or
/// category name that contains "fmi2" is not rewritten (messages are written with the
/// FMI 3.0 function's name, never renamed afterwards), while the function named is the
/// FMI 3.0 one that was called.
#[test]
fn fmi3_reasons_containing_fmi2_are_logged_unaltered() {
    let messages = Messages::default();
    unsafe {
        let c = instantiate_logging(
            FmuKind::StickSlipBeam,
            "fmi2-named",
            &messages,
            true,
            false,
            false,
        );
        assert!(!c.is_null());
        let unknown = CString::new("fmi2Category").unwrap();
        assert_eq!(fmi3SetDebugLogging(c, 1, 1, &unknown.as_ptr()), 1);
        assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 1, 1.0), OK);
        let law = [vr::<StickSlipBeam>("friction.law")];
        let neural = [stickslip::scene::FrictionLawKind::Neural.code()];
        assert_eq!(fmi3SetInt32(c, law.as_ptr(), 1, neural.as_ptr(), 1), OK);
        let weights = [vr::<StickSlipBeam>("friction.weights")];
        let path = CString::new("/tmp/fmi2dir/x.json").unwrap();
        assert_eq!(fmi3SetString(c, weights.as_ptr(), 1, &path.as_ptr(), 1), OK);
        assert_eq!(fmi3ExitInitializationMode(c), ERROR);
        fmi3FreeInstance(c);
    }
    let log = texts(&messages);
    let failed = log
        .iter()
        .find(|m| m.starts_with("fmi3ExitInitializationMode: "))
        .unwrap_or_else(|| panic!("no fmi3ExitInitializationMode error: {log:?}"));
    assert!(failed.contains("/tmp/fmi2dir/x.json"), "{failed}");
    assert!(
        log.iter()
            .any(|m| m
                .starts_with("fmi3SetDebugLogging: unknown log category \"fmi2Category\" ignored")),
        "{log:?}"
    );
    // The calls are logged (logCalls) with the names of the FMI 3.0 functions.
    for call in [
        "fmi3SetDebugLogging",
        "fmi3SetString",
        "fmi3ExitInitializationMode",
    ] {
        assert!(log.iter().any(|m| m == call), "{call}: {log:?}");
    }
    assert!(!log.iter().any(|m| m.contains("fmi3dir")), "{log:?}");
}

unsafe fn instantiate_with(
    kind: FmuKind,
    name: &str,
    messages: &Messages,
    event_mode_used: bool,
    early_return_allowed: bool,
) -> fmi3Instance {
    unsafe {
        instantiate_logging(
            kind,
            name,
            messages,
            false,
            event_mode_used,
            early_return_allowed,
        )
    }
}

/// An FMI 3.0 co-simulation instance of `kind` (resources: the workspace's `weights/`)
/// whose log lands in `messages`; shared with the other FMI 3.0 test modules.
pub(crate) unsafe fn instantiate_logging(
    kind: FmuKind,
    name: &str,
    messages: &Messages,
    logging_on: bool,
    event_mode_used: bool,
    early_return_allowed: bool,
) -> fmi3Instance {
    let name = CString::new(name).unwrap();
    let token = CString::new(kind.guid()).unwrap();
    let resources = CString::new(format!("{}/", stickslip_tests::weights_dir().display())).unwrap();
    unsafe {
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token.as_ptr(),
            resources.as_ptr(),
            0,
            u8::from(logging_on),
            u8::from(event_mode_used),
            u8::from(early_return_allowed),
            null(),
            0,
            messages as *const Messages as *mut c_void,
            Some(log3),
            None,
        )
    }
}

/// fmi3DoStep's result: (status, eventHandlingNeeded, earlyReturn, lastSuccessfulTime).
pub(crate) unsafe fn do_step3(c: fmi3Instance, t: f64, h: f64) -> (fmi3Status, bool, bool, f64) {
    let (mut event, mut terminate, mut early, mut last) = (0u8, 1u8, 0u8, f64::NAN);
    let status = unsafe {
        fmi3DoStep(
            c,
            t,
            h,
            0,
            &mut event,
            &mut terminate,
            &mut early,
            &mut last,
        )
    };
    assert_eq!(terminate, 0);
    (status, event != 0, early != 0, last)
}

/// fmi3UpdateDiscreteStates; its outputs must say: settled, no time event.
unsafe fn update_discrete_states(c: fmi3Instance) -> fmi3Status {
    let mut flags = [1u8; 5];
    let mut next = f64::NAN;
    let [a, b, c_, d, e] = &mut flags;
    let status = unsafe { fmi3UpdateDiscreteStates(c, a, b, c_, d, e, &mut next) };
    if status == OK {
        assert_eq!(flags, [0; 5]);
        assert_eq!(next, 0.0);
    }
    status
}

/// StickSlipBeam (modal fidelity) initialised with eventModeUsed: in Event Mode at 0 s.
unsafe fn initialise_in_event_mode(c: fmi3Instance) {
    unsafe {
        assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 1, 1.0), OK);
        let fidelity = [vr::<StickSlipBeam>("fidelity.level")];
        let modal = [FidelityLevel::Modal.code()];
        assert_eq!(fmi3SetInt32(c, fidelity.as_ptr(), 1, modal.as_ptr(), 1), OK);
        assert_eq!(fmi3ExitInitializationMode(c), OK);
    }
}

/// The master's loop with events: communication steps of `h` from `t` to `end`; at each
/// early return or event it handles Event Mode (enter, read, set the belt speed input,
/// update, back to Step Mode) and goes on. Returns the outputs (as bits) at every point
/// where a step ended and the times of the events.
unsafe fn run_with_events(
    c: fmi3Instance,
    mut t: f64,
    h: f64,
    end: f64,
) -> (Vec<Vec<u64>>, Vec<f64>) {
    let vrs = outputs_of::<StickSlipBeam>();
    let belt = [vr::<StickSlipBeam>("belt_speed")];
    let mut outputs = Vec::new();
    let mut events = Vec::new();
    unsafe {
        while t < end - 1e-12 {
            let target = ((t / h + 1e-9).floor() + 1.0) * h;
            let (status, event, early, last) = do_step3(c, t, target - t);
            assert_eq!(status, OK, "fmi3DoStep at {t} s");
            if early {
                assert!(event, "with eventModeUsed an early return is an event");
                assert!(last > t && last < target, "{t} < {last} < {target}");
            } else {
                assert_eq!(last, target);
            }
            t = last;
            if event {
                events.push(t);
                assert_eq!(fmi3EnterEventMode(c), OK);
                // Inputs can be set in Event Mode (the same value: the run must not
                // change).
                let v = [0.02];
                assert_eq!(fmi3SetFloat64(c, belt.as_ptr(), 1, v.as_ptr(), 1), OK);
                assert_eq!(update_discrete_states(c), OK);
                assert_eq!(fmi3EnterStepMode(c), OK);
            }
            outputs.push(read(c, &vrs));
        }
    }
    (outputs, events)
}

/// Serializes the current state of `c`.
unsafe fn saved_bytes(c: fmi3Instance) -> Vec<u8> {
    unsafe {
        let mut state: fmi3FMUState = null_mut();
        assert_eq!(fmi3GetFMUState(c, &mut state), OK);
        let mut size = 0;
        assert_eq!(fmi3SerializedFMUStateSize(c, state, &mut size), OK);
        let mut bytes = vec![0u8; size];
        assert_eq!(
            fmi3SerializeFMUState(c, state, bytes.as_mut_ptr(), size),
            OK
        );
        assert_eq!(fmi3FreeFMUState(c, &mut state), OK);
        bytes
    }
}

/// Deserializes `bytes` into `c` and sets them; the status of fmi3SetFMUState.
unsafe fn restore(c: fmi3Instance, bytes: &[u8]) -> fmi3Status {
    unsafe {
        let mut state: fmi3FMUState = null_mut();
        assert_eq!(
            fmi3DeserializeFMUState(c, bytes.as_ptr(), bytes.len(), &mut state),
            OK
        );
        let status = fmi3SetFMUState(c, state);
        assert_eq!(fmi3FreeFMUState(c, &mut state), OK);
        status
    }
}

/// What `event_life` returns: the first early return (its time, the `transitions` and
/// `stick` outputs there), the run after it (outputs, event times) continued straight
/// on, after restoring the state saved at the early return in the same instance, in a
/// fresh one, and after restoring a state saved in Event Mode.
#[derive(Debug, PartialEq)]
struct EventLife {
    first_switch: f64,
    transitions_at_switch: i32,
    stick_at_switch: bool,
    straight: (Vec<Vec<u64>>, Vec<f64>),
    restored: (Vec<Vec<u64>>, Vec<f64>),
    fresh: (Vec<Vec<u64>>, Vec<f64>),
    from_event_mode: (Vec<Vec<u64>>, Vec<f64>),
}

/// StickSlipBeam with eventModeUsed and earlyReturnAllowed through the C interface:
/// every illegal call of the event state table refused (and recovered from), the early
/// return at the breakaway, and FMU states saved after the early return and in Event
/// Mode restored.
unsafe fn event_life(name: &str, h: f64, end: f64) -> EventLife {
    let messages = Messages::default();
    let kind = FmuKind::StickSlipBeam;
    let transitions = [vr::<StickSlipBeam>("transitions")];
    let stick = [vr::<StickSlipBeam>("stick")];
    unsafe {
        let c = instantiate_with(kind, name, &messages, true, true);
        assert!(!c.is_null(), "{:?}", messages.lock().unwrap());
        // Illegal in Event Mode (after fmi3ExitInitializationMode): a step, and entering
        // Event Mode again; illegal in Step Mode: fmi3UpdateDiscreteStates and
        // fmi3EnterStepMode. Each is fmi3Error with the reason; fmi3Reset recovers.
        type Illegal = unsafe fn(fmi3Instance) -> fmi3Status;
        let in_event_mode: [(&str, Illegal); 2] = [
            ("fmi3DoStep", |c| do_step3(c, 0.0, 1e-3).0),
            ("fmi3EnterEventMode", |c| fmi3EnterEventMode(c)),
        ];
        for (call, illegal) in in_event_mode {
            initialise_in_event_mode(c);
            assert_eq!(illegal(c), ERROR, "{call} in Event Mode");
            assert_eq!(fmi3Reset(c), OK);
            let log = messages.lock().unwrap();
            assert!(
                log.iter().any(|(s, m)| *s == ERROR
                    && m.starts_with(&format!(
                        "{call}: illegal call sequence: called in mode EventMode"
                    ))),
                "{call}: {log:?}"
            );
        }
        let in_step_mode: [(&str, Illegal); 2] = [
            ("fmi3UpdateDiscreteStates", |c| update_discrete_states(c)),
            ("fmi3EnterStepMode", |c| fmi3EnterStepMode(c)),
        ];
        for (call, illegal) in in_step_mode {
            initialise_in_event_mode(c);
            assert_eq!(fmi3EnterStepMode(c), OK);
            assert_eq!(illegal(c), ERROR, "{call} in Step Mode");
            assert_eq!(fmi3Reset(c), OK);
            let log = messages.lock().unwrap();
            assert!(
                log.iter().any(|(s, m)| *s == ERROR
                    && m.starts_with(&format!(
                        "{call}: illegal call sequence: called in mode StepComplete"
                    ))),
                "{call}: {log:?}"
            );
        }

        initialise_in_event_mode(c);
        // Event Mode at the start: outputs can be read, the discrete states settle.
        read(c, &outputs_of::<StickSlipBeam>());
        assert_eq!(update_discrete_states(c), OK);
        assert_eq!(fmi3EnterStepMode(c), OK);
        // Steps of h until the first early return: the breakaway.
        let mut t = 0.0;
        let first_switch = loop {
            let (status, event, early, last) = do_step3(c, t, h);
            assert_eq!(status, OK);
            if early {
                assert!(event && last < t + h && last > t);
                break last;
            }
            assert_eq!(last, t + h);
            if event {
                // The switch fell on the communication point: an event without an
                // early return.
                break last;
            }
            t = last;
            assert!(t < end, "no switch before {end} s");
        };
        let mut transitions_at_switch = 0;
        let mut stick_at_switch = 1u8;
        assert_eq!(
            fmi3GetInt32(c, transitions.as_ptr(), 1, &mut transitions_at_switch, 1),
            OK
        );
        assert_eq!(
            fmi3GetBoolean(c, stick.as_ptr(), 1, &mut stick_at_switch, 1),
            OK
        );
        // The state right after the early return, with the event still pending.
        let pending = saved_bytes(c);
        // The event must be handled before the next step.
        assert_eq!(do_step3(c, first_switch, 1e-3).0, ERROR);
        assert!(messages.lock().unwrap().iter().any(|(s, m)| *s == ERROR
            && m.starts_with(
                "fmi3DoStep: illegal call sequence: the last step ended at an event"
            )));
        // Back from the Error state by the saved state; then the standard's way on.
        assert_eq!(restore(c, &pending), OK);
        let handle = |c: fmi3Instance| {
            assert_eq!(fmi3EnterEventMode(c), OK);
            assert_eq!(update_discrete_states(c), OK);
            assert_eq!(fmi3EnterStepMode(c), OK);
        };
        handle(c);
        let straight = run_with_events(c, first_switch, h, end);
        assert_eq!(restore(c, &pending), OK);
        handle(c);
        let restored = run_with_events(c, first_switch, h, end);

        // A state saved in Event Mode, restored after the run went on.
        assert_eq!(restore(c, &pending), OK);
        assert_eq!(fmi3EnterEventMode(c), OK);
        let in_event_mode = saved_bytes(c);
        assert_eq!(update_discrete_states(c), OK);
        assert_eq!(fmi3EnterStepMode(c), OK);
        run_with_events(c, first_switch, h, end);
        assert_eq!(restore(c, &in_event_mode), OK);
        assert_eq!(update_discrete_states(c), OK);
        assert_eq!(fmi3EnterStepMode(c), OK);
        let from_event_mode = run_with_events(c, first_switch, h, end);
        assert_eq!(fmi3Terminate(c), OK);
        fmi3FreeInstance(c);

        // A fresh instance with event mode takes the state; one without refuses it.
        let fresh_instance = instantiate_with(kind, name, &messages, true, true);
        assert_eq!(restore(fresh_instance, &pending), OK);
        handle(fresh_instance);
        let fresh = run_with_events(fresh_instance, first_switch, h, end);
        fmi3FreeInstance(fresh_instance);
        // Refused already by fmi3DeserializeFMUState, which checks what fmi3SetFMUState would.
        let without = instantiate_with(kind, name, &messages, false, false);
        let mut refused: fmi3FMUState = null_mut();
        assert_eq!(
            fmi3DeserializeFMUState(without, pending.as_ptr(), pending.len(), &mut refused),
            ERROR
        );
        assert!(refused.is_null());
        fmi3FreeInstance(without);
        assert!(messages
            .lock()
            .unwrap()
            .iter()
            .any(|(s, m)| *s == ERROR && m.contains("instantiated with eventModeUsed = false")));
        EventLife {
            first_switch,
            transitions_at_switch,
            stick_at_switch: stick_at_switch != 0,
            straight,
            restored,
            fresh,
            from_event_mode,
        }
    }
}

/// The time at which the `transitions` output of StickSlipBeam (modal fidelity, no
/// events) first steps up, stepped at its internal step: the switch time the library
/// records.
unsafe fn first_transition_without_events(end: f64) -> f64 {
    let messages = Messages::default();
    let transitions = [vr::<StickSlipBeam>("transitions")];
    let dt_vr = [vr::<StickSlipBeam>("time.step")];
    unsafe {
        let c = instantiate_with(FmuKind::StickSlipBeam, "no-events", &messages, false, false);
        assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 1, 1.0), OK);
        let fidelity = [vr::<StickSlipBeam>("fidelity.level")];
        let modal = [FidelityLevel::Modal.code()];
        assert_eq!(fmi3SetInt32(c, fidelity.as_ptr(), 1, modal.as_ptr(), 1), OK);
        assert_eq!(fmi3ExitInitializationMode(c), OK);
        let mut dt = 0.0;
        assert_eq!(fmi3GetFloat64(c, dt_vr.as_ptr(), 1, &mut dt, 1), OK);
        let n = (end / dt).round() as usize;
        for k in 0..n {
            step(c, k as f64 * dt, dt);
            let mut count = 0;
            assert_eq!(fmi3GetInt32(c, transitions.as_ptr(), 1, &mut count, 1), OK);
            if count > 0 {
                fmi3FreeInstance(c);
                return (k + 1) as f64 * dt;
            }
        }
        panic!("no transition before {end} s");
    }
}

#[test]
fn fmi3_event_mode_and_early_return_at_a_stick_slip_switch() {
    // h = 7e-3 s: off the internal grid (1 ms), so that landing steps are exercised.
    let life = unsafe { event_life("events", 7e-3, 0.7) };
    // The early return ends at the breakaway, which the run without events records at
    // the same time to rounding (the same internal steps up to it).
    let reference = unsafe { first_transition_without_events(0.7) };
    assert!(
        (life.first_switch - reference).abs() < 1e-9,
        "{} s against {reference} s",
        life.first_switch
    );
    assert_eq!(life.transitions_at_switch, 1);
    assert!(!life.stick_at_switch);
    // The run goes on through further switches (each an event), and every restored
    // state continues bit for bit.
    assert!(life.straight.1.len() >= 3, "{:?}", life.straight.1);
    assert_eq!(life.straight, life.restored);
    assert_eq!(life.straight, life.fresh);
    assert_eq!(life.straight, life.from_event_mode);
}

/// The loop `scripts/valgrind.sh` runs under valgrind (after the FMI 2.0 one).
#[test]
#[ignore = "run by scripts/valgrind.sh"]
fn valgrind_driver_loop3() {
    for round in 0..2 {
        for kind in FmuKind::ALL {
            let (straight, again) = unsafe { life(kind, 40, &format!("valgrind-{round}")) };
            assert_eq!(straight, again);
        }
        // Early return at the breakaway and Event Mode, with every illegal call of the
        // event state table and the state round trips.
        let events = unsafe { event_life(&format!("valgrind-events-{round}"), 0.05, 0.45) };
        assert_eq!(events.straight, events.restored);
    }
    println!(
        "2 rounds x 2 FMUs, and StickSlipBeam with events, through the FMI 3.0 interface done"
    );
}

/// fmi3Get/Set of Int32, Boolean and String check what FMI 3.0 adds to FMI 2.0's
/// arguments: nValues must equal the number of scalar value references, and NULL arrays
/// are refused with FMI 3.0's argument names; each refusal is fmi3Error with the reason
/// logged under the function called. One fresh instance per case: an error leaves the
/// instance in the Error mode, where a setter would be refused for that reason instead.
#[test]
fn fmi3_scalar_accessors_check_n_values_and_null_arrays() {
    let text = CString::new("paper-plain.json").unwrap();
    let texts_ptrs = [text.as_ptr(), text.as_ptr()];
    type Case = (
        &'static str,
        &'static str,
        fn(fmi3Instance, &[*const c_char]) -> fmi3Status,
    );
    let cases: [Case; 4] = [
        ("fmi3GetInt32", "nValues = 2", |c, _| {
            let mut out = [0i32; 2];
            let vr = [vr::<StickSlipBeam>("transitions")];
            unsafe { fmi3GetInt32(c, vr.as_ptr(), 1, out.as_mut_ptr(), 2) }
        }),
        ("fmi3GetBoolean", "nValues = 0", |c, _| {
            let mut out = [0u8; 1];
            let vr = [vr::<StickSlipBeam>("stick")];
            unsafe { fmi3GetBoolean(c, vr.as_ptr(), 1, out.as_mut_ptr(), 0) }
        }),
        ("fmi3SetString", "nValues = 2", |c, strings| {
            let vr = [vr::<StickSlipBeam>("friction.weights")];
            unsafe { fmi3SetString(c, vr.as_ptr(), 1, strings.as_ptr(), 2) }
        }),
        (
            "fmi3GetInt32",
            "valueReferences or values is NULL",
            |c, _| {
                let mut out = [0i32; 1];
                unsafe { fmi3GetInt32(c, null(), 1, out.as_mut_ptr(), 1) }
            },
        ),
    ];
    for (call, reason, case) in cases {
        let messages = Messages::default();
        unsafe {
            let c = instantiate(FmuKind::StickSlipBeam, "n-values", &messages);
            assert!(!c.is_null());
            assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 1, 1.0), OK);
            assert_eq!(case(c, &texts_ptrs), ERROR, "{call}: {reason}");
            fmi3FreeInstance(c);
        }
        let log = texts(&messages);
        assert!(
            log.iter()
                .any(|m| m.starts_with(&format!("{call}: ")) && m.contains(reason)),
            "{call}: {reason}: {log:?}"
        );
    }
}

/// FMI 3.0's Boolean is a C99 `bool`, one byte. A byte other than 0 or 1 from an
/// importer (by value here) must not be undefined behaviour: any non-zero byte reads as
/// true, as C converts it. With eventModeUsed = 2 or 0xFF the instance leaves
/// Initialization Mode into Event Mode, as with 1, so fmi3EnterStepMode is legal; with 0
/// it is in Step Mode already and the call is refused.
#[test]
fn boolean_bytes_other_than_0_or_1_read_as_true() {
    let messages = Messages::default();
    let name = CString::new("boolean-bytes").unwrap();
    let token = CString::new(FmuKind::StickSlipBeam.guid()).unwrap();
    let resources = CString::new(format!("{}/", stickslip_tests::weights_dir().display())).unwrap();
    for (byte, expected) in [(0u8, ERROR), (1, OK), (2, OK), (0xFF, OK)] {
        unsafe {
            let c = fmi3InstantiateCoSimulation(
                name.as_ptr(),
                token.as_ptr(),
                resources.as_ptr(),
                0,
                0,
                byte,
                0,
                null(),
                0,
                &messages as *const Messages as *mut c_void,
                Some(log3),
                None,
            );
            assert!(!c.is_null(), "{:?}", messages.lock().unwrap());
            assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, byte, 1.0), OK);
            assert_eq!(fmi3ExitInitializationMode(c), OK);
            assert_eq!(fmi3EnterStepMode(c), expected, "eventModeUsed = {byte}");
            fmi3FreeInstance(c);
        }
    }
}
