//! `--law-parameter NAME=VALUE`: any law's parameter by its registry name, the same run
//! as the older shortcut flag and as the scene file's table, and refusals that name the
//! parameters.

use crate::stickslip;

const RUN: [&str; 8] = [
    "simulate",
    "--fidelity",
    "modal",
    "--modes",
    "4",
    "--t-end",
    "0.8",
    "--every",
];

/// The run's samples (the CSV `--out` writes; stdout has the wall time).
fn run(extra: &[&str]) -> String {
    let csv = std::env::temp_dir().join(format!(
        "law-parameter-{}-{}.csv",
        std::process::id(),
        extra.join("_").replace(['/', '='], "-")
    ));
    let mut args: Vec<&str> = RUN.to_vec();
    args.push("50");
    args.extend(extra);
    args.extend(["--out", csv.to_str().unwrap()]);
    let (ok, _, err) = stickslip(&args);
    assert!(ok, "{args:?}: {err}");
    let samples = std::fs::read_to_string(&csv).unwrap();
    let _ = std::fs::remove_file(&csv);
    samples
}

#[test]
fn a_law_parameter_by_name_is_the_shortcut_flag_and_the_scene_table() {
    let by_name = run(&[
        "--friction",
        "lugre",
        "--law-parameter",
        "lugre.bristle_stiffness=2e5",
    ]);
    let by_flag = run(&["--friction", "lugre", "--bristle-stiffness", "2e5"]);
    assert_eq!(by_name, by_flag);
    let scene = std::env::temp_dir().join(format!("law-parameter-{}.toml", std::process::id()));
    std::fs::write(&scene, "[friction.lugre]\nbristle_stiffness = 2e5\n").unwrap();
    let by_file = run(&["--friction", "lugre", "--scene", scene.to_str().unwrap()]);
    let _ = std::fs::remove_file(&scene);
    assert_eq!(by_name, by_file);
    // The default stiffness is another run.
    assert_ne!(by_name, run(&["--friction", "lugre"]));
    // A choice by its word.
    assert_eq!(
        run(&[
            "--friction",
            "rate-and-state",
            "--law-parameter",
            "rate_and_state.state_evolution=slip"
        ]),
        run(&["--friction", "rate-and-state", "--state-evolution", "slip"])
    );
}

#[test]
fn a_wrong_name_or_value_is_refused_naming_the_parameters() {
    for (assignment, says) in [
        (
            "lugre.stiffness=1",
            "the parameters are lugre.bristle_stiffness",
        ),
        ("lugre.bristle_stiffness", "expected NAME=VALUE"),
        ("lugre.bristle_stiffness=stiff", "is not a number"),
        (
            "rate_and_state.state_evolution=ageing",
            "possible values: aging, slip",
        ),
    ] {
        let (ok, _, err) = stickslip(&["simulate", "--law-parameter", assignment]);
        assert!(!ok, "{assignment} accepted");
        assert!(err.contains(says), "{assignment}: {err}");
    }
    // In range is the scene's check, by the parameter's name.
    let (ok, _, err) = stickslip(&[
        "simulate",
        "--friction",
        "lugre",
        "--law-parameter",
        "lugre.bristle_stiffness=-1",
    ]);
    assert!(!ok);
    assert!(
        err.contains("friction.lugre.bristle_stiffness") && err.contains("> 0 (N/m)"),
        "{err}"
    );
}
