//! The command-line contract: `simulate` CSV header and summary, `static` error line,
//! clear errors for bad input.

use std::process::Command;

fn stickslip(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(args)
        .output()
        .expect("run stickslip");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn simulate_writes_the_contract_csv_and_summary() {
    let dir = std::env::temp_dir().join(format!("stickslip-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("run.csv");
    let (ok, stdout, stderr) = stickslip(&[
        "simulate",
        "--fidelity",
        "modal",
        "--t-end",
        "0.5",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    for needle in [
        "breakaway time",
        "slip phases",
        "stick-slip period",
        "tip deflection after breakaway",
        "wall time",
    ] {
        assert!(stdout.contains(needle), "missing {needle:?} in {stdout}");
    }
    assert!(stdout.contains("0.4000 s"), "{stdout}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("t,tip_deflection,tip_velocity,friction_force,stick")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 5001);
    // At t = 0.2 s the tip sticks at v_b t = 4 mm (SI units in the file).
    let row = &rows[2000];
    assert!((row[0] - 0.2).abs() < 1e-12);
    assert!((row[1] - 0.004).abs() < 1e-6, "{row:?}");
    assert!((row[2] - 0.02).abs() < 1e-6, "{row:?}");
    assert_eq!(row[4], 1.0);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn static_prints_the_relative_error() {
    let (ok, stdout, stderr) = stickslip(&["static", "--fidelity", "beam"]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("relative error"), "{stdout}");
    assert!(stdout.contains("8.000000"), "{stdout}");
}

#[test]
fn bad_input_gives_a_clear_error_and_a_failing_status() {
    let (ok, _, stderr) = stickslip(&["simulate", "--dt=-1e-4"]);
    assert!(!ok);
    assert!(stderr.contains("time.step"), "{stderr}");
    let (ok, _, stderr) = stickslip(&["simulate", "--scene", "/nonexistent/scene.toml"]);
    assert!(!ok);
    assert!(stderr.contains("/nonexistent/scene.toml"), "{stderr}");
}
