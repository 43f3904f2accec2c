//! fmi3Instantiate*: what the FMU does not offer is refused, and reasons that contain
//! "fmi2" are logged unaltered.

use super::*;

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
        let neural = [stickslip::friction::FrictionLawKind::Neural.code()];
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
