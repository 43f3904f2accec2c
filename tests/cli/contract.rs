//! The command-line contract: `simulate` CSV header and summary, `static` error line,
//! clear errors for bad input.

use super::stickslip;

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
pub(crate) fn scratch(name: &str) -> std::path::PathBuf {
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
/// `--fidelity auto --tolerance` does; without a tolerance both take the default.
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

    // Without a tolerance, file and flag both take the default, the FMU's start value
    // (issue 17, item 6), and run as the explicit default does.
    std::fs::write(
        &scene,
        "[fidelity]\nlevel = \"auto\"\n\n[time]\nend = 0.6\n",
    )
    .unwrap();
    let mut outputs = Vec::new();
    for (name, args) in [
        ("file", vec!["--scene", scene.to_str().unwrap()]),
        ("flag", vec!["--fidelity", "auto", "--t-end", "0.6"]),
        (
            "explicit",
            vec![
                "--fidelity",
                "auto",
                "--tolerance",
                "1e-5",
                "--t-end",
                "0.6",
            ],
        ),
    ] {
        let out = dir.join(format!("default-{name}.csv"));
        let mut all = vec!["simulate", "--out", out.to_str().unwrap()];
        all.extend(args);
        let (ok, _, stderr) = stickslip(&all);
        assert!(ok, "{name}: {stderr}");
        assert!(
            stderr.contains("fidelity = auto (tolerance 1e-5 m"),
            "{name}: {stderr}"
        );
        outputs.push(std::fs::read(&out).unwrap());
    }
    assert!(outputs[0] == outputs[1] && outputs[1] == outputs[2]);
    std::fs::remove_dir_all(&dir).ok();
}

/// `--damping-ratio` goes with `--fidelity auto --tolerance`: auto picks a configuration
/// for the scene with the Rayleigh damping of that ratio at modes 1 and 3, which is the
/// damping `stickslip estimates --rayleigh-ratio` reports (a scene file giving those a
/// and b runs the same, bit for bit), and which changes the run.
#[test]
fn fidelity_auto_takes_the_damping_ratio() {
    let dir = scratch("auto-damping");
    let (ok, stdout, stderr) = stickslip(&["estimates", "--rayleigh-ratio", "0.02"]);
    assert!(ok, "{stderr}");
    let estimates: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let a = estimates["mass_proportional"].as_f64().unwrap();
    let b = estimates["stiffness_proportional"].as_f64().unwrap();
    assert!(a > 0.0 && b > 0.0, "{estimates}");

    let run = |name: &str, extra: &[&str]| -> Vec<u8> {
        let csv = dir.join(format!("{name}.csv"));
        let mut args = vec!["simulate", "--t-end", "0.6", "--out", csv.to_str().unwrap()];
        args.extend_from_slice(extra);
        let (ok, _, stderr) = stickslip(&args);
        assert!(ok, "{name}: {stderr}");
        assert!(
            stderr.contains("fidelity = auto (tolerance 1e-4 m") && stderr.contains("chose "),
            "{name}: {stderr}"
        );
        std::fs::read(&csv).unwrap()
    };
    let auto = ["--fidelity", "auto", "--tolerance", "1e-4"];
    let flags = run("flags", &[&auto[..], &["--damping-ratio", "0.02"]].concat());
    let scene = dir.join("damped.toml");
    std::fs::write(
        &scene,
        format!(
            "[fidelity]\nlevel = \"auto\"\ntolerance = 1e-4\n\n[damping]\nmass_proportional = {a:?}\nstiffness_proportional = {b:?}\n"
        ),
    )
    .unwrap();
    let file = run("file", &["--scene", scene.to_str().unwrap()]);
    assert!(
        flags == file,
        "--damping-ratio 0.02 is not the damping of estimates"
    );
    let undamped = run("undamped", &auto);
    assert!(flags != undamped, "--damping-ratio changed nothing");
    std::fs::remove_dir_all(&dir).ok();
}

