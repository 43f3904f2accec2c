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

/// A scratch folder of its own for each test.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("stickslip-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `--friction analytical` (the name scripts use) is the scene's `exponential`.
#[test]
fn friction_analytical_is_the_scenes_exponential() {
    let dir = scratch("analytical");
    let mut csvs = Vec::new();
    for law in ["analytical", "exponential"] {
        let csv = dir.join(format!("{law}.csv"));
        let (ok, stdout, stderr) = stickslip(&[
            "simulate",
            "--fidelity",
            "modal",
            "--friction",
            law,
            "--t-end",
            "0.5",
            "--out",
            csv.to_str().unwrap(),
        ]);
        assert!(ok, "{stderr}");
        assert!(stdout.contains("exponential friction"), "{stdout}");
        csvs.push(std::fs::read(&csv).unwrap());
    }
    assert!(csvs[0] == csvs[1]);
    std::fs::remove_dir_all(&dir).ok();
}

/// The external law needs the FMU's inputs: refused on the command line and in a scene
/// file, with a message, not a panic.
#[test]
fn the_external_law_is_refused_with_a_clear_message() {
    let (ok, _, stderr) = stickslip(&["simulate", "--friction", "external"]);
    assert!(!ok);
    assert!(
        stderr.contains("--friction") && stderr.contains("StickSlipBeam"),
        "{stderr}"
    );
    let dir = scratch("external");
    let scene = dir.join("external.toml");
    std::fs::write(&scene, "[friction]\nlaw = \"external\"\n").unwrap();
    let (ok, _, stderr) = stickslip(&["simulate", "--scene", scene.to_str().unwrap()]);
    assert!(!ok);
    assert!(stderr.contains("friction.law = external"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `fidelity.level = "auto"` with its tolerance in a scene file runs as
/// `--fidelity auto --tolerance` does; without a tolerance it is refused.
#[test]
fn a_scene_file_with_fidelity_auto_runs_like_the_flag() {
    let dir = scratch("auto");
    let scene = dir.join("auto.toml");
    std::fs::write(
        &scene,
        "[fidelity]\nlevel = \"auto\"\ntolerance = 1e-4\n\n[time]\nend = 0.6\n",
    )
    .unwrap();
    let from_file = dir.join("file.csv");
    let (ok, _, stderr) = stickslip(&[
        "simulate",
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        from_file.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("fidelity = auto (tolerance 1e-4 m"),
        "{stderr}"
    );
    let from_flags = dir.join("flags.csv");
    let (ok, _, stderr) = stickslip(&[
        "simulate",
        "--fidelity",
        "auto",
        "--tolerance",
        "1e-4",
        "--t-end",
        "0.6",
        "--out",
        from_flags.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(std::fs::read(&from_file).unwrap() == std::fs::read(&from_flags).unwrap());

    std::fs::write(&scene, "[fidelity]\nlevel = \"auto\"\n").unwrap();
    let (ok, _, stderr) = stickslip(&["simulate", "--scene", scene.to_str().unwrap()]);
    assert!(!ok);
    assert!(stderr.contains("fidelity.tolerance"), "{stderr}");
    let (ok, _, stderr) = stickslip(&["simulate", "--fidelity", "auto"]);
    assert!(!ok);
    assert!(stderr.contains("--tolerance"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}
