//! `stickslip train --test-data`: training on a split the user gives, here the paper
//! authors' own (data/paper-authors, Apache-2.0, from TUHH-DYN/NeuralNetworkFrictionModel_FEA).

use std::path::PathBuf;

use crate::contract::scratch;
use crate::stickslip;

fn paper_file(which: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/paper-authors")
        .join(format!("exponential_friction_model_samples_{which}.csv"))
}

/// The value after `key` on the stdout line starting with `line_start`.
fn metric(stdout: &str, line_start: &str, key: &str) -> f64 {
    let line = stdout
        .lines()
        .find(|l| l.trim_start().starts_with(line_start))
        .unwrap_or_else(|| panic!("no '{line_start}' line in {stdout}"));
    let rest = &line[line
        .find(key)
        .unwrap_or_else(|| panic!("no {key} in {line}"))
        + key.len()..];
    rest.split_whitespace().next().unwrap().parse().unwrap()
}

/// Trains with the paper's settings (3 x 100 tanh, lambda 0.004, the default iteration
/// limit and seed) on the authors' training file, tested on their test file; returns
/// (test MSE in N^2, test R^2).
fn train_on_the_authors_split(variant: &str) -> (f64, f64) {
    let out = scratch(&format!("paper-split-{variant}")).join("w.json");
    let (train, test) = (paper_file("training"), paper_file("test"));
    let start = std::time::Instant::now();
    let (ok, stdout, stderr) = stickslip(&[
        "train",
        "--data",
        train.to_str().unwrap(),
        "--test-data",
        test.to_str().unwrap(),
        "--features",
        "Fn,vs",
        "--target",
        "Ff",
        "--velocity-feature",
        "vs",
        "--normal-force-feature",
        "Fn",
        "--variant",
        variant,
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    let seconds = start.elapsed().as_secs_f64();
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("(test: exponential_friction_model_samples_test.csv)"),
        "{stdout}"
    );
    assert!(stdout.contains("train ( 3496 samples)"), "{stdout}");
    assert!(stdout.contains("test  ( 1498 samples)"), "{stdout}");
    let (mse, r2) = (
        metric(&stdout, "test ", "MSE "),
        metric(&stdout, "test ", "R2 "),
    );
    println!("{variant}: authors' test file MSE {mse:.4} N^2, R2 {r2:.5} ({seconds:.1} s)");
    (mse, r2)
}

/// The authors' network gets MSE 4.52 N^2, R^2 0.9974 on their test file (Vater et al.
/// 2023, re-evaluated from their published network); the 2 % relative noise puts the
/// floor at about 0.65 N^2 (data/paper-authors/README.md).
///
/// The signed network F = sign(v) g(|v|, F_n), with the paper's settings otherwise,
/// reaches the floor (measured 0.658 N^2): asserted below 1.0, which a wrong test file,
/// a mixed-up column or a weak fit would miss. The plain network F(v, F_n), the paper's
/// form, is seed-dependent on this split without the authors' early stopping (measured
/// seeds 1-4: 2.40, 5.73, 5.03, 3.46 N^2; the default seed 2 gives 5.73), so it is only
/// held to the paper's order: below twice 4.52 and R^2 above 0.995.
#[test]
fn the_paper_settings_on_the_authors_split_reach_the_noise_floor_when_signed() {
    let (mse, r2) = train_on_the_authors_split("signed");
    assert!(
        mse < 1.0,
        "signed: test MSE {mse} N^2 not near the 0.65 floor (paper: 4.52)"
    );
    assert!(
        mse > 0.5,
        "signed: test MSE {mse} N^2 below the noise floor: a leak?"
    );
    assert!(
        r2 > 0.9974,
        "signed: test R2 {r2} not above the paper's 0.9974"
    );
    let (mse, r2) = train_on_the_authors_split("plain");
    assert!(
        mse < 2.0 * 4.52,
        "plain: test MSE {mse} N^2 not of the paper's order"
    );
    assert!(r2 > 0.995, "plain: test R2 {r2}");
}

/// A given test set and a random hold-out share exclude each other; a test set without
/// --data has nothing to go with; a test file lacking a selected column is named.
#[test]
fn test_data_is_refused_with_test_fraction_and_with_other_columns() {
    let dir = scratch("test-data-errors");
    let out = dir.join("w.json");
    let other = dir.join("other.csv");
    std::fs::write(&other, "Fn,v,Ff\n100,0.1,30\n99,-0.1,-30\n").unwrap();
    let (train, test) = (paper_file("training"), paper_file("test"));
    let base = |test: &str| -> Vec<String> {
        [
            "train",
            "--data",
            train.to_str().unwrap(),
            "--test-data",
            test,
            "--features",
            "Fn,vs",
            "--target",
            "Ff",
            "--out",
            out.to_str().unwrap(),
        ]
        .map(String::from)
        .to_vec()
    };
    let run = |args: Vec<String>| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (ok, _, stderr) = stickslip(&args);
        assert!(!ok, "{args:?} succeeded");
        stderr
    };

    let mut with_fraction = base(test.to_str().unwrap());
    with_fraction.extend(["--test-fraction".into(), "0.2".into()]);
    let stderr = run(with_fraction);
    assert!(
        stderr.contains("'--test-data <TEST.csv>' cannot be used with '--test-fraction"),
        "{stderr}"
    );

    let stderr = run(vec![
        "train".into(),
        "--test-data".into(),
        test.to_str().unwrap().into(),
        "--out".into(),
        out.to_str().unwrap().into(),
    ]);
    assert!(stderr.contains("--data"), "{stderr}");

    let stderr = run(base(other.to_str().unwrap()));
    let expected = format!(
        "error: {}, line 1: no column named 'vs' in the header (columns: Fn, v, Ff)",
        other.display()
    );
    assert_eq!(stderr.lines().last(), Some(expected.as_str()), "{stderr}");

    let kilonewtons = dir.join("kN.csv");
    std::fs::write(&kilonewtons, "Fn,vs,Ff[kN]\n100,0.1,0.03\n99,-0.1,-0.03\n").unwrap();
    let stderr = run(base(kilonewtons.to_str().unwrap()));
    assert!(
        stderr.contains("the test data's column 'Ff[kN]' does not match the training data's 'Ff'"),
        "{stderr}"
    );
    assert!(!out.exists(), "no weights are written for refused data");
}