/// The error line of each kind of bad input, word for word (as the pre-split binary
/// printed them): the command line's own cases and the physics' and the trainer's
/// messages passed through.
#[test]
fn error_lines_are_the_documented_ones() {
    let dir = std::env::temp_dir().join(format!("stickslip-cli-errors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let negative_modulus = dir.join("negative.toml");
    std::fs::write(&negative_modulus, "[material]\nyoungs_modulus = -1\n").unwrap();
    // E = exp(mu_0 / a) / (2 V_0) overflows: the law has no finite slope at rest.
    let steep_rate_and_state = dir.join("steep.toml");
    std::fs::write(
        &steep_rate_and_state,
        "[friction]\nlaw = \"rate-and-state\"\n[friction.rate_and_state]\ndirect_effect = 1e-6\n",
    )
    .unwrap();
    let broken_csv = dir.join("broken.csv");
    std::fs::write(&broken_csv, "v,Fn,F\n0.1,100,20\n0.2,100\n").unwrap();
    let weights = dir.join("w.json");
    let study_out = dir.join("study");
    let cases: &[(&[&str], String)] = &[
        (
            &["simulate", "--dt", "-1"],
            "invalid scene: time.step = -1e0; it must be finite and > 0 (s)".into(),
        ),
        (
            &["simulate", "--scene", negative_modulus.to_str().unwrap()],
            "invalid scene: material.youngs_modulus = -1e0; it must be finite and > 0 (Pa)".into(),
        ),
        (
            &["simulate", "--scene", steep_rate_and_state.to_str().unwrap()],
            "invalid scene: friction.rate_and_state.direct_effect = 1e-6; it must be >= 7.206847e-4 (1) with mu_0 = 5e-1 and V_0 = 1e-3 m/s: below it the slope at v = 0, F_n a exp(mu_0 / a) / (2 V_0), exceeds 1e304 a F_n and overflows".into(),
        ),
        (
            &["simulate", "--tolerance", "1e-4"],
            "--tolerance applies to --fidelity auto only".into(),
        ),
        (
            &["simulate", "--fidelity", "auto", "--tolerance", "1e-4", "--dt", "1e-4"],
            "--dt is chosen by --fidelity auto; leave it out".into(),
        ),
        (
            &["simulate", "--fidelity", "auto", "--tolerance", "-1"],
            "invalid scene: fidelity.tolerance = -1e0; it must be finite and > 0 (m)".into(),
        ),
        (
            &["simulate", "--damping-ratio", "-1"],
            "--damping-ratio = -1; it must be finite and >= 0".into(),
        ),
        (
            &["static", "--fidelity", "modal", "--elements", "5", "--modes", "50"],
            "fidelity.modes = 50 exceeds the 10 degrees of freedom of the full model".into(),
        ),
        (
            &["static", "--load", "0"],
            "--load = 0; it must be finite and non-zero".into(),
        ),
        (
            // Every resolution axis empty: the mesh's modal bases are one too (since
            // issue 27 a grid of them alone has a reference, the richest basis).
            &["study", "--modes", "--elements", "--element-sizes", "--plane-stress-modal"],
            "the grid is empty: give at least one resolution and one time step".into(),
        ),
        (
            &["study", "--elements", "--element-sizes", "--plane-stress-modal", "--modes", "1", "--dts", "3e-4", "--t-end", "0.01", "--out", study_out.to_str().unwrap()],
            "the reference modal 1 modes, dt 3e-4 s, generalized-alpha failed: time step 0.0003 s does not divide the comparison interval 0.001 s".into(),
        ),
        (
            &["train", "--features", "v", "--out", weights.to_str().unwrap()],
            "--features and --target select columns of --data; give --data FILE.csv".into(),
        ),
        (
            &["train", "--data", broken_csv.to_str().unwrap(), "--features", "v,Fn", "--target", "F", "--out", weights.to_str().unwrap()],
            format!("{}, line 3: 2 field(s), but the header has 3 columns", broken_csv.display()),
        ),
        (
            &["train", "--out", "/nonexistent/dir/w.json"],
            "cannot write /nonexistent/dir/w.json: its directory does not exist".into(),
        ),
        (
            &["train", "--samples", "5", "--out", weights.to_str().unwrap()],
            "synthetic data: at least 10 samples are needed".into(),
        ),
    ];
    for (args, line) in cases {
        let (ok, _, stderr) = stickslip(args);
        assert!(!ok, "{args:?} succeeded");
        // Progress lines (the study's) may come before it; the error is the last line.
        let expected = format!("error: {line}");
        assert_eq!(stderr.lines().last(), Some(expected.as_str()), "{args:?}");
    }
    // File errors name the path once, with the reason.
    for (args, prefix) in [
        (
            &[
                "simulate",
                "--friction",
                "neural",
                "--weights",
                "/nonexistent",
            ][..],
            "error: friction.weights: weights file /nonexistent: no such file",
        ),
        (
            &[
                "simulate",
                "--t-end",
                "0.01",
                "--out",
                "/nonexistent/dir/x.csv",
            ],
            "error: cannot write /nonexistent/dir/x.csv: its directory does not exist",
        ),
        (
            &[
                "train",
                "--data",
                "/nonexistent/m.csv",
                "--features",
                "v",
                "--target",
                "F",
                "--out",
                "w.json",
            ],
            "error: data file /nonexistent/m.csv: no such file",
        ),
    ] {
        let (ok, _, stderr) = stickslip(args);
        assert!(!ok, "{args:?} succeeded");
        assert!(stderr.starts_with(prefix), "{args:?}: {stderr}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--inference` (and a scene file's `friction.inference`) chooses how the neural law is
/// evaluated: the table and f32 runs follow the exact one (their errors, 1e-5 N and
/// less, move the tip by nanometres over half a second), a flag and a scene file give
/// the same run, and a network with more inputs than the table is refused with its
/// reason.
#[test]
fn inference_is_chosen_by_flag_or_scene_file() {
    let dir = scratch("inference");
    let run = |extra: &[&str], name: &str| -> Vec<f64> {
        let csv = dir.join(format!("{name}.csv"));
        let mut args = vec![
            "simulate",
            "--fidelity",
            "modal",
            "--friction",
            "neural",
            "--t-end",
            "0.5",
            "--out",
            csv.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (ok, _, stderr) = stickslip(&args);
        assert!(ok, "{stderr}");
        std::fs::read_to_string(&csv)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
            .collect()
    };
    let exact = run(&[], "exact");
    for inference in ["f32", "table"] {
        let tip = run(&["--inference", inference], inference);
        let deviation = exact
            .iter()
            .zip(&tip)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(deviation < 1e-7, "{inference}: {deviation} m");
        assert!(
            deviation > 0.0,
            "{inference} runs something else than the exact network"
        );
    }
    let scene = dir.join("table.toml");
    std::fs::write(
        &scene,
        "[friction]\nlaw = \"neural\"\ninference = \"table\"\n",
    )
    .unwrap();
    let by_file = run(&["--scene", scene.to_str().unwrap()], "file");
    assert_eq!(by_file, run(&["--inference", "table"], "flag"));
    let weights = dir.join("three.json");
    std::fs::write(&weights, three_input_weights()).unwrap();
    let (ok, _, stderr) = stickslip(&[
        "simulate",
        "--friction",
        "neural",
        "--inference",
        "table",
        "--weights",
        weights.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("friction.inference = table") && stderr.contains("temperature"),
        "{stderr}"
    );
    let (ok, _, stderr) = stickslip(&["simulate", "--inference", "fast"]);
    assert!(
        !ok && stderr.contains("exact") && stderr.contains("table"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The shipped plain network with a third input it ignores, `temperature` (as
/// stickslip_tests::three_input_weights, which this package cannot depend on).
fn three_input_weights() -> String {
    use stickslip::neural::{FeatureRole, NeuralModel, PAPER_PLAIN_JSON};
    let mut model = NeuralModel::from_json(PAPER_PLAIN_JSON, "shipped").unwrap();
    let mut temperature = model.features[0].clone();
    temperature.name = "temperature".into();
    temperature.role = FeatureRole::Other;
    model.features.push(temperature);
    model.layer_sizes[0] = 3;
    for row in &mut model.layers[0].weights {
        row.push(0.0);
    }
    model.to_json().unwrap()
}

#[test]
fn the_paper_authors_preset_breaks_away_after_its_preload_and_excludes_a_scene_file() {
    let (ok, stdout, stderr) = stickslip(&[
        "simulate",
        "--preset",
        "paper-authors",
        "--fidelity",
        "modal",
        "--t-end",
        "0.45",
    ]);
    assert!(ok, "{stderr}");
    // (mu_s F_n - 0.01 mu_s F_n) / (k v_b) = 0.396 s, detected at the end of its step:
    // the summary's four digits show 0.3960 or 0.3961.
    assert!(
        stdout.contains("0.3960 s") || stdout.contains("0.3961 s"),
        "{stdout}"
    );
    let (ok, _, stderr) = stickslip(&[
        "simulate",
        "--preset",
        "paper-authors",
        "--scene",
        "scene.toml",
    ]);
    assert!(!ok);
    assert!(stderr.contains("--preset"), "{stderr}");
}

#[test]
fn the_slip_rule_flags_reach_the_scene_and_a_law_with_state_refuses_them() {
    // Set on the default scene they change the run: the free first step and the lagged
    // force move the first re-stick, so the summaries differ.
    let base = ["simulate", "--fidelity", "modal", "--t-end", "0.8"];
    let (ok, plain, stderr) = stickslip(&base);
    assert!(ok, "{stderr}");
    let mut with_rules = base.to_vec();
    with_rules.extend(["--first-slip-step", "free", "--slip-force", "lagged"]);
    let (ok, ruled, stderr) = stickslip(&with_rules);
    assert!(ok, "{stderr}");
    assert_ne!(plain, ruled);
    for (flag, value, field) in [
        ("--slip-force", "lagged", "contact.slip_force"),
        ("--first-slip-step", "free", "contact.first_slip_step"),
    ] {
        let (ok, _, stderr) = stickslip(&[
            "simulate",
            "--friction",
            "lugre",
            flag,
            value,
            "--t-end",
            "0.01",
        ]);
        assert!(!ok);
        assert!(
            stderr.contains(field) && stderr.contains("friction.law = lugre"),
            "{stderr}"
        );
    }
}

/// A scene file with a `[structure]` runs on that structure (the CalculiX beam, its
/// files named relative to the scene file, whatever the working directory), and a flag
/// that asks for a built-in model is refused naming the field.
#[test]
fn a_scene_with_a_structure_runs_on_it() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/calculix-beam/scene.toml");
    let scene = scene.to_str().unwrap();
    let (ok, stdout, stderr) = stickslip(&["simulate", "--scene", scene]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("structure, 1002 DOFs (calculix beam), contact node 502 direction 2"),
        "{stdout}"
    );
    // One step after the built-in plane stress's 0.4000 s (docs/structures.md).
    assert!(
        stdout.contains("breakaway time          0.4001 s"),
        "{stdout}"
    );
    let (ok, _, stderr) = stickslip(&["simulate", "--scene", scene, "--fidelity", "beam"]);
    assert!(!ok);
    assert!(
        stderr.contains(
            "fidelity.level = beam; it must be plane-stress (the structure's full model), modal (its reduction) or auto"
        ),
        "{stderr}"
    );
}

/// A sensor whose output would repeat a column of the CSV (`stick`, or `t` through its
/// velocity column's base) is refused before the run, naming the output; without
/// `--out` there is no CSV and the same scene runs.
#[test]
fn simulate_refuses_a_sensor_named_like_a_csv_column() {
    let dir = std::env::temp_dir().join(format!("stickslip-cli-sensor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let job =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/calculix-beam/beam");
    let scene = dir.join("scene.toml");
    let csv = dir.join("run.csv");
    for (sensor, clash) in [("stick", "stick"), ("tip", "tip_velocity")] {
        std::fs::write(
            &scene,
            format!(
                "[time]\nend = 0.001\n[structure]\nformat = \"calculix\"\njob = {:?}\ncontact = {{ node = 502, direction = 2 }}\nsensors = [{{ name = \"{sensor}\", node = 252, direction = 2 }}]\n",
                job.to_str().unwrap()
            ),
        )
        .unwrap();
        let (ok, _, stderr) = stickslip(&[
            "simulate",
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            csv.to_str().unwrap(),
        ]);
        assert!(!ok);
        assert!(
            stderr.contains(&format!("the sensor output {clash} is also a column")),
            "{stderr}"
        );
        assert!(!csv.exists(), "a refused run wrote {}", csv.display());
    }
    let (ok, _, stderr) = stickslip(&["simulate", "--scene", scene.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `static` and `estimates` of a scene with a `[structure]` report the structure's own
/// numbers (tests/physics/structure_statics.rs checks them against the cantilever), and
/// `static --convergence`, the built-in beam's mesh study, is refused saying what to run.
#[test]
fn static_and_estimates_of_a_structure_are_the_structures() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/calculix-beam/scene.toml");
    let scene = scene.to_str().unwrap();
    let (ok, stdout, stderr) = stickslip(&["static", "--scene", scene, "--load", "1"]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("structure, 1002 DOFs (calculix beam), contact node 502 direction 2"),
        "{stdout}"
    );
    assert!(
        stdout.contains("contact compliance      1.600153"),
        "{stdout}"
    );
    assert!(!stdout.contains("Euler-Bernoulli"), "{stdout}");
    let (ok, stdout, stderr) = stickslip(&["estimates", "--scene", scene]);
    assert!(ok, "{stderr}");
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(json["omega"].as_array().unwrap().len(), 4);
    assert!(json["structure"]
        .as_str()
        .unwrap()
        .starts_with("structure, 1002 DOFs"));
    let compliance = json["contact_compliance"].as_f64().unwrap();
    assert!((compliance - 1.600154e-4).abs() < 1e-9, "{compliance}");
    let (ok, _, stderr) = stickslip(&["static", "--scene", scene, "--convergence"]);
    assert!(!ok);
    assert!(
        stderr.contains("static --convergence (and its --out) is the built-in beam's mesh study"),
        "{stderr}"
    );
}
