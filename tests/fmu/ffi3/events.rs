//! Event Mode and the early return at a stick-slip switch: the event state table, the
//! FMU state round trips in Event Mode, and the run without events.

use super::*;

/// fmi3UpdateDiscreteStates; its outputs must say: settled, no time event.
pub(super) unsafe fn update_discrete_states(c: fmi3Instance) -> fmi3Status {
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
pub(super) unsafe fn initialise_in_event_mode(c: fmi3Instance) {
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
pub(super) unsafe fn run_with_events(
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
pub(super) unsafe fn saved_bytes(c: fmi3Instance) -> Vec<u8> {
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
pub(super) unsafe fn restore(c: fmi3Instance, bytes: &[u8]) -> fmi3Status {
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
pub(super) struct EventLife {
    pub(super) first_switch: f64,
    pub(super) transitions_at_switch: i32,
    pub(super) stick_at_switch: bool,
    pub(super) straight: (Vec<Vec<u64>>, Vec<f64>),
    pub(super) restored: (Vec<Vec<u64>>, Vec<f64>),
    pub(super) fresh: (Vec<Vec<u64>>, Vec<f64>),
    pub(super) from_event_mode: (Vec<Vec<u64>>, Vec<f64>),
}

/// StickSlipBeam with eventModeUsed and earlyReturnAllowed through the C interface:
/// every illegal call of the event state table refused (and recovered from), the early
/// return at the breakaway, and FMU states saved after the early return and in Event
/// Mode restored.
pub(super) unsafe fn event_life(name: &str, h: f64, end: f64) -> EventLife {
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
pub(super) unsafe fn first_transition_without_events(end: f64) -> f64 {
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
