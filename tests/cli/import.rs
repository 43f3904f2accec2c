//! `stickslip import-network`: an ONNX file as our weights file, described by its
//! metadata or by flags, checked on data. The ONNX files are the fuzz seeds
//! (fuzz/corpus/onnx, written by `stickslip_tests::onnx`, which this package cannot
//! depend on), small exports in PyTorch form.

use std::path::{Path, PathBuf};
use stickslip::neural::NeuralLaw;

use super::stickslip;

/// `stickslip import-network ONNX --out OUT` and `extra` flags.
fn import(onnx: &Path, out: &Path, extra: &[&str]) -> (bool, String, String) {
    let mut args = vec![
        "import-network",
        onnx.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    stickslip(&args)
}

fn seed(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/corpus/onnx")
        .join(name)
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stickslip-cli-import-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// (v, F_n) on a 41 x 11 grid over the seeds' training box.
fn grid() -> Vec<[f64; 2]> {
    let mut points = Vec::new();
    for i in 0..41 {
        for j in 0..11 {
            points.push([
                -0.37 + 0.73 * i as f64 / 40.0,
                90.5 + 19.0 * j as f64 / 10.0,
            ]);
        }
    }
    points
}

fn forces(law: &mut NeuralLaw, points: &[[f64; 2]]) -> Vec<f64> {
    points.iter().map(|p| law.evaluate(p).unwrap()).collect()
}

/// The JSON written round-trips bit for bit: it evaluates as the ONNX file itself does
/// when read as weights, and it is the same model.
#[test]
fn import_network_writes_weights_that_evaluate_as_the_onnx_file() {
    for name in [
        "seed-torch-f64-tanh-2-4-1.onnx",
        "seed-torch-f32-sigmoid-2-3-2-1.onnx",
        "seed-skl-f32-relu-2-4-1.onnx",
        "seed-torch-f64-signed-2-3-1.onnx",
    ] {
        let onnx = seed(name);
        let out = scratch(&format!("{name}.json"));
        let (ok, stdout, stderr) = import(&onnx, &out, &[]);
        assert!(ok, "{name}: {stderr}");
        assert!(stdout.contains("wrote"), "{stdout}");
        let direct = NeuralLaw::from_file(&onnx).unwrap();
        let mut written = NeuralLaw::from_file(&out).unwrap();
        assert_eq!(written.model(), direct.model(), "{name}");
        let points = grid();
        let (a, b) = (
            forces(&mut direct.clone(), &points),
            forces(&mut written, &points),
        );
        assert!(
            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "{name}"
        );
        std::fs::remove_file(out).unwrap();
    }
}

/// `--check-data`: MSE and R^2 of the imported network against the CSV's target, and the
/// largest difference from a prediction column. The target is the network's own force
/// plus +-0.5 N alternating (so MSE = 0.25 exactly up to rounding), the prediction column
/// the network's force with 1e-3 N added on one row (so the largest difference is
/// 1e-3 N).
#[test]
fn check_data_prints_mse_r2_and_the_largest_difference() {
    let onnx = seed("seed-torch-f64-tanh-2-4-1.onnx");
    let mut law = NeuralLaw::from_file(&onnx).unwrap();
    let points = grid();
    let f = forces(&mut law, &points);
    let mut csv = String::from("sliding_velocity[m/s],normal_force[N],friction_force[N],ort\n");
    for (k, (p, f)) in points.iter().zip(&f).enumerate() {
        let noise = if k % 2 == 0 { 0.5 } else { -0.5 };
        let prediction = if k == 7 { f + 1e-3 } else { *f };
        csv += &format!("{:?},{:?},{:?},{prediction:?}\n", p[0], p[1], f + noise);
    }
    let data = scratch("check.csv");
    std::fs::write(&data, csv).unwrap();
    let out = scratch("check.json");
    let (ok, stdout, stderr) = import(
        &onnx,
        &out,
        &[
            "--check-data",
            data.to_str().unwrap(),
            "--prediction-column",
            "ort",
        ],
    );
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("(451 samples): MSE = 2.500000e-1"),
        "{stdout}"
    );
    let mean = f.iter().sum::<f64>() / f.len() as f64;
    let ss_tot: f64 = f
        .iter()
        .enumerate()
        .map(|(k, x)| {
            let t = x + if k % 2 == 0 { 0.5 } else { -0.5 };
            (t - mean).powi(2)
        })
        .sum();
    let r2 = 1.0 - 0.25 * f.len() as f64 / ss_tot;
    // ss_tot's mean is the forces' (the noise's mean is 0.5/451): r2 to ~1e-6.
    let printed: f64 = stdout
        .split("R^2 = ")
        .nth(1)
        .and_then(|s| s.lines().next())
        .unwrap()
        .parse()
        .unwrap();
    assert!((printed - r2).abs() < 1e-5, "{printed} vs {r2}: {stdout}");
    assert!(
        stdout.contains("against column ort: largest |difference| = 1.000e-3 N"),
        "{stdout}"
    );
    std::fs::remove_file(out).unwrap();
    std::fs::remove_file(data).unwrap();
}

/// A file without `stickslip.features` is refused naming the key and the flags; with
/// `--feature` flags (one per column) it imports, the flags naming and ranging the
/// inputs; malformed flags are refused by name.
#[test]
fn features_come_from_flags_when_the_file_has_none() {
    let onnx = seed("seed-torch-f64-no-metadata-2-2-1.onnx");
    let out = scratch("bare.json");
    let (ok, _, stderr) = import(&onnx, &out, &[]);
    assert!(!ok);
    for part in ["stickslip.features", "--feature NAME:ROLE:UNIT:MIN:MAX"] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    assert!(!out.exists());
    let (ok, stdout, stderr) = import(
        &onnx,
        &out,
        &[
            "--feature",
            "v:sliding_velocity:m/s:-0.5:0.5",
            "--feature",
            "load:normal_force:N:80:120",
            "--target",
            "F:N:-60:60",
            "--variant",
            "plain",
        ],
    );
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("v [m/s] sliding_velocity -0.5..0.5"),
        "{stdout}"
    );
    let model = NeuralLaw::from_file(&out).unwrap().model().clone();
    assert_eq!(model.features[1].name, "load");
    assert_eq!(model.features[1].max, 120.0);
    assert_eq!(model.target.name, "F");
    std::fs::remove_file(&out).unwrap();

    for (flag, value, expected) in [
        ("--feature", "v:speed:m/s:0:1", "role 'speed'"),
        ("--feature", "v:sliding_velocity:0:1", "got 4 field(s)"),
        (
            "--feature",
            "v:other::0:nan",
            "MAX 'nan' is not a finite number",
        ),
        ("--target", "F:N:0", "expected NAME:UNIT:MIN:MAX"),
    ] {
        let (ok, _, stderr) = import(&onnx, &out, &[flag, value]);
        assert!(!ok);
        assert!(stderr.contains(expected), "{value}: {stderr}");
    }
    // One --feature for a two-input network.
    let (ok, _, stderr) = import(
        &onnx,
        &out,
        &["--feature", "v:sliding_velocity:m/s:-0.5:0.5"],
    );
    assert!(!ok);
    assert!(
        stderr.contains("1 features are described but the network has 2 inputs"),
        "{stderr}"
    );
}

