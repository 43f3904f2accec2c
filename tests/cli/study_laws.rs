//! `stickslip study --laws`: the law axis is parsed and refused with the reason, and a
//! study over two laws writes one front per law and study.csv's law column.

use crate::stickslip;

fn out_dir(tag: &str) -> std::path::PathBuf {
    let dir =
        std::env::temp_dir().join(format!("stickslip-study-laws-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn laws_that_cannot_be_on_the_axis_are_refused_with_the_reason() {
    for (law, reason) in [
        (
            "external",
            "its force comes from StickSlipBeam.fmu's inputs",
        ),
        ("lugre:w.json", "only the neural law takes a weights file"),
        (
            "dahl",
            "expected one of exponential, coulomb, neural, lugre, rate-and-state",
        ),
    ] {
        let (ok, _, err) = stickslip(&["study", "--laws", law, "--modes", "1"]);
        assert!(!ok, "{law} accepted");
        assert!(err.contains(reason), "{law}: {err}");
    }
    // front.json is the scene law's front, the one `auto` reads: a law axis without the
    // scene's law has none to write.
    let (ok, _, err) = stickslip(&["study", "--laws", "lugre", "--write-front", "f.json"]);
    assert!(!ok);
    assert_eq!(
        err.lines().last(),
        Some("error: --write-front writes the front of the scene's law (exponential), which --laws leaves out")
    );
}

#[test]
fn a_study_of_two_laws_writes_a_front_per_law_and_a_law_column() {
    let dir = out_dir("two");
    let (ok, stdout, err) = stickslip(&[
        "study",
        "--laws",
        "exponential,lugre",
        "--t-end",
        "0.05",
        "--modes",
        "1",
        "--elements",
        "--element-sizes",
        "--plane-stress-modal",
        "--dts",
        "1e-3,5e-4",
        "--integrators",
        "generalized-alpha",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(
        stdout.contains("Pareto front of exponential") && stdout.contains("Pareto front of lugre"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(dir.join("study.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let column = header
        .iter()
        .position(|h| *h == "law")
        .expect("a law column");
    let laws: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(column).unwrap())
        .collect();
    // Two configurations per law, the finest (dt 5e-4 s) the law's reference, left out.
    assert_eq!(laws, ["exponential", "lugre"]);
    let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
    assert_eq!(read("front.json"), read("front-exponential.json"));
    assert_ne!(read("front-lugre.json"), read("front-exponential.json"));
    std::fs::remove_dir_all(&dir).ok();
}
