//! Every FMI 2.0 function in every state an instance can reach, through the C ABI.
//!
//! For each FMU, each state of the co-simulation state machine and each of the 34
//! functions, a fresh instance is driven into the state and the function is called once.
//! The expected answer comes from the standard's table of allowed calls (FMI 2.0.x,
//! section 4.2.4, the table after the co-simulation state chart), written down in
//! `STANDARD` below, not taken from the implementation (`Call::allowed_in`). Where this
//! FMU answers differently on purpose, `UNSUPPORTED` says so and why.
//!
//! Each cell checks:
//! - the returned status;
//! - an fmi2Error is explained by a message in category logStatusError that names the
//!   function and, for a call in the wrong state, the state;
//! - an allowed call logs no error;
//! - every logger call uses the format "%s";
//! - afterwards the instance still resets and steps (no cell leaves it wedged).
//!
//! `cargo test --release -p stickslip-tests --test fmu call_matrix -- --nocapture` prints
//! the matrix.

use std::ffi::{c_char, c_void, CString};
use std::ptr::null_mut;
use stickslip::choice::Choice;
use stickslip::friction::LawChoice;
use stickslip::scene::FidelityLevel;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::ffi2::*;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::FmuKind;

use stickslip_tests::fmi_log::{owned, record, Entry, Log};
use stickslip_tests::vr;

const OK: fmi2Status = 0;
const DISCARD: fmi2Status = 2;
const ERROR: fmi2Status = 3;

/// Communication step of the probes (s).
const H: f64 = 1e-3;

// ---------------------------------------------------------------------------------------
// The standard.

/// The states of the co-simulation state machine that an instance of these FMUs can be
/// in. The standard's table has four more columns, none reachable here:
/// - start/end: there is no instance yet (fmi2Instantiate is probed in every column as
///   the creation of a second instance, allowed since canBeInstantiatedOnlyOncePerProcess
///   is false);
/// - stepInProgress and stepCanceled: canRunAsynchronuously is false, so fmi2DoStep never
///   returns fmi2Pending;
/// - fatal: no function returns fmi2Fatal.
///
/// stepFailed is entered only after fmi2DoStep returned fmi2Discard, which this FMU never
/// does. It is reached here by restoring a serialized FMU state whose mode says
/// step-failed, so that the column is checked all the same.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
}

const STATES: [State; 6] = [
    State::Instantiated,
    State::InitializationMode,
    State::StepComplete,
    State::StepFailed,
    State::Terminated,
    State::Error,
];

impl State {
    fn column(self) -> usize {
        STATES.iter().position(|&s| s == self).unwrap()
    }

    /// The name a refusal must mention.
    fn name(self) -> &'static str {
        match self {
            State::Instantiated => "Instantiated",
            State::InitializationMode => "InitializationMode",
            State::StepComplete => "StepComplete",
            State::StepFailed => "StepFailed",
            State::Terminated => "Terminated",
            State::Error => "Error",
        }
    }

    fn header(self) -> &'static str {
        match self {
            State::Instantiated => "instantiated",
            State::InitializationMode => "init mode",
            State::StepComplete => "stepComplete",
            State::StepFailed => "stepFailed",
            State::Terminated => "terminated",
            State::Error => "error",
        }
    }
}

