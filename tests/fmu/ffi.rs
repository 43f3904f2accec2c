//! The C interface itself: NULL arguments, GUID and type checks, the logger format,
//! strings and FMU state through raw pointers, unsupported functions.

use std::ffi::{c_char, c_void, CStr, CString};
use std::ptr::{null, null_mut};
use std::sync::Mutex;
use stickslip_fmi::ffi2::*;
use stickslip_fmi::FmuKind;

const OK: fmi2Status = 0;
const DISCARD: fmi2Status = 2;
const ERROR: fmi2Status = 3;

/// (format, message) of every logger call, per environment (one Vec per test).
type Messages = Mutex<Vec<(String, String)>>;

/// A non-variadic function with the logger's six arguments. Called through the
/// variadic type, it receives the same registers on x86-64 System V and AArch64 Linux.
extern "C" fn record(
    environment: fmi2ComponentEnvironment,
    _instance: fmi2String,
    _status: fmi2Status,
    _category: fmi2String,
    format: fmi2String,
    message: *const c_char,
) {
    let messages = unsafe { &*(environment as *const Messages) };
    let text = |p: *const c_char| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned();
    messages.lock().unwrap().push((text(format), text(message)));
}

fn callbacks(messages: &Messages) -> fmi2CallbackFunctions {
    type Plain = extern "C" fn(
        fmi2ComponentEnvironment,
        fmi2String,
        fmi2Status,
        fmi2String,
        fmi2String,
        *const c_char,
    );
    // SAFETY: see `record`; the FMU always passes exactly one variadic argument.
    let logger: fmi2CallbackLogger = unsafe { std::mem::transmute::<Plain, _>(record) };
    fmi2CallbackFunctions {
        logger: Some(logger),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: messages as *const Messages as *mut c_void,
    }
}

fn resource_uri() -> CString {
    let dir = stickslip_tests::weights_dir();
    CString::new(format!("file://{}", dir.display())).unwrap()
}

fn instantiate(
    name: &str,
    guid: &str,
    fmu_type: i32,
    functions: &fmi2CallbackFunctions,
) -> fmi2Component {
    let name = CString::new(name).unwrap();
    let guid = CString::new(guid).unwrap();
    let uri = resource_uri();
    unsafe {
        fmi2Instantiate(
            name.as_ptr(),
            fmu_type,
            guid.as_ptr(),
            uri.as_ptr(),
            functions,
            0,
            0,
        )
    }
}

/// StickSlipBeam at modal fidelity (fidelity.level, vr 50, = 1), initialised, with no
/// stop time.
unsafe fn initialized_modal_beam(functions: &fmi2CallbackFunctions) -> fmi2Component {
    let c = instantiate("b", &FmuKind::StickSlipBeam.guid(), 1, functions);
    unsafe {
        assert_eq!(fmi2SetInteger(c, [50u32].as_ptr(), 1, [1].as_ptr()), OK);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
    }
    c
}

fn logged(messages: &Messages, needle: &str) -> bool {
    messages
        .lock()
        .unwrap()
        .iter()
        .any(|(_, m)| m.contains(needle))
}

#[test]
fn version_and_platform() {
    let text = |p| unsafe { CStr::from_ptr(p) }.to_str().unwrap();
    assert_eq!(text(fmi2GetVersion()), "2.0");
    assert_eq!(text(fmi2GetTypesPlatform()), "default");
}

#[test]
fn instantiation_checks_guid_type_and_arguments() {
    let messages = Messages::default();
    let functions = callbacks(&messages);
    let c = instantiate("x", "{not-ours}", 1, &functions);
    assert!(c.is_null());
    assert!(logged(&messages, "GUID \"{not-ours}\" does not match"));
    let c = instantiate("x", &FmuKind::StickSlipBeam.guid(), 0, &functions);
    assert!(c.is_null());
    assert!(logged(&messages, "co-simulation"));
    let guid = CString::new(FmuKind::StickSlipBeam.guid()).unwrap();
    let c = unsafe { fmi2Instantiate(c"x".as_ptr(), 1, guid.as_ptr(), null(), null(), 0, 0) };
    assert!(c.is_null(), "NULL callbacks");
    let c = unsafe { fmi2Instantiate(null(), 1, guid.as_ptr(), null(), &functions, 0, 0) };
    assert!(c.is_null(), "NULL instance name");
    assert!(logged(&messages, "instanceName"));
}