/// `simulate --weights` takes the .onnx file: the run is the one of the JSON that
/// import-network writes from it, byte for byte.
#[test]
fn simulate_takes_an_onnx_file_as_weights() {
    let onnx = seed("seed-torch-f32-sigmoid-2-3-2-1.onnx");
    let json = scratch("simulate.json");
    let (ok, _, stderr) = import(&onnx, &json, &[]);
    assert!(ok, "{stderr}");
    let mut runs = Vec::new();
    for weights in [&onnx, &json] {
        let csv = scratch(&format!("simulate-{}.csv", runs.len()));
        let mut args: Vec<&str> = "simulate --friction neural --fidelity modal --t-end 0.5"
            .split(' ')
            .collect();
        args.extend(["--weights", weights.to_str().unwrap()]);
        args.extend(["--out", csv.to_str().unwrap()]);
        let (ok, stdout, stderr) = stickslip(&args);
        assert!(ok, "{stderr}");
        assert!(stdout.contains("breakaway time"), "{stdout}");
        runs.push(std::fs::read(&csv).unwrap());
        std::fs::remove_file(csv).unwrap();
    }
    assert!(runs[0] == runs[1], "the .onnx and its JSON ran differently");
    std::fs::remove_file(json).unwrap();
}

/// A MATLAB .mat file (the paper authors' fitrnet network) is refused with the Python
/// command that converts it, naming the file and the output, and nothing is written.
#[test]
fn a_mat_file_is_refused_with_the_python_command() {
    let mat = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/paper-authors/trained_regression_nn_friction_model.mat");
    let out = scratch("authors.json");
    let (ok, _, stderr) = import(&mat, &out, &[]);
    assert!(!ok);
    assert!(stderr.contains("MCOS"), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "python -m stickslip_checks.import_fitrnet {} --out {} --weights-out {}",
            mat.display(),
            out.with_extension("onnx").display(),
            out.display()
        )),
        "{stderr}"
    );
    assert!(!out.exists());
    // Recognised by its header too, whatever its name.
    let renamed = scratch("authors.bin");
    std::fs::copy(&mat, &renamed).unwrap();
    let (ok, _, stderr) = import(&renamed, &out, &[]);
    assert!(!ok && stderr.contains("import_fitrnet"), "{stderr}");
    std::fs::remove_file(renamed).unwrap();
}
