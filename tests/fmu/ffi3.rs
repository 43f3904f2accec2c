//! The FMI 3.0 C interface (`stickslip_fmi::ffi3`) called as an importer calls it:
//! a whole life of each FMU (instantiate, initialise, steps with reads and writes, FMU
//! state get/serialize/deserialize/set/free, an illegal call and the recovery by
//! fmi3Reset, free), checked for bit-identical state round trips, and the ignored loop
//! `valgrind_driver_loop3` that `scripts/valgrind.sh` runs under valgrind.
//!
//!
//! The helpers the tests share (and the FMI 3.0 instantiation other modules use) are here;
//! the tests are in `life`, `instantiation`, `events`, `valgrind_driver` and
//! `accessors`.

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

mod accessors;
mod events;
mod instantiation;
mod life;
mod valgrind_driver;
use events::*;
