//! The packaged binaries export exactly the 34 FMI 2.0 co-simulation functions and
//! nothing else of ours, and each archive holds what an importer expects.

use std::collections::BTreeSet;
use std::io::Read;
use stickslip_fmi::FmuKind;

const FMI2_FUNCTIONS: [&str; 34] = [
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
];

fn open(kind: FmuKind) -> zip::ZipArchive<std::fs::File> {
    let path = fmu_build::fmu_path(kind);
    let file = std::fs::File::open(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; run `cargo run --release -p fmu-build` first",
            path.display()
        )
    });
    zip::ZipArchive::new(file).unwrap()
}

#[test]
fn archives_hold_description_binary_and_weights() {
    for kind in FmuKind::ALL {
        let mut archive = open(kind);
        let names: BTreeSet<String> = (0..archive.len())
            .map(|k| archive.by_index(k).unwrap().name().unwrap().into_owned())
            .collect();
        let id = kind.model_identifier();
        let expected: BTreeSet<String> = [
            "modelDescription.xml".to_string(),
            format!("binaries/linux64/{id}.so"),
            "resources/paper-plain.json".into(),
            "resources/paper-signed.json".into(),
        ]
        .into_iter()
        .collect();
        assert_eq!(names, expected);
        let mut xml = String::new();
        archive
            .by_name("modelDescription.xml")
            .unwrap()
            .read_to_string(&mut xml)
            .unwrap();
        assert_eq!(xml, kind.model_description(), "{id}: stale FMU; rebuild it");
        for name in ["paper-plain.json", "paper-signed.json"] {
            let mut packed = Vec::new();
            archive
                .by_name(&format!("resources/{name}"))
                .unwrap()
                .read_to_end(&mut packed)
                .unwrap();
            let shipped =
                std::fs::read(fmu_build::workspace_root().join("weights").join(name)).unwrap();
            assert!(
                packed == shipped,
                "{id}: resources/{name} differs from weights/{name}"
            );
        }
    }
}

/// The library reads the networks from `resources/`; it does not carry the signed
/// network's 0.66 MB of JSON itself. (The plain network stays linked: `fidelity = auto`
/// calibrates a neural scene with the shipped default law, `stickslip::neural`.)
#[test]
fn the_library_does_not_embed_the_signed_network() {
    let mut archive = open(FmuKind::StickSlipBeam);
    let mut binary = Vec::new();
    archive
        .by_name("binaries/linux64/StickSlipBeam.so")
        .unwrap()
        .read_to_end(&mut binary)
        .unwrap();
    let weights =
        std::fs::read(fmu_build::workspace_root().join("weights/paper-signed.json")).unwrap();
    let probe = &weights[weights.len() / 2..weights.len() / 2 + 64];
    assert!(
        !binary.windows(probe.len()).any(|w| w == probe),
        "the signed network's JSON is linked into the FMU binary"
    );
}

#[test]
fn binaries_export_exactly_the_fmi2_functions() {
    let dir = std::env::temp_dir().join(format!("stickslip-symbols-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for kind in FmuKind::ALL {
        let mut archive = open(kind);
        let id = kind.model_identifier();
        let mut binary = Vec::new();
        archive
            .by_name(&format!("binaries/linux64/{id}.so"))
            .unwrap()
            .read_to_end(&mut binary)
            .unwrap();
        let so = dir.join(format!("{id}.so"));
        std::fs::write(&so, binary).unwrap();
        let output = std::process::Command::new("nm")
            .args(["-D", "--defined-only", "--format=posix"])
            .arg(&so)
            .output()
            .expect("nm (binutils) runs");
        assert!(output.status.success());
        let exported: BTreeSet<String> = String::from_utf8_lossy(&output.stdout)
            .lines()
            .filter_map(|line| line.split_whitespace().next().map(str::to_owned))
            .collect();
        let expected: BTreeSet<String> = FMI2_FUNCTIONS.iter().map(|s| s.to_string()).collect();
        assert_eq!(exported, expected, "{id}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn packaging_is_reproducible() {
    let library = fmu_build::target_dir()
        .join("release")
        .join("libstickslip_fmi.so");
    let dir = std::env::temp_dir().join(format!("stickslip-repro-{}", std::process::id()));
    let first = fmu_build::package(FmuKind::NeuralFriction, &library, &dir.join("a")).unwrap();
    let second = fmu_build::package(FmuKind::NeuralFriction, &library, &dir.join("b")).unwrap();
    assert_eq!(
        std::fs::read(first).unwrap(),
        std::fs::read(second).unwrap()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A failure names the file it concerns, in the words `fmu-build` prints.
#[test]
fn packaging_errors_name_the_file() {
    let dir = std::env::temp_dir().join(format!("stickslip-missing-{}", std::process::id()));
    let missing = dir.join("libmissing.so");
    let error = fmu_build::package(FmuKind::NeuralFriction, &missing, &dir).unwrap_err();
    assert!(
        matches!(&error, fmu_build::BuildError::Io { path, .. } if *path == missing),
        "{error:?}"
    );
    assert!(
        error
            .to_string()
            .starts_with(&format!("{}: ", missing.display())),
        "{error}"
    );
    let drift = fmu_build::BuildError::Drift(vec!["a.xml".into(), "b.xml".into()]);
    assert!(
        drift
            .to_string()
            .starts_with("a.xml, b.xml differ from what the Rust tables generate"),
        "{drift}"
    );
    assert!(
        !dir.exists(),
        "nothing is written when the library is missing"
    );
}
