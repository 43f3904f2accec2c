//! The packaged binaries export exactly the 34 FMI 2.0 co-simulation functions and the
//! 75 FMI 3.0 functions and nothing else of ours, and each archive holds what an
//! importer expects.

use fmu_build::platform::{packaged_platforms, Platform};
use std::collections::BTreeSet;
use std::io::Read;
use stickslip_fmi::FmuKind;

/// Every function of fmi3Functions.h (FMI 3.0, all three interface types: an FMU
/// exports them all; those of capabilities ours lack return fmi3Error).
const FMI3_FUNCTIONS: [&str; 75] = [
    "fmi3GetVersion",
    "fmi3SetDebugLogging",
    "fmi3InstantiateModelExchange",
    "fmi3InstantiateCoSimulation",
    "fmi3InstantiateScheduledExecution",
    "fmi3FreeInstance",
    "fmi3EnterInitializationMode",
    "fmi3ExitInitializationMode",
    "fmi3EnterEventMode",
    "fmi3Terminate",
    "fmi3Reset",
    "fmi3GetFloat32",
    "fmi3GetFloat64",
    "fmi3GetInt8",
    "fmi3GetUInt8",
    "fmi3GetInt16",
    "fmi3GetUInt16",
    "fmi3GetInt32",
    "fmi3GetUInt32",
    "fmi3GetInt64",
    "fmi3GetUInt64",
    "fmi3GetBoolean",
    "fmi3GetString",
    "fmi3GetBinary",
    "fmi3GetClock",
    "fmi3SetFloat32",
    "fmi3SetFloat64",
    "fmi3SetInt8",
    "fmi3SetUInt8",
    "fmi3SetInt16",
    "fmi3SetUInt16",
    "fmi3SetInt32",
    "fmi3SetUInt32",
    "fmi3SetInt64",
    "fmi3SetUInt64",
    "fmi3SetBoolean",
    "fmi3SetString",
    "fmi3SetBinary",
    "fmi3SetClock",
    "fmi3GetNumberOfVariableDependencies",
    "fmi3GetVariableDependencies",
    "fmi3GetFMUState",
    "fmi3SetFMUState",
    "fmi3FreeFMUState",
    "fmi3SerializedFMUStateSize",
    "fmi3SerializeFMUState",
    "fmi3DeserializeFMUState",
    "fmi3GetDirectionalDerivative",
    "fmi3GetAdjointDerivative",
    "fmi3EnterConfigurationMode",
    "fmi3ExitConfigurationMode",
    "fmi3GetIntervalDecimal",
    "fmi3GetIntervalFraction",
    "fmi3GetShiftDecimal",
    "fmi3GetShiftFraction",
    "fmi3SetIntervalDecimal",
    "fmi3SetIntervalFraction",
    "fmi3SetShiftDecimal",
    "fmi3SetShiftFraction",
    "fmi3EvaluateDiscreteStates",
    "fmi3UpdateDiscreteStates",
    "fmi3EnterContinuousTimeMode",
    "fmi3CompletedIntegratorStep",
    "fmi3SetTime",
    "fmi3SetContinuousStates",
    "fmi3GetContinuousStateDerivatives",
    "fmi3GetEventIndicators",
    "fmi3GetContinuousStates",
    "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfEventIndicators",
    "fmi3GetNumberOfContinuousStates",
    "fmi3EnterStepMode",
    "fmi3GetOutputDerivatives",
    "fmi3DoStep",
    "fmi3ActivateModelPartition",
];

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
        // Every platform's binary (x86_64 Linux alone under STICKSLIP_HOST_ONLY=1).
        let weights = stickslip_fmi::networks::WEIGHTS_RESOURCES;
        let expected: BTreeSet<String> = ["modelDescription.xml".to_string()]
            .into_iter()
            .chain(weights.iter().map(|name| format!("resources/{name}")))
            .chain(
                packaged_platforms()
                    .into_iter()
                    .map(|p| p.binary_entry(2, id)),
            )
            .collect();
        // The two networks and the learned law with memory.
        assert!(weights.contains(&"rate-and-state-learned.json"));
        assert_eq!(names, expected);
        let mut xml = String::new();
        archive
            .by_name("modelDescription.xml")
            .unwrap()
            .read_to_string(&mut xml)
            .unwrap();
        assert_eq!(xml, kind.model_description(), "{id}: stale FMU; rebuild it");
        for name in weights {
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
fn binaries_export_exactly_the_fmi2_and_fmi3_functions() {
    let dir = std::env::temp_dir().join(format!("stickslip-symbols-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fmi3 = |kind: FmuKind| {
        let path = fmu_build::fmu3_path(kind);
        let file = std::fs::File::open(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; run `cargo run --release -p fmu-build` first",
                path.display()
            )
        });
        (zip::ZipArchive::new(file).unwrap(), "x86_64-linux")
    };
    let archives = FmuKind::ALL
        .into_iter()
        .flat_map(|kind| [(kind, (open(kind), "linux64")), (kind, fmi3(kind))]);
    for (kind, (mut archive, platform)) in archives {
        let id = kind.model_identifier();
        let mut binary = Vec::new();
        archive
            .by_name(&format!("binaries/{platform}/{id}.so"))
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
        let expected: BTreeSet<String> = FMI2_FUNCTIONS
            .iter()
            .chain(&FMI3_FUNCTIONS)
            .map(|s| s.to_string())
            .collect();
        assert_eq!(exported, expected, "{id} ({platform})");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn packaging_is_reproducible() {
    let library = fmu_build::target_dir()
        .join("release")
        .join("libstickslip_fmi.so");
    let dir = std::env::temp_dir().join(format!("stickslip-repro-{}", std::process::id()));
    let binaries = [(Platform::X86_64Linux, library)];
    for package in [fmu_build::package, fmu_build::package3] {
        let first = package(FmuKind::NeuralFriction, &binaries, &dir.join("a")).unwrap();
        let second = package(FmuKind::NeuralFriction, &binaries, &dir.join("b")).unwrap();
        assert_eq!(
            std::fs::read(first).unwrap(),
            std::fs::read(second).unwrap()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A failure names the file it concerns, in the words `fmu-build` prints.
#[test]
fn packaging_errors_name_the_file() {
    let dir = std::env::temp_dir().join(format!("stickslip-missing-{}", std::process::id()));
    let missing = dir.join("libmissing.so");
    let error = fmu_build::package(
        FmuKind::NeuralFriction,
        &[(Platform::X86_64Linux, missing.clone())],
        &dir,
    )
    .unwrap_err();
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
