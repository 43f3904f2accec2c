//! `stickslip train-memory`: records from CSV, bad rows refused with their line, the
//! exported records read back (and trained with the slip evolution and trained initial
//! states), and the weights file it writes run by `simulate`.

use crate::stickslip;

/// A file in a folder of this test's own (`tag`): the tests run in parallel.
fn temp(tag: &str, name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "stickslip-train-memory-{tag}-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// `train-memory --data` on a file of `text`: it must fail; its stderr.
fn refused(text: &str) -> String {
    let bad = temp("bad", "bad.csv");
    std::fs::write(&bad, text).unwrap();
    let out = temp("bad", "never.json");
    let (ok, _, err) = stickslip(&[
        "train-memory",
        "--data",
        bad.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok && !out.exists(), "{err}");
    err
}

#[test]
fn bad_rows_and_units_are_refused_with_the_line() {
    let err = refused("t[s],v[m/s],F_n[N],F[N]\n0,0.01,100,50\n0.001,0.01,100,5x\n");
    assert!(
        err.contains("bad.csv, line 3: column 'F': '5x' is not a number"),
        "{err}"
    );
    let err = refused("t,v[mm/s],F_n,F\n0,10,100,50\n0.001,10,100,50\n");
    assert!(
        err.contains("column 'v' is in 'mm/s', expected 'm/s'"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(temp("bad", "x").parent().unwrap());
}

/// Synthetic records exported, read back as measured data and trained on (a short fit:
/// the point is the path, not the accuracy, which `tests/neural/learned_state.rs` asserts);
/// the weights file runs the paper scene.
#[test]
fn exported_records_train_again_and_the_weights_run_a_scene() {
    let records = temp("export", "records.csv");
    let first = temp("export", "first.json");
    let (ok, stdout, err) = stickslip(&[
        "train-memory",
        "--iterations",
        "3",
        "--hidden",
        "2",
        "--quiet",
        "--export-data",
        records.to_str().unwrap(),
        "--out",
        first.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("12 records (27330 samples)"), "{stdout}");
    assert!(stdout.contains("direct effect"), "{stdout}");
    let second = temp("export", "second.json");
    let (ok, stdout, err) = stickslip(&[
        "train-memory",
        "--data",
        records.to_str().unwrap(),
        "--iterations",
        "3",
        "--learned-evolution",
        "slip",
        "--train-initial-state",
        "--quiet",
        "--out",
        second.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("12 records"), "{stdout}");
    // The learned law's evolution is the one asked for, and the file says so; the
    // scene below runs the slip law through the contact.
    assert!(stdout.contains("learned (slip law)"), "{stdout}");
    let text = std::fs::read_to_string(&second).unwrap();
    assert!(text.contains("\"state_evolution\": \"slip\""), "{text}");
    assert!(text.contains("from a trained initial state"), "{text}");
    let (ok, stdout, err) = stickslip(&[
        "simulate",
        "--friction",
        "neural",
        "--weights",
        second.to_str().unwrap(),
        "--fidelity",
        "modal",
        "--t-end",
        "0.6",
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("neural-memory friction"), "{stdout}");
    let _ = std::fs::remove_dir_all(records.parent().unwrap());
}