/// FMI 2.0.x section 4.2.4: which function may be called in which state, for the
/// columns in `STATES` (instantiated, initialization mode, stepComplete, stepFailed,
/// terminated, error). 'x' = allowed, '.' = not allowed. Cells with a footnote count as
/// allowed:
/// - Get* in initialization mode: outputs (and states); in stepFailed and error the
///   values are for debugging only;
/// - Set* in instantiated: variables with initial = exact or approx; in initialization
///   mode: initial = exact or inputs; in stepComplete: inputs and tunable parameters.
///   The probes pick such variables (`Probe`), or make an empty request (nvr = 0) when
///   the FMU has no variable of that type that the footnote admits;
/// - fmi2GetFMUstate, fmi2GetDirectionalDerivative and fmi2GetRealOutputDerivatives in
///   stepFailed and error: allowed, values for debugging only.
///
/// fmi2Instantiate belongs to the start state only; see `State`.
/// fmi2CancelStep is allowed only in stepInProgress, which is never reached.
const STANDARD: [(&str, &str); 34] = [
    ("fmi2GetTypesPlatform", "xxxxxx"),
    ("fmi2GetVersion", "xxxxxx"),
    ("fmi2SetDebugLogging", "xxxxxx"),
    ("fmi2Instantiate", "xxxxxx"),
    ("fmi2FreeInstance", "xxxxxx"),
    ("fmi2SetupExperiment", "x....."),
    ("fmi2EnterInitializationMode", "x....."),
    ("fmi2ExitInitializationMode", ".x...."),
    ("fmi2Terminate", "..xx.."),
    ("fmi2Reset", "xxxxxx"),
    ("fmi2GetReal", ".xxxxx"),
    ("fmi2GetInteger", ".xxxxx"),
    ("fmi2GetBoolean", ".xxxxx"),
    ("fmi2GetString", ".xxxxx"),
    ("fmi2SetReal", "xxx..."),
    ("fmi2SetInteger", "xxx..."),
    ("fmi2SetBoolean", "xxx..."),
    ("fmi2SetString", "xxx..."),
    ("fmi2GetFMUstate", "xxxxxx"),
    ("fmi2SetFMUstate", "xxxxxx"),
    ("fmi2FreeFMUstate", "xxxxxx"),
    ("fmi2SerializedFMUstateSize", "xxxxxx"),
    ("fmi2SerializeFMUstate", "xxxxxx"),
    ("fmi2DeSerializeFMUstate", "xxxxxx"),
    ("fmi2GetDirectionalDerivative", ".xxxxx"),
    ("fmi2SetRealInputDerivatives", "xxx..."),
    ("fmi2GetRealOutputDerivatives", "..xxxx"),
    ("fmi2DoStep", "..x..."),
    ("fmi2CancelStep", "......"),
    ("fmi2GetStatus", "..xxx."),
    ("fmi2GetRealStatus", "..xxx."),
    ("fmi2GetIntegerStatus", "..xxx."),
    ("fmi2GetBooleanStatus", "..xxx."),
    ("fmi2GetStringStatus", "..xxx."),
];

/// Our decision (docs/fmu-reference.md, "Behaviour"): a function whose capability flag in
/// modelDescription.xml is false returns fmi2Error in every state and logs the flag.
/// The standard forbids the importer to call these functions at all when the flag is
/// false, so where its table allows them (marked * in the printed matrix) this is a
/// deliberate difference, not a refusal of a legal call sequence. NeuralFriction provides
/// directional derivatives (`PROVIDED`): for it that row is the standard's.
const UNSUPPORTED: [(&str, &str); 4] = [
    (
        "fmi2GetDirectionalDerivative",
        "providesDirectionalDerivative",
    ),
    ("fmi2SetRealInputDerivatives", "canInterpolateInputs"),
    ("fmi2GetRealOutputDerivatives", "maxOutputDerivativeOrder"),
    // Not a difference: the table allows it only in stepInProgress, never reached.
    ("fmi2CancelStep", "canRunAsynchronuously"),
];

