//! Resource locations: odd characters in the path (percent-encoded and raw), a missing
//! folder, unreadable or corrupted weights, non-file URIs and NULL.

use super::*;

// Resource locations.

fn errors(log: &[Entry]) -> Vec<&str> {
    log.iter()
        .filter(|e| e.status == ERROR && e.category == "logStatusError" && e.format == "%s")
        .map(|e| e.message.as_str())
        .collect()
}

/// Instantiation is refused (NULL) with an fmi2Error message from fmi2Instantiate that
/// contains every one of `needles`.
fn assert_refused(kind: FmuKind, uri: Option<&str>, needles: &[&str]) {
    let (c, log) = instantiate_at(kind, uri);
    if !c.is_null() {
        unsafe { fmi2FreeInstance(c) };
        panic!("{kind:?} instantiated with resource location {uri:?}");
    }
    let errors = errors(&log);
    assert!(
        errors.iter().any(|m| m.starts_with("fmi2Instantiate: ")
            && needles.iter().all(|n| m.contains(n))
            && names_paths_once(m, needles)),
        "{kind:?}, {uri:?}: no error message containing {needles:?} (each path once); logged {log:?}"
    );
}

/// Whether every needle that is a path occurs in `message` exactly once (the reader
/// names the file; no layer above adds it again).
fn names_paths_once(message: &str, needles: &[&str]) -> bool {
    needles
        .iter()
        .filter(|n| n.contains('/'))
        .all(|n| message.matches(n).count() == 1)
}

/// The first 0.6 s (past breakaway at 0.4 s) of the neural-law beam (modal) with resources at `uri` and weights
/// `weights` (a name in resources/ or an absolute path).
fn neural_run(uri: &str, weights: &'static str) -> Vec<Point> {
    let config = Config {
        fidelity: FidelityLevel::Modal,
        law: FrictionLawKind::Neural,
        weights,
    };
    let mut run = Run::start(config, uri);
    for _ in 0..600 {
        run.step();
    }
    run.finish()
}

