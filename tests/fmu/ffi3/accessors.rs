//! The scalar accessors: nValues and NULL arrays checked, Boolean bytes other than 0 or
//! 1 read as true.

use super::*;

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
