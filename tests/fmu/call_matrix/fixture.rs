//! The importer side of the call matrix: the logger, instances driven into each state of
//! the state machine (`Fixture`), their FMU states and the way into stepFailed.

use super::*;

// The importer side: logger, instances driven into each state.

pub(super) fn callbacks(log: &Log) -> fmi2CallbackFunctions {
    type Fixed = extern "C" fn(
        fmi2ComponentEnvironment,
        fmi2String,
        fmi2Status,
        fmi2String,
        fmi2String,
        *const c_char,
    );
    // SAFETY: see `record`.
    let logger = unsafe { std::mem::transmute::<Fixed, fmi2CallbackLogger>(record) };
    fmi2CallbackFunctions {
        logger: Some(logger),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: log as *const Log as *mut c_void,
    }
}

/// The repository's weights folder stands in for the unpacked resources/.
pub(super) fn resource_uri() -> CString {
    let dir = stickslip_tests::weights_dir();
    CString::new(format!("file://{}", dir.display())).unwrap()
}

pub(super) fn instantiate(
    kind: FmuKind,
    name: &str,
    functions: &fmi2CallbackFunctions,
) -> fmi2Component {
    let name = CString::new(name).unwrap();
    let guid = CString::new(kind.guid()).unwrap();
    let uri = resource_uri();
    unsafe {
        fmi2Instantiate(
            name.as_ptr(),
            1,
            guid.as_ptr(),
            uri.as_ptr(),
            functions,
            0,
            0,
        )
    }
}

/// StickSlipBeam's fidelity.level (an enumeration) at its modal item: fast to set up.
pub(super) unsafe fn set_modal(c: fmi2Component) {
    ok(
        fmi2SetInteger(
            c,
            &vr::<StickSlipBeam>("fidelity.level"),
            1,
            &FidelityLevel::Modal.code(),
        ),
        "fmi2SetInteger(fidelity.level)",
    );
}

pub(super) fn ok(status: fmi2Status, what: &str) {
    assert_eq!(status, OK, "{what} while driving the instance");
}

/// One instance in one state, with an FMU state taken right after instantiation (and its
/// bytes) for the state-function probes.
pub(super) struct Fixture {
    pub(super) kind: FmuKind,
    /// Boxed: the logger's environment pointer must not move.
    pub(super) log: Box<Log>,
    /// Kept alive while the instance lives (FMI 2.0 lets the FMU keep the pointer).
    pub(super) _functions: Box<fmi2CallbackFunctions>,
    /// NULL once fmi2FreeInstance was probed.
    pub(super) c: fmi2Component,
    pub(super) saved: fmi2FMUstate,
    pub(super) bytes: Vec<c_char>,
    /// States the probes created, freed on drop.
    pub(super) extra: Vec<fmi2FMUstate>,
    /// The instance's time (s).
    pub(super) time: f64,
}

impl Fixture {
    pub(super) fn new(kind: FmuKind) -> Fixture {
        let log = Box::new(Log::default());
        let functions = Box::new(callbacks(&log));
        let c = instantiate(kind, "matrix", &functions);
        assert!(!c.is_null(), "fmi2Instantiate of {kind:?}: {:?}", log);
        Fixture {
            kind,
            log,
            _functions: functions,
            c,
            saved: null_mut(),
            bytes: Vec::new(),
            extra: Vec::new(),
            time: 0.0,
        }
    }

    pub(super) fn take_log(&self) -> Vec<Entry> {
        std::mem::take(&mut *self.log.lock().unwrap())
    }

    /// From instantiated to stepComplete at t = H.
    pub(super) unsafe fn initialize_and_step(&mut self) {
        let c = self.c;
        if self.kind == FmuKind::StickSlipBeam {
            set_modal(c);
        }
        ok(
            fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
            "fmi2SetupExperiment",
        );
        ok(
            fmi2EnterInitializationMode(c),
            "fmi2EnterInitializationMode",
        );
        ok(fmi2ExitInitializationMode(c), "fmi2ExitInitializationMode");
        ok(fmi2DoStep(c, 0.0, H, 1), "fmi2DoStep");
        self.time = H;
    }

    /// A fresh instance driven into `state`.
    pub(super) fn in_state(kind: FmuKind, state: State) -> Fixture {
        let mut f = Fixture::new(kind);
        let c = f.c;
        unsafe {
            if kind == FmuKind::StickSlipBeam {
                set_modal(c);
            }
            ok(fmi2GetFMUstate(c, &mut f.saved), "fmi2GetFMUstate");
            f.bytes = serialize(c, f.saved);
            match state {
                State::Instantiated => {}
                State::InitializationMode => {
                    ok(
                        fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
                        "fmi2SetupExperiment",
                    );
                    ok(
                        fmi2EnterInitializationMode(c),
                        "fmi2EnterInitializationMode",
                    );
                }
                State::StepComplete => f.initialize_and_step(),
                State::Terminated => {
                    f.initialize_and_step();
                    ok(fmi2Terminate(c), "fmi2Terminate");
                }
                State::Error => {
                    f.initialize_and_step();
                    // A communication point that is not the FMU's time.
                    assert_eq!(fmi2DoStep(c, 1.0, H, 1), ERROR);
                }
                State::StepFailed => {
                    f.initialize_and_step();
                    enter_step_failed(c);
                }
            }
        }
        f.take_log();
        f
    }
}

impl Drop for Fixture {
    fn drop(&mut self) {
        if self.c.is_null() {
            return;
        }
        unsafe {
            for mut s in self.extra.drain(..).chain([self.saved]) {
                if !s.is_null() {
                    fmi2FreeFMUstate(self.c, &mut s);
                }
            }
            fmi2FreeInstance(self.c);
        }
    }
}

pub(super) unsafe fn serialize(c: fmi2Component, state: fmi2FMUstate) -> Vec<c_char> {
    let mut size = 0;
    ok(
        fmi2SerializedFMUstateSize(c, state, &mut size),
        "fmi2SerializedFMUstateSize",
    );
    let mut bytes = vec![0 as c_char; size];
    ok(
        fmi2SerializeFMUstate(c, state, bytes.as_mut_ptr(), size),
        "fmi2SerializeFMUstate",
    );
    bytes
}

/// stepComplete -> stepFailed: the instance's own state with its mode changed, restored.
pub(super) unsafe fn enter_step_failed(c: fmi2Component) {
    let mut state = null_mut();
    ok(fmi2GetFMUstate(c, &mut state), "fmi2GetFMUstate");
    let bytes: Vec<u8> = serialize(c, state).iter().map(|&b| b as u8).collect();
    let mut json: serde_json::Value =
        serde_json::from_slice(stickslip_tests::state_json(&bytes)).unwrap();
    assert_eq!(json["mode"], "step-complete");
    json["mode"] = "step-failed".into();
    let edited = stickslip_fmi::instance::with_checksum(&serde_json::to_vec(&json).unwrap());
    let mut failed = null_mut();
    ok(
        fmi2DeSerializeFMUstate(
            c,
            edited.as_ptr() as *const c_char,
            edited.len(),
            &mut failed,
        ),
        "fmi2DeSerializeFMUstate",
    );
    ok(fmi2SetFMUstate(c, failed), "fmi2SetFMUstate(step-failed)");
    ok(fmi2FreeFMUstate(c, &mut state), "fmi2FreeFMUstate");
    ok(fmi2FreeFMUstate(c, &mut failed), "fmi2FreeFMUstate");
}