#[test]
fn resource_uris_with_spaces_and_non_ascii_characters_work_encoded_and_raw() {
    let root = odd_temp_dir("uri");
    let dir = copy_resources(&root);
    let raw = dir.display().to_string();
    let encoded = file_uri(&dir);
    assert!(encoded.contains("%20") && encoded.contains("%C3%BC"));
    let uris = [
        encoded.clone(),
        format!("{encoded}/"),
        format!("file://{raw}"),
        format!("file://{raw}/"),
        encoded.replacen("file://", "file://localhost", 1),
        encoded.replacen("file://", "file:", 1),
    ];
    for uri in &uris {
        for kind in FmuKind::ALL {
            let (c, log) = instantiate_at(kind, Some(uri));
            assert!(!c.is_null(), "{kind:?} at {uri}: {log:?}");
            assert!(errors(&log).is_empty());
            unsafe { fmi2FreeInstance(c) };
        }
    }

    // The weights are read from that folder: swap the two networks there, and the beam's
    // run with "paper-plain.json" is the repository's run with "paper-signed.json".
    let plain = dir.join("paper-plain.json");
    let signed = dir.join("paper-signed.json");
    std::fs::rename(&plain, dir.join("swap")).unwrap();
    std::fs::rename(&signed, &plain).unwrap();
    std::fs::rename(dir.join("swap"), &signed).unwrap();
    let repository = repository_uri();
    let expected = neural_run(&repository, "paper-signed.json");
    assert!(first_difference(&expected, &neural_run(&repository, "paper-plain.json")).is_some());
    for uri in [&uris[0], &uris[2]] {
        assert_eq!(
            first_difference(&neural_run(uri, "paper-plain.json"), &expected),
            None,
            "{uri}"
        );
    }
    // An absolute weights path with the same characters (the repository's plain network,
    // now named paper-signed.json in the copy).
    let absolute: &'static str = signed.display().to_string().leak();
    assert_eq!(
        first_difference(
            &neural_run(&repository, absolute),
            &neural_run(&repository, "paper-plain.json")
        ),
        None
    );
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn a_missing_resources_folder_fails_instantiation_with_a_reason() {
    let root = odd_temp_dir("missing");
    let missing = root.join("resources");
    for uri in [file_uri(&missing), format!("file://{}", missing.display())] {
        for kind in FmuKind::ALL {
            // The message names the file it looked for, decoded.
            let file = missing.join("paper-plain.json").display().to_string();
            assert_refused(kind, Some(&uri), &[file.as_str(), "no such file"]);
        }
    }
}

/// A weights file that cannot be used is reported where the network is first needed:
/// NeuralFriction (whose default law is the network) refuses instantiation;
/// StickSlipBeam (default law exponential, the network read only for
/// friction.law = neural) instantiates, runs the exponential law, and refuses
/// fmi2ExitInitializationMode with the neural law. Each refusal logs all `needles`.
fn assert_weights_refused(uri: &str, needles: &[&str]) {
    assert_refused(FmuKind::NeuralFriction, Some(uri), needles);
    let vrs = BeamVrs::get();
    for (law, accepted) in [
        (FrictionLawKind::Exponential, true),
        (FrictionLawKind::Neural, false),
    ] {
        let (c, _) = instantiate_at(FmuKind::StickSlipBeam, Some(uri));
        assert!(
            !c.is_null(),
            "StickSlipBeam read the network at instantiation"
        );
        let log = Log::default();
        let functions = callbacks(&log);
        unsafe {
            fmi2FreeInstance(c);
            let guid = CString::new(FmuKind::StickSlipBeam.guid()).unwrap();
            let uri = CString::new(uri).unwrap();
            let c = fmi2Instantiate(
                c"resources".as_ptr(),
                1,
                guid.as_ptr(),
                uri.as_ptr(),
                &functions,
                0,
                0,
            );
            assert!(!c.is_null());
            assert_eq!(
                fmi2SetInteger(
                    c,
                    [vrs.fidelity].as_ptr(),
                    1,
                    [FidelityLevel::Modal.code()].as_ptr()
                ),
                OK
            );
            assert_eq!(
                fmi2SetInteger(c, [vrs.friction_law].as_ptr(), 1, [law.code()].as_ptr()),
                OK
            );
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            let status = fmi2ExitInitializationMode(c);
            if accepted {
                assert_eq!(status, OK, "{:?}", log.lock().unwrap());
                assert_eq!(fmi2DoStep(c, 0.0, 0.01, 1), OK);
            } else {
                assert_eq!(status, ERROR);
            }
            fmi2FreeInstance(c);
        }
        let entries = log.into_inner().unwrap();
        if !accepted {
            assert!(
                errors(&entries).iter().any(|m| {
                    m.starts_with("fmi2ExitInitializationMode")
                        && needles.iter().all(|n| m.contains(n))
                        && names_paths_once(m, needles)
                }),
                "no error containing {needles:?} (each path once): {entries:?}"
            );
        }
    }
}

#[test]
fn unreadable_or_corrupted_weights_give_a_reason_where_the_network_is_first_needed() {
    use std::os::unix::fs::PermissionsExt;
    let root = odd_temp_dir("weights");
    let dir = copy_resources(&root);
    let uri = file_uri(&dir);
    let plain = dir.join("paper-plain.json");
    let name = plain.display().to_string();

    std::fs::set_permissions(&plain, std::fs::Permissions::from_mode(0o000)).unwrap();
    if std::fs::read(&plain).is_ok() {
        println!(
            "note: skipped the unreadable-weights case: {} is still readable after chmod 000 \
             (running as root)",
            name
        );
    } else {
        assert_weights_refused(&uri, &[name.as_str(), "cannot be read"]);
    }
    std::fs::set_permissions(&plain, std::fs::Permissions::from_mode(0o644)).unwrap();

    // A read error at any privilege: a link to /proc/self/mem, a regular file whose read
    // at offset 0 fails (address 0 is never mapped).
    std::fs::remove_file(&plain).unwrap();
    std::os::unix::fs::symlink("/proc/self/mem", &plain).unwrap();
    if std::fs::read(&plain).is_ok() {
        println!("note: skipped the read-error case: /proc/self/mem reads here");
    } else {
        assert_weights_refused(&uri, &[name.as_str(), "cannot be read"]);
    }
    std::fs::remove_file(&plain).unwrap();

    let cases: [(&[u8], &str); 4] = [
        (b"{\"format\": 3", "not a valid model description"),
        (&[0xff, 0xfe, 0x00, 0x7b], "not UTF-8 text (byte 0"),
        (b"", "the file is empty"),
        (b"{\"weights\": [1, 2, 3]}", "format is '(missing)'"),
    ];
    for (contents, reason) in cases {
        std::fs::write(&plain, contents).unwrap();
        assert_weights_refused(&uri, &["weights file", name.as_str(), reason]);
    }

    // Special files are refused by their type, before anything is read: /dev/zero would
    // be read forever, a FIFO would block the importer.
    std::fs::remove_file(&plain).unwrap();
    // (The default weights' type is checked at instantiation, so both FMUs refuse there.)
    std::os::unix::fs::symlink("/dev/zero", &plain).unwrap();
    for kind in FmuKind::ALL {
        assert_refused(
            kind,
            Some(&uri),
            &[name.as_str(), "is a character device, not a regular file"],
        );
    }
    std::fs::remove_file(&plain).unwrap();
    let fifo = std::process::Command::new("mkfifo").arg(&plain).status();
    if fifo.is_ok_and(|s| s.success()) {
        for kind in FmuKind::ALL {
            assert_refused(
                kind,
                Some(&uri),
                &[name.as_str(), "is a FIFO (named pipe), not a regular file"],
            );
        }
        std::fs::remove_file(&plain).unwrap();
    } else {
        println!("note: skipped the FIFO case: mkfifo is not available");
    }

    // An ONNX file (found by its first byte, whatever its name) whose metadata does not
    // describe the features: the reason names the metadata key and the import flags.
    let shipped = stickslip::neural::NeuralLaw::paper_default().unwrap();
    let mut bare = stickslip_tests::onnx::export(
        shipped.model(),
        stickslip_tests::onnx::Exporter::Torch,
        true,
    );
    bare.metadata.clear();
    std::fs::write(&plain, bare.encode()).unwrap();
    assert_weights_refused(
        &uri,
        &[
            name.as_str(),
            "stickslip.features",
            "--feature NAME:ROLE:UNIT:MIN:MAX",
        ],
    );

    // A folder where the file should be.
    std::fs::remove_file(&plain).unwrap();
    std::fs::create_dir(&plain).unwrap();
    for kind in FmuKind::ALL {
        assert_refused(
            kind,
            Some(&uri),
            &[name.as_str(), "is a directory, not a file"],
        );
    }
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn non_file_uris_and_null_fail_instantiation_with_a_reason() {
    let weights = weights_dir().display().to_string();
    let uris = [
        "http://example.com/StickSlipBeam/resources".to_string(),
        "https://example.com/resources/".to_string(),
        "ftp://example.com/resources".to_string(),
        // A file URI on another host, a bad escape, a relative path, nothing.
        format!("file://fileserver{weights}"),
        format!("file://{weights}%zz"),
        format!("file://{weights}%C3"),
        weights.clone(),
        "weights".to_string(),
        String::new(),
    ];
    for kind in FmuKind::ALL {
        for uri in &uris {
            assert_refused(kind, Some(uri), &["fmuResourceLocation", "not a file URI"]);
        }
        assert_refused(kind, None, &["fmuResourceLocation", "NULL"]);
    }
}
