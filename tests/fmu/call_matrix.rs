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
//!
//! The instances driven into each state are in `fixture`, the one call of each function in
//! `probes`; the standard, the check of a cell and the tests are here.

use std::ffi::{c_char, c_void, CString};
use std::ptr::null_mut;
use stickslip::choice::Choice;
use stickslip::scene::FidelityLevel;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::ffi2::*;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::friction::NeuralFrictionLaw;
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

mod fixture;
mod probes;
use fixture::*;
use probes::*;
