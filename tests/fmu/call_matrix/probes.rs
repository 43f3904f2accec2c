//! The probes of the call matrix: one call of each of the 34 functions with valid
//! arguments.

use super::*;

// The probes: one call of each function with valid arguments.

/// Variables a probe reads or writes, per FMU and type. `None`: the FMU has no variable
/// of that type that the standard's footnote admits, so the probe makes an empty request.
pub(super) struct Probe {
    pub(super) get_real: u32,
    pub(super) get_integer: Option<u32>,
    pub(super) get_boolean: Option<u32>,
    pub(super) get_string: Option<u32>,
    /// Before fmi2ExitInitializationMode: parameters (initial = exact), set to their
    /// start values.
    pub(super) parameter_real: (u32, f64),
    pub(super) parameter_integer: Option<(u32, i32)>,
    pub(super) parameter_boolean: Option<(u32, fmi2Boolean)>,
    pub(super) parameter_string: Option<(u32, &'static str)>,
    /// Afterwards: an input, set to its start value.
    pub(super) input_real: (u32, f64),
    pub(super) output_real: u32,
}

pub(super) fn probe_variables(kind: FmuKind) -> Probe {
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
                parameter_integer: Some((vr("law"), NeuralFrictionLaw::NEURAL.code())),
                parameter_boolean: None,
                parameter_string: Some((vr("weights"), "paper-plain.json")),
                input_real: (vr("sliding_velocity"), 0.0),
                output_real: vr("friction_force"),
            }
        }
    }
}

/// (value references, count) of an optional single variable.
pub(super) fn one(vr: &Option<u32>) -> (*const u32, usize) {
    match vr {
        Some(v) => (v as *const u32, 1),
        None => ([].as_ptr(), 0),
    }
}

/// Calls `function` once. Returns its status (for functions without one: OK when they
/// returned what the standard says, ERROR otherwise) and any complaint about the values
/// it returned.
pub(super) unsafe fn call(
    f: &mut Fixture,
    function: &str,
    state: State,
) -> (fmi2Status, Option<String>) {
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