/// Status kinds this FMU cannot report, for which FMI 2.0.x section 4.2.3 says: "If a
/// status is required which cannot be retrieved by the slave it returns fmi2Discard."
/// The probes ask fmi2GetStatus for fmi2DoStepStatus (there is never a pending step),
/// fmi2GetIntegerStatus for fmi2DoStepStatus (no fmi2StatusKind has an Integer value) and
/// fmi2GetStringStatus for fmi2PendingStatus. fmi2GetRealStatus(fmi2LastSuccessfulTime)
/// and fmi2GetBooleanStatus(fmi2Terminated) are available and answer fmi2OK.
const DISCARDED_STATUS: [&str; 3] = [
    "fmi2GetStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetStringStatus",
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Expect {
    /// Allowed: fmi2OK (for the functions without a status: returned what the standard
    /// says they return).
    Ok,
    /// Allowed: fmi2Discard, a status this FMU cannot provide.
    Discard,
    /// Not allowed in this state: fmi2Error, logged with the function and the state.
    Refused,
    /// Capability flag false: fmi2Error, logged with the function and the flag.
    Unsupported { flag: &'static str },
}

fn standard_allows(function: &str, state: State) -> bool {
    let (_, row) = STANDARD
        .iter()
        .find(|(f, _)| *f == function)
        .unwrap_or_else(|| panic!("{function} is not in the table"));
    row.as_bytes()[state.column()] == b'x'
}

/// The functions of UNSUPPORTED that an FMU does provide.
const PROVIDED: [(FmuKind, &str); 1] = [(FmuKind::NeuralFriction, "fmi2GetDirectionalDerivative")];

fn expected(kind: FmuKind, function: &str, state: State) -> Expect {
    let provided = PROVIDED.contains(&(kind, function));
    if let Some((_, flag)) = UNSUPPORTED.iter().find(|(f, _)| *f == function) {
        if !provided {
            return Expect::Unsupported { flag };
        }
    }
    if !standard_allows(function, state) {
        Expect::Refused
    } else if DISCARDED_STATUS.contains(&function) {
        Expect::Discard
    } else {
        Expect::Ok
    }
}

// ---------------------------------------------------------------------------------------
// The importer side: logger, instances driven into each state.

fn callbacks(log: &Log) -> fmi2CallbackFunctions {
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
fn resource_uri() -> CString {
    let dir = stickslip_tests::weights_dir();
    CString::new(format!("file://{}", dir.display())).unwrap()
}

fn instantiate(kind: FmuKind, name: &str, functions: &fmi2CallbackFunctions) -> fmi2Component {
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
unsafe fn set_modal(c: fmi2Component) {
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

fn ok(status: fmi2Status, what: &str) {
    assert_eq!(status, OK, "{what} while driving the instance");
}

/// One instance in one state, with an FMU state taken right after instantiation (and its
/// bytes) for the state-function probes.
struct Fixture {
    kind: FmuKind,
    /// Boxed: the logger's environment pointer must not move.
    log: Box<Log>,
    /// Kept alive while the instance lives (FMI 2.0 lets the FMU keep the pointer).
    _functions: Box<fmi2CallbackFunctions>,
    /// NULL once fmi2FreeInstance was probed.
    c: fmi2Component,
    saved: fmi2FMUstate,
    bytes: Vec<c_char>,
    /// States the probes created, freed on drop.
    extra: Vec<fmi2FMUstate>,
    /// The instance's time (s).
    time: f64,
}

impl Fixture {
    fn new(kind: FmuKind) -> Fixture {
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

    fn take_log(&self) -> Vec<Entry> {
        std::mem::take(&mut *self.log.lock().unwrap())
    }

    /// From instantiated to stepComplete at t = H.
    unsafe fn initialize_and_step(&mut self) {
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
    fn in_state(kind: FmuKind, state: State) -> Fixture {
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

unsafe fn serialize(c: fmi2Component, state: fmi2FMUstate) -> Vec<c_char> {
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
unsafe fn enter_step_failed(c: fmi2Component) {
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

// ---------------------------------------------------------------------------------------
// The probes: one call of each function with valid arguments.

/// Variables a probe reads or writes, per FMU and type. `None`: the FMU has no variable
/// of that type that the standard's footnote admits, so the probe makes an empty request.
struct Probe {
    get_real: u32,
    get_integer: Option<u32>,
    get_boolean: Option<u32>,
    get_string: Option<u32>,
    /// Before fmi2ExitInitializationMode: parameters (initial = exact), set to their
    /// start values.
    parameter_real: (u32, f64),
    parameter_integer: Option<(u32, i32)>,
    parameter_boolean: Option<(u32, fmi2Boolean)>,
    parameter_string: Option<(u32, &'static str)>,
    /// Afterwards: an input, set to its start value.
    input_real: (u32, f64),
    output_real: u32,
}

fn probe_variables(kind: FmuKind) -> Probe {
    match kind {
        FmuKind::StickSlipBeam => {
            let vr = vr::<StickSlipBeam>;
            Probe {
                get_real: vr("tip_deflection"),
                get_integer: Some(vr("transitions")),
                get_boolean: Some(vr("stick")),
                get_string: Some(vr("friction.weights")),
                parameter_real: (vr("time.step"), 1e-4),
                parameter_integer: Some((vr("fidelity.level"), FidelityLevel::Modal.code())),
                parameter_boolean: Some((vr("fidelity.static_correction"), 1)),
                parameter_string: Some((vr("friction.weights"), "paper-plain.json")),
                input_real: (vr("belt_speed"), 0.02),
                output_real: vr("tip_deflection"),
            }
        }
        // No Boolean variable.
        FmuKind::NeuralFriction => {
            let vr = vr::<NeuralFriction>;
            Probe {
                get_real: vr("friction_force"),
                get_integer: Some(vr("law")),
                get_boolean: None,
                get_string: Some(vr("weights")),
                parameter_real: (vr("static_coefficient"), 0.5),
                parameter_integer: Some((vr("law"), LawChoice::Neural.code())),
                parameter_boolean: None,
                parameter_string: Some((vr("weights"), "paper-plain.json")),
                input_real: (vr("sliding_velocity"), 0.0),
                output_real: vr("friction_force"),
            }
        }
    }
}

/// (value references, count) of an optional single variable.
fn one(vr: &Option<u32>) -> (*const u32, usize) {
    match vr {
        Some(v) => (v as *const u32, 1),
        None => ([].as_ptr(), 0),
    }
}

/// Calls `function` once. Returns its status (for functions without one: OK when they
/// returned what the standard says, ERROR otherwise) and any complaint about the values
/// it returned.
unsafe fn call(f: &mut Fixture, function: &str, state: State) -> (fmi2Status, Option<String>) {
    let c = f.c;
    let p = probe_variables(f.kind);
    let before_exit = matches!(state, State::Instantiated | State::InitializationMode);
    let mut complaint = None;
    let status = match function {
        "fmi2GetTypesPlatform" => {
            let s = unsafe { owned(fmi2GetTypesPlatform()) };
            if s == "default" {
                OK
            } else {
                complaint = Some(format!("returned {s:?}"));
                ERROR
            }
        }
        "fmi2GetVersion" => {
            let s = unsafe { owned(fmi2GetVersion()) };
            if s == "2.0" {
                OK
            } else {
                complaint = Some(format!("returned {s:?}"));
                ERROR
            }
        }
        "fmi2SetDebugLogging" => {
            let category = c"logEvents".as_ptr();
            fmi2SetDebugLogging(c, 1, 1, &category)
        }
        "fmi2Instantiate" => {
            let log = Log::default();
            let functions = callbacks(&log);
            let second = instantiate(f.kind, "second", &functions);
            if second.is_null() {
                complaint = Some(format!("no second instance: {:?}", log));
                ERROR
            } else {
                fmi2FreeInstance(second);
                OK
            }
        }
        "fmi2FreeInstance" => {
            fmi2FreeInstance(c);
            f.c = null_mut();
            f.saved = null_mut();
            OK
        }
        "fmi2SetupExperiment" => fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
        "fmi2EnterInitializationMode" => fmi2EnterInitializationMode(c),
        "fmi2ExitInitializationMode" => fmi2ExitInitializationMode(c),
        "fmi2Terminate" => fmi2Terminate(c),
        "fmi2Reset" => fmi2Reset(c),
        "fmi2GetReal" => {
            let mut v = 0.0;
            fmi2GetReal(c, &p.get_real, 1, &mut v)
        }
        "fmi2GetInteger" => {
            let (vr, n) = one(&p.get_integer);
            let mut v = [0; 1];
            fmi2GetInteger(c, vr, n, v.as_mut_ptr())
        }
        "fmi2GetBoolean" => {
            let (vr, n) = one(&p.get_boolean);
            let mut v = [0; 1];
            fmi2GetBoolean(c, vr, n, v.as_mut_ptr())
        }
        "fmi2GetString" => {
            let (vr, n) = one(&p.get_string);
            let mut v = [std::ptr::null(); 1];
            fmi2GetString(c, vr, n, v.as_mut_ptr())
        }
        "fmi2SetReal" => {
            let (vr, v) = if before_exit {
                p.parameter_real
            } else {
                p.input_real
            };
            fmi2SetReal(c, &vr, 1, &v)
        }
        "fmi2SetInteger" => match p.parameter_integer.filter(|_| before_exit) {
            Some((vr, v)) => fmi2SetInteger(c, &vr, 1, &v),
            None => fmi2SetInteger(c, [].as_ptr(), 0, [].as_ptr()),
        },
        "fmi2SetBoolean" => match p.parameter_boolean.filter(|_| before_exit) {
            Some((vr, v)) => fmi2SetBoolean(c, &vr, 1, &v),
            None => fmi2SetBoolean(c, [].as_ptr(), 0, [].as_ptr()),
        },
        "fmi2SetString" => match p.parameter_string.filter(|_| before_exit) {
            Some((vr, v)) => {
                let v = CString::new(v).unwrap();
                fmi2SetString(c, &vr, 1, &v.as_ptr())
            }
            None => fmi2SetString(c, [].as_ptr(), 0, [].as_ptr()),
        },
        "fmi2GetFMUstate" => {
            let mut s = null_mut();
            let status = fmi2GetFMUstate(c, &mut s);
            f.extra.push(s);
            status
        }
        "fmi2SetFMUstate" => fmi2SetFMUstate(c, f.saved),
        "fmi2FreeFMUstate" => {
            let status = fmi2FreeFMUstate(c, &mut f.saved);
            if status == OK && !f.saved.is_null() {
                complaint = Some("the state pointer was not set to NULL".into());
            }
            status
        }
        "fmi2SerializedFMUstateSize" => {
            let mut size = 0;
            let status = fmi2SerializedFMUstateSize(c, f.saved, &mut size);
            if status == OK && size != f.bytes.len() {
                complaint = Some(format!("size {size}, expected {}", f.bytes.len()));
            }
            status
        }
        "fmi2SerializeFMUstate" => {
            let mut bytes = vec![0 as c_char; f.bytes.len()];
            let status = fmi2SerializeFMUstate(c, f.saved, bytes.as_mut_ptr(), bytes.len());
            if status == OK && bytes != f.bytes {
                complaint = Some("other bytes than right after instantiation".into());
            }
            status
        }
        "fmi2DeSerializeFMUstate" => {
            let mut s = null_mut();
            let status = fmi2DeSerializeFMUstate(c, f.bytes.as_ptr(), f.bytes.len(), &mut s);
            f.extra.push(s);
            status
        }
        "fmi2GetDirectionalDerivative" => {
            let mut d = 0.0;
            fmi2GetDirectionalDerivative(c, &p.output_real, 1, &p.input_real.0, 1, &1.0, &mut d)
        }
        "fmi2SetRealInputDerivatives" => {
            fmi2SetRealInputDerivatives(c, &p.input_real.0, 1, &1, &0.0)
        }
        "fmi2GetRealOutputDerivatives" => {
            let mut d = 0.0;
            fmi2GetRealOutputDerivatives(c, &p.output_real, 1, &1, &mut d)
        }
        "fmi2DoStep" => fmi2DoStep(c, f.time, H, 1),
        "fmi2CancelStep" => fmi2CancelStep(c),
        "fmi2GetStatus" => {
            let mut v = OK;
            fmi2GetStatus(c, 0, &mut v)
        }
        "fmi2GetRealStatus" => {
            let mut t = -1.0;
            let status = fmi2GetRealStatus(c, 2, &mut t);
            if status == OK && t != f.time {
                complaint = Some(format!("last successful time {t}, expected {}", f.time));
            }
            status
        }
        "fmi2GetIntegerStatus" => {
            let mut v = 0;
            fmi2GetIntegerStatus(c, 0, &mut v)
        }
        "fmi2GetBooleanStatus" => {
            let mut v = -1;
            let status = fmi2GetBooleanStatus(c, 3, &mut v);
            if status == OK && v != 0 {
                complaint = Some(format!("fmi2Terminated = {v}, expected fmi2False"));
            }
            status
        }
        "fmi2GetStringStatus" => {
            let mut v = std::ptr::null();
            fmi2GetStringStatus(c, 1, &mut v)
        }
        other => panic!("no probe for {other}"),
    };
    (status, complaint)
}

// ---------------------------------------------------------------------------------------
// Checking a cell.

/// Whether `token`, the function name a message starts with, names `function`. The FMU
/// names families with a wildcard: "fmi2Get*", "fmi2Set*", "fmi2Get*Status",
/// "fmi2(De)SerializeFMUstate".
fn names(token: &str, function: &str) -> bool {
    if token == function {
        return true;
    }
    if let Some((before, after)) = token.split_once("(De)") {
        return [format!("{before}{after}"), format!("{before}De{after}")]
            .iter()
            .any(|t| t == function);
    }
    match token.split_once('*') {
        Some((prefix, suffix)) => {
            function.len() >= prefix.len() + suffix.len()
                && function.starts_with(prefix)
                && function.ends_with(suffix)
        }
        None => false,
    }
}

/// Checks what one call logged; returns the problems.
fn check_log(function: &str, state: State, expect: Expect, log: &[Entry]) -> Vec<String> {
    let mut problems = Vec::new();
    if let Some(e) = log.iter().find(|e| e.format != "%s") {
        problems.push(format!("logger called with format {:?}", e.format));
    }
    let errors: Vec<&Entry> = log.iter().filter(|e| e.status == ERROR).collect();
    let explains = |e: &Entry| {
        let token = e.message.split(':').next().unwrap_or("");
        if e.category != "logStatusError" || !names(token, function) {
            return false;
        }
        match expect {
            Expect::Refused => {
                // The state, before any list of allowed states.
                let head = e.message.split('[').next().unwrap_or("");
                e.message.contains("illegal call sequence") && head.contains(state.name())
            }
            Expect::Unsupported { flag } => {
                e.message.contains("not supported") && e.message.contains(flag)
            }
            Expect::Ok | Expect::Discard => false,
        }
    };
    match expect {
        Expect::Refused | Expect::Unsupported { .. } => {
            if !errors.iter().copied().any(explains) {
                problems.push(format!("no message explains the refusal; logged {log:?}"));
            }
        }
        Expect::Ok | Expect::Discard => {
            if !errors.is_empty() {
                problems.push(format!("an allowed call logged errors: {errors:?}"));
            }
        }
    }
    problems
}

/// After the probe: the instance resets and steps again.
unsafe fn still_usable(f: &mut Fixture) -> Result<(), String> {
    if f.c.is_null() {
        return Ok(());
    }
    if fmi2Reset(f.c) != OK {
        return Err("fmi2Reset after the probe failed".into());
    }
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        f.initialize_and_step();
    }));
    result.map_err(|_| format!("no restart after fmi2Reset: {:?}", f.take_log()))
}

fn status_name(status: fmi2Status) -> &'static str {
    match status {
        0 => "ok",
        1 => "warn",
        2 => "disc",
        3 => "ERR",
        4 => "FATAL",
        _ => "???",
    }
}

struct Outcome {
    function: &'static str,
    state: State,
    expect: Expect,
    status: fmi2Status,
    problems: Vec<String>,
}

fn run_cell(kind: FmuKind, function: &'static str, state: State) -> Outcome {
    let expect = expected(kind, function, state);
    let mut f = Fixture::in_state(kind, state);
    let (status, complaint) = unsafe { call(&mut f, function, state) };
    let log = f.take_log();
    let mut problems = Vec::new();
    let wanted = match expect {
        Expect::Ok => OK,
        Expect::Discard => DISCARD,
        Expect::Refused | Expect::Unsupported { .. } => ERROR,
    };
    if status != wanted {
        problems.push(format!(
            "returned {}, expected {}",
            status_name(status),
            status_name(wanted)
        ));
    }
    problems.extend(complaint);
    problems.extend(check_log(function, state, expect, &log));
    if let Err(e) = unsafe { still_usable(&mut f) } {
        problems.push(e);
    }
    Outcome {
        function,
        state,
        expect,
        status,
        problems,
    }
}

fn cell_text(o: &Outcome) -> String {
    if !o.problems.is_empty() {
        return format!("!!{}", status_name(o.status));
    }
    match o.expect {
        Expect::Ok => "ok".into(),
        Expect::Discard => "disc".into(),
        Expect::Refused => "ERR".into(),
        Expect::Unsupported { .. } if standard_allows(o.function, o.state) => "n/s*".into(),
        Expect::Unsupported { .. } => "n/s".into(),
    }
}

/// Runs and prints the whole matrix of one FMU; fails with every broken cell.
fn matrix(kind: FmuKind) {
    let start = std::time::Instant::now();
    let outcomes: Vec<Outcome> = STANDARD
        .iter()
        .flat_map(|&(function, _)| STATES.map(|state| run_cell(kind, function, state)))
        .collect();

    let mut text = format!("\n{kind:?}: every function in every state\n");
    text += &format!("{:30}", "");
    for s in STATES {
        text += &format!("{:>14}", s.header());
    }
    text += "\n";
    for row in outcomes.chunks(STATES.len()) {
        text += &format!("{:30}", row[0].function);
        for o in row {
            text += &format!("{:>14}", cell_text(o));
        }
        text += "\n";
    }
    let count = |p: fn(&Outcome) -> bool| outcomes.iter().filter(|o| p(o)).count();
    let deviations = count(|o| {
        matches!(o.expect, Expect::Unsupported { .. }) && standard_allows(o.function, o.state)
    });
    text += &format!(
        "{} cells: {} ok, {} discard, {} refused as the standard says, {} not supported \
         ({} of them allowed by the table: capability flag false, marked *), {} broken; {:.2} s\n\
         ok/disc: allowed, answered fmi2OK/fmi2Discard; ERR: fmi2Error, logged \"illegal call \
         sequence\" with the function and state; n/s: fmi2Error, logged \"not supported\" with \
         the capability flag; !!: the answer differs from the expectation\n",
        outcomes.len(),
        count(|o| o.problems.is_empty() && o.expect == Expect::Ok),
        count(|o| o.problems.is_empty() && o.expect == Expect::Discard),
        count(|o| o.problems.is_empty() && o.expect == Expect::Refused),
        count(|o| matches!(o.expect, Expect::Unsupported { .. })),
        deviations,
        count(|o| !o.problems.is_empty()),
        start.elapsed().as_secs_f64(),
    );
    println!("{text}");

    let broken: Vec<String> = outcomes
        .iter()
        .filter(|o| !o.problems.is_empty())
        .map(|o| format!("{} in {:?}: {}", o.function, o.state, o.problems.join("; ")))
        .collect();
    assert!(
        broken.is_empty(),
        "{kind:?}: {} cells differ from the standard:\n{}",
        broken.len(),
        broken.join("\n")
    );
}

#[test]
fn stick_slip_beam_answers_every_call_in_every_state_as_the_standard_says() {
    matrix(FmuKind::StickSlipBeam);
}

#[test]
fn neural_friction_answers_every_call_in_every_state_as_the_standard_says() {
    matrix(FmuKind::NeuralFriction);
}

/// The table above is complete: 34 distinct functions, each with a probe, and every
/// exported fmi2 function of the library is among them (fmu-build's symbols test checks
/// the binary exports exactly these).
#[test]
fn the_table_covers_the_34_functions() {
    let mut names: Vec<&str> = STANDARD.iter().map(|(f, _)| *f).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), 34);
    // The FMI 2.0 interface's folder, every file of it.
    let source = [
        include_str!("../../src/fmi/src/ffi2/mod.rs"),
        include_str!("../../src/fmi/src/ffi2/values.rs"),
        include_str!("../../src/fmi/src/ffi2/state.rs"),
        include_str!("../../src/fmi/src/ffi2/step.rs"),
    ]
    .concat();
    let mut exported: Vec<&str> = source
        .split("fn ")
        .skip(1)
        .filter_map(|rest| rest.split('(').next())
        .filter(|name| name.starts_with("fmi2"))
        .collect();
    // Functions generated by the getter!, setter!, unavailable_status! and mode_change!
    // macros.
    for line in source.lines() {
        for mac in [
            "getter!(",
            "setter!(",
            "unavailable_status!(",
            "mode_change!(",
        ] {
            if let Some(rest) = line.trim().strip_prefix(mac) {
                exported.extend(rest.split([',', ' ']).next());
            }
        }
    }
    exported.sort_unstable();
    exported.dedup();
    assert_eq!(exported, names);
}

/// The two unreachable-by-stepping states are what the matrix thinks they are: a
/// restored step-failed state refuses fmi2DoStep but accepts fmi2Terminate, and an
/// instance in the Error state comes back through fmi2SetFMUstate.
#[test]
fn step_failed_and_error_states_are_entered_as_described() {
    for kind in FmuKind::ALL {
        let f = Fixture::in_state(kind, State::StepFailed);
        unsafe {
            assert_eq!(fmi2Terminate(f.c), OK);
        }
        let f = Fixture::in_state(kind, State::Error);
        unsafe {
            assert_eq!(fmi2DoStep(f.c, f.time, H, 1), ERROR);
            assert_eq!(fmi2SetFMUstate(f.c, f.saved), OK);
            // Back to the state right after instantiation.
            assert_eq!(fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0), OK);
        }
    }
}