#[test]
fn percent_signs_reach_the_logger_verbatim() {
    let messages = Messages::default();
    let functions = callbacks(&messages);
    let c = instantiate("b", &FmuKind::StickSlipBeam.guid(), 1, &functions);
    assert!(!c.is_null());
    let weights_vr = [15u32];
    let hostile = CString::new("%s%n%d%%.json").unwrap();
    let model_vr = [10u32];
    unsafe {
        assert_eq!(fmi2SetInteger(c, model_vr.as_ptr(), 1, [3].as_ptr()), OK);
        assert_eq!(
            fmi2SetString(c, weights_vr.as_ptr(), 1, [hostile.as_ptr()].as_ptr()),
            OK
        );
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), ERROR);
        fmi2FreeInstance(c);
    }
    let all = messages.lock().unwrap();
    assert!(all.iter().all(|(format, _)| format == "%s"));
    assert!(
        all.iter()
            .any(|(_, m)| m.contains("%s%n%d%%.json: no such file")),
        "{all:?}"
    );
}

/// StickSlipBeam's `friction.weights` naming what is not a readable file: refused at
/// fmi2ExitInitializationMode with the reader's reason, the path once in the message
/// (the log used to repeat it: "weights file X: X: ..."); /dev/zero and a FIFO are
/// refused by their type, never read.
#[test]
fn a_weights_parameter_that_is_no_file_is_named_once_in_the_log() {
    let dir = std::env::temp_dir().join(format!("stickslip-ffi-weights-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let empty = dir.join("empty.json");
    std::fs::write(&empty, b"").unwrap();
    let folder = dir.join("folder.onnx");
    std::fs::create_dir_all(&folder).unwrap();
    let fifo = dir.join("fifo.json");
    let mut cases = vec![
        (dir.join("missing.json"), "no such file"),
        (folder, "is a directory, not a file"),
        (
            std::path::PathBuf::from("/dev/zero"),
            "is a character device, not a regular file",
        ),
        (empty, "the file is empty"),
    ];
    if std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        cases.push((fifo, "is a FIFO (named pipe), not a regular file"));
    } else {
        println!("note: skipped the FIFO case: mkfifo is not available");
    }
    for (path, reason) in cases {
        let messages = Messages::default();
        let functions = callbacks(&messages);
        let c = instantiate("b", &FmuKind::StickSlipBeam.guid(), 1, &functions);
        assert!(!c.is_null());
        let name = path.display().to_string();
        let weights = CString::new(name.as_str()).unwrap();
        unsafe {
            // friction.law = neural (code 3), friction.weights (value reference 15).
            assert_eq!(fmi2SetInteger(c, [10u32].as_ptr(), 1, [3].as_ptr()), OK);
            assert_eq!(
                fmi2SetString(c, [15u32].as_ptr(), 1, [weights.as_ptr()].as_ptr()),
                OK
            );
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            assert_eq!(fmi2ExitInitializationMode(c), ERROR);
            fmi2FreeInstance(c);
        }
        let all = messages.lock().unwrap();
        let expected = format!("weights file {name}: {reason}");
        let message = all
            .iter()
            .map(|(_, m)| m)
            .find(|m| m.contains(&expected))
            .unwrap_or_else(|| panic!("no message with {expected:?}: {all:?}"));
        assert_eq!(message.matches(&name).count(), 1, "{message}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn null_arguments_and_empty_requests() {
    let messages = Messages::default();
    let functions = callbacks(&messages);
    unsafe {
        assert_eq!(fmi2DoStep(null_mut(), 0.0, 1e-3, 0), ERROR);
        assert_eq!(fmi2Reset(null_mut()), ERROR);
        fmi2FreeInstance(null_mut());
        let c = instantiate("b", &FmuKind::StickSlipBeam.guid(), 1, &functions);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 1.2), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        // A fixed parameter may still be set in initialization mode.
        assert_eq!(fmi2SetInteger(c, [50u32].as_ptr(), 1, [1].as_ptr()), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        // nvr = 0 with NULL arrays is a valid empty request.
        assert_eq!(fmi2GetReal(c, null(), 0, null_mut()), OK);
        assert_eq!(fmi2SetReal(c, null(), 0, null()), OK);
        // nvr = 1 with NULL arrays is not.
        assert_eq!(fmi2GetReal(c, null(), 1, null_mut()), ERROR);
        assert!(logged(&messages, "vr or value is NULL"));
        fmi2FreeInstance(c);
    }
}

#[test]
fn strings_booleans_and_status_through_pointers() {
    let messages = Messages::default();
    let functions = callbacks(&messages);
    unsafe {
        let c = initialized_modal_beam(&functions);
        let mut s: fmi2String = null();
        assert_eq!(fmi2GetString(c, [15u32].as_ptr(), 1, &mut s), OK);
        assert_eq!(CStr::from_ptr(s).to_str().unwrap(), "paper-plain.json");
        let mut stick = -1;
        assert_eq!(fmi2GetBoolean(c, [205u32].as_ptr(), 1, &mut stick), OK);
        assert_eq!(stick, 1);
        for k in 0..10 {
            assert_eq!(fmi2DoStep(c, k as f64 * 0.05, 0.05, 1), OK);
        }
        let mut t = 0.0;
        assert_eq!(fmi2GetRealStatus(c, 2, &mut t), OK);
        assert!((t - 0.5).abs() < 1e-12);
        let mut terminated = -1;
        assert_eq!(fmi2GetBooleanStatus(c, 3, &mut terminated), OK);
        assert_eq!(terminated, 0);
        let mut status = 0;
        assert_eq!(fmi2GetStatus(c, 0, &mut status), DISCARD);
        assert_eq!(fmi2GetBoolean(c, [205u32].as_ptr(), 1, &mut stick), OK);
        assert_eq!(stick, 0, "slipping after breakaway");
        let mut transitions = 0;
        assert_eq!(
            fmi2GetInteger(c, [206u32].as_ptr(), 1, &mut transitions),
            OK
        );
        assert!(transitions >= 1);
        assert_eq!(fmi2Terminate(c), OK);
        fmi2FreeInstance(c);
    }
}

#[test]
fn fmu_state_through_pointers_and_bytes() {
    let messages = Messages::default();
    let functions = callbacks(&messages);
    unsafe {
        let c = initialized_modal_beam(&functions);
        assert_eq!(fmi2DoStep(c, 0.0, 0.45, 1), OK);
        let mut state: fmi2FMUstate = null_mut();
        assert_eq!(fmi2GetFMUstate(c, &mut state), OK);
        assert!(!state.is_null());
        // Overwriting an existing state keeps the pointer.
        let before = state;
        assert_eq!(fmi2GetFMUstate(c, &mut state), OK);
        assert_eq!(state, before);
        let mut size = 0usize;
        assert_eq!(fmi2SerializedFMUstateSize(c, state, &mut size), OK);
        let mut bytes = vec![0 as c_char; size];
        assert_eq!(
            fmi2SerializeFMUstate(c, state, bytes.as_mut_ptr(), size),
            OK
        );
        assert_eq!(
            fmi2SerializeFMUstate(c, state, bytes.as_mut_ptr(), size - 1),
            ERROR
        );
        assert_eq!(fmi2Reset(c), OK);

        let tip = |c| {
            let mut u = 0.0;
            assert_eq!(fmi2GetReal(c, [200u32].as_ptr(), 1, &mut u), OK);
            u
        };
        assert_eq!(fmi2SetFMUstate(c, state), OK);
        assert_eq!(fmi2DoStep(c, 0.45, 0.1, 1), OK);
        let first = tip(c);

        let mut copy: fmi2FMUstate = null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(c, bytes.as_ptr(), size, &mut copy),
            OK
        );
        assert_eq!(fmi2SetFMUstate(c, copy), OK);
        assert_eq!(fmi2DoStep(c, 0.45, 0.1, 1), OK);
        assert_eq!(tip(c), first);

        let garbage = [b'{' as c_char, b'x' as c_char];
        let mut bad: fmi2FMUstate = null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(c, garbage.as_ptr(), 2, &mut bad),
            ERROR
        );
        assert!(bad.is_null());
        assert!(logged(&messages, "serialized FMU state is malformed"));

        assert_eq!(fmi2FreeFMUstate(c, &mut state), OK);
        assert!(state.is_null());
        assert_eq!(fmi2FreeFMUstate(c, &mut copy), OK);
        assert_eq!(
            fmi2FreeFMUstate(c, &mut state),
            OK,
            "freeing NULL is a no-op"
        );
        fmi2FreeInstance(c);
    }
}

/// State handles the instance did not hand out are never read or written through:
/// a freed state, another instance's state and a garbage pointer give fmi2Error and a
/// reason; fmi2GetFMUstate with a garbage `*FMUstate` allocates a new state instead of
/// overwriting what the garbage points to.
#[test]
fn foreign_freed_and_garbage_state_handles_are_refused() {
    let messages = Messages::default();
    let functions = callbacks(&messages);
    unsafe {
        let a = initialized_modal_beam(&functions);
        let b = initialized_modal_beam(&functions);
        let mut of_b: fmi2FMUstate = null_mut();
        assert_eq!(fmi2GetFMUstate(b, &mut of_b), OK);
        let mut freed: fmi2FMUstate = null_mut();
        assert_eq!(fmi2GetFMUstate(a, &mut freed), OK);
        let mut good: fmi2FMUstate = null_mut();
        assert_eq!(fmi2GetFMUstate(a, &mut good), OK);
        // Freed after `good` exists, so that `good` cannot reuse its address.
        let dangling = freed;
        assert_eq!(fmi2FreeFMUstate(a, &mut freed), OK);
        // Never dereferenced: the check happens before any read.
        let mut target = [0u64; 8];
        let garbage = target.as_mut_ptr() as fmi2FMUstate;
        let mut size = 0usize;
        let mut bytes = [0 as c_char; 16];
        for handle in [of_b, dangling, garbage] {
            messages.lock().unwrap().clear();
            assert_eq!(fmi2SetFMUstate(a, handle), ERROR);
            assert_eq!(fmi2SerializedFMUstateSize(a, handle, &mut size), ERROR);
            assert_eq!(
                fmi2SerializeFMUstate(a, handle, bytes.as_mut_ptr(), 16),
                ERROR
            );
            assert!(logged(&messages, "was not returned by this instance"));
        }
        assert_eq!(target, [0u64; 8]);
        // Each refusal put `a` in the Error mode; the state saved before leads back.
        assert_eq!(fmi2DoStep(a, 0.0, 0.01, 1), ERROR);
        assert_eq!(fmi2SetFMUstate(a, good), OK);
        assert_eq!(fmi2DoStep(a, 0.0, 0.01, 1), OK);
        let mut uninitialised = garbage;
        assert_eq!(fmi2GetFMUstate(a, &mut uninitialised), OK);
        assert_ne!(uninitialised, garbage);
        assert_eq!(target, [0u64; 8], "the garbage target was written");
        assert_eq!(fmi2SetFMUstate(a, uninitialised), OK);
        assert_eq!(fmi2FreeFMUstate(a, &mut uninitialised), OK);
        assert_eq!(fmi2FreeFMUstate(a, &mut good), OK);
        assert_eq!(fmi2FreeFMUstate(b, &mut of_b), OK);
        fmi2FreeInstance(a);
        fmi2FreeInstance(b);
    }
}

#[test]
fn unsupported_functions_return_error_with_a_reason() {
    let messages = Messages::default();
    let functions = callbacks(&messages);
    unsafe {
        // StickSlipBeam has no directional derivatives (NeuralFriction's: tests/fmu/directional.rs).
        let beam = initialized_modal_beam(&functions);
        let mut d = 0.0;
        assert_eq!(
            fmi2GetDirectionalDerivative(
                beam,
                [20u32].as_ptr(),
                1,
                [10u32].as_ptr(),
                1,
                &1.0,
                &mut d
            ),
            ERROR
        );
        assert!(logged(&messages, "providesDirectionalDerivative is false"));
        fmi2FreeInstance(beam);
        let c = instantiate("f", &FmuKind::NeuralFriction.guid(), 1, &functions);
        assert!(!c.is_null());
        assert_eq!(fmi2CancelStep(c), ERROR);
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(
            fmi2SetRealInputDerivatives(c, [10u32].as_ptr(), 1, &1, &1.0),
            ERROR
        );
        fmi2FreeInstance(c);
    }
}
