//! The packaged binary is the portable build (cargo-zigbuild, glibc 2.17 symbol
//! versions): it asks nothing of the system that glibc 2.17 lacks, and it computes
//! exactly what the host build computes.
//!
//! Loading on an old glibc itself cannot be tried on these machines (no glibc older than
//! the host's 2.36 can be installed offline), so the symbol versions are the evidence:
//! the dynamic loader refuses a library exactly when it needs a version its glibc does
//! not define.

use crate::value_reference::vr;
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use fmi::schema::fmi2::{Causality, ScalarVariableElement};
use fmi::traits::FmiImport;
use fmu_build::glibc::{GlibcVersion, Requirements, VersionNeed, FLOOR};
use std::collections::BTreeSet;
use std::ffi::CString;
use std::io::Read;
use std::path::{Path, PathBuf};
use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;
use stickslip::scene::FidelityLevel;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::FmuKind;

/// The binary inside the packaged FMU of `kind`.
fn packaged_binary(kind: FmuKind) -> Vec<u8> {
    let path = fmu_build::fmu_path(kind);
    let file = std::fs::File::open(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; run `cargo run --release -p fmu-build` first",
            path.display()
        )
    });
    let mut archive = zip::ZipArchive::new(file).expect("an FMU is a zip archive");
    let mut binary = Vec::new();
    archive
        .by_name(&format!("binaries/linux64/{}.so", kind.model_identifier()))
        .expect("the FMU carries binaries/linux64/<modelIdentifier>.so")
        .read_to_end(&mut binary)
        .expect("readable");
    binary
}

fn host_library() -> Vec<u8> {
    let path = fmu_build::host_library_path();
    std::fs::read(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; `cargo run --release -p fmu-build` builds it",
            path.display()
        )
    })
}

// ---------------------------------------------------------------------------------------
// Symbol versions.

#[test]
fn packaged_binaries_need_nothing_newer_than_glibc_2_17() {
    for kind in FmuKind::ALL {
        let id = kind.model_identifier();
        let requirements =
            Requirements::of_elf(&packaged_binary(kind)).unwrap_or_else(|e| panic!("{id}.so: {e}"));
        assert!(
            requirements.is_x86_64(),
            "{id}.so: e_machine {}, not x86_64 (binaries/linux64)",
            requirements.machine
        );
        let glibc: Vec<String> = requirements
            .glibc_versions()
            .iter()
            .map(|v| v.to_string())
            .collect();
        // Every Rust cdylib calls into libc; finding no version would mean the reader
        // missed the section, not that the binary needs nothing.
        assert!(
            requirements.versions.iter().any(|n| n.file == "libc.so.6"),
            "{id}.so: no version needed from libc.so.6 was found: {requirements:?}"
        );
        let problems = requirements.problems_on(FLOOR);
        assert!(
            problems.is_empty(),
            "{id}.so does not load on glibc {FLOOR}: it needs {}.\nAll GLIBC versions it needs: {}; libraries: {}.\n(Built with --host-toolchain, or without zig? `bash scripts/zig-env.sh`, then `cargo run --release -p fmu-build`.)",
            problems.join(", "),
            glibc.join(", "),
            requirements.needed.join(", ")
        );
        println!(
            "{id}.so: needs glibc {} or later; GLIBC versions {}; libraries {}",
            requirements
                .oldest_glibc()
                .expect("checked above: it needs libc versions"),
            glibc.join(", "),
            requirements.needed.join(", ")
        );
    }
}

/// The aarch64 Linux binary of both FMI versions is linked like the x86_64 one (zig,
/// glibc 2.17 symbol versions): an aarch64 ELF file that loads on glibc 2.17. Not
/// checked under STICKSLIP_HOST_ONLY, whose FMUs do not carry it.
#[test]
fn aarch64_binaries_need_nothing_newer_than_glibc_2_17() {
    use fmu_build::platform::{packaged_platforms, Platform};
    if !packaged_platforms().contains(&Platform::Aarch64Linux) {
        return;
    }
    const EM_AARCH64: u16 = 183;
    for kind in FmuKind::ALL {
        let id = kind.model_identifier();
        for (version, path) in [
            (2, fmu_build::fmu_path(kind)),
            (3, fmu_build::fmu3_path(kind)),
        ] {
            let entry = Platform::Aarch64Linux.binary_entry(version, id);
            let file = std::fs::File::open(&path).expect("the FMU was built");
            let mut binary = Vec::new();
            zip::ZipArchive::new(file)
                .expect("an FMU is a zip archive")
                .by_name(&entry)
                .unwrap_or_else(|e| panic!("{}: {entry}: {e}", path.display()))
                .read_to_end(&mut binary)
                .expect("readable");
            let requirements =
                Requirements::of_elf(&binary).unwrap_or_else(|e| panic!("{entry}: {e}"));
            assert_eq!(requirements.machine, EM_AARCH64, "{entry}");
            assert!(
                requirements.versions.iter().any(|n| n.file == "libc.so.6"),
                "{entry}: no version needed from libc.so.6 was found: {requirements:?}"
            );
            let problems = requirements.problems_on(FLOOR);
            assert!(
                problems.is_empty(),
                "{entry}: needs {}",
                problems.join(", ")
            );
        }
    }
}

/// `readelf -V` and `readelf -d` (binutils) on `path`: the version needs and the
/// DT_NEEDED libraries, as an independent reading of the same sections.
fn readelf(path: &Path) -> (BTreeSet<VersionNeed>, Vec<String>) {
    let run = |flag: &str| {
        let output = std::process::Command::new("readelf")
            .args([flag, "--wide"])
            .arg(path)
            .output()
            .expect("readelf (binutils) runs");
        assert!(output.status.success(), "readelf {flag} {}", path.display());
        String::from_utf8_lossy(&output.stdout).into_owned()
    };
    // "  000000: Version: 1  File: libc.so.6  Cnt: 5", then
    // "  0x0060:   Name: GLIBC_2.2.5  Flags: none  Version: 3" per version; the version
    // needs section comes last in the output.
    let mut versions = BTreeSet::new();
    let mut file = None;
    let versions_text = run("-V");
    let needs = versions_text
        .split("Version needs section")
        .nth(1)
        .expect("readelf shows a version needs section");
    for line in needs.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if let Some(k) = words.iter().position(|w| *w == "File:") {
            file = words.get(k + 1).map(|s| s.to_string());
        } else if let Some(k) = words.iter().position(|w| *w == "Name:") {
            versions.insert(VersionNeed {
                file: file.clone().expect("a File: line before its versions"),
                version: words[k + 1].to_string(),
            });
        }
    }
    // " 0x0000000000000001 (NEEDED)             Shared library: [libm.so.6]"
    let needed = run("-d")
        .lines()
        .filter(|line| line.contains("(NEEDED)"))
        .filter_map(|line| {
            let start = line.find('[')? + 1;
            let end = line.rfind(']')?;
            Some(line[start..end].to_string())
        })
        .collect();
    (versions, needed)
}

/// The reader agrees with binutils on both builds: on the packaged (portable) binary and
/// on the host build, which needs newer versions on this machine (GLIBC_2.34 on
/// glibc 2.36), so a reader that missed or misread entries would show here.
#[test]
fn the_version_reader_agrees_with_readelf() {
    let dir = scratch_dir("readelf");
    let packaged = dir.join("packaged.so");
    std::fs::write(&packaged, packaged_binary(FmuKind::StickSlipBeam)).unwrap();
    for path in [packaged, fmu_build::host_library_path()] {
        let ours = Requirements::of_elf(&std::fs::read(&path).unwrap())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (versions, needed) = readelf(&path);
        assert!(
            !versions.is_empty(),
            "{}: readelf found no versions",
            path.display()
        );
        assert_eq!(
            ours.versions.iter().cloned().collect::<BTreeSet<_>>(),
            versions,
            "{}: version needs",
            path.display()
        );
        assert_eq!(
            ours.versions.len(),
            versions.len(),
            "{}: duplicates",
            path.display()
        );
        assert_eq!(ours.needed, needed, "{}: DT_NEEDED", path.display());
        println!(
            "{}: {} version needs, newest GLIBC {}",
            path.display(),
            versions.len(),
            ours.oldest_glibc().map_or("none".into(), |v| v.to_string())
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn glibc_versions_order_like_releases_and_problems_are_named() {
    let parse = GlibcVersion::from_symbol_version;
    assert_eq!(parse("GLIBC_2.2.5"), Some(GlibcVersion(2, 2, 5)));
    assert_eq!(parse("GLIBC_2.17"), Some(GlibcVersion(2, 17, 0)));
    assert_eq!(parse("GLIBC_PRIVATE"), None);
    assert_eq!(parse("GCC_3.0"), None);
    assert_eq!(parse("GLIBC_2"), None);
    assert_eq!(parse("GLIBC_2.1.2.3"), None);
    // Numeric, not lexical: 2.3.4 < 2.14 < 2.17 < 2.34.
    assert!(parse("GLIBC_2.3.4") < parse("GLIBC_2.14"));
    assert!(parse("GLIBC_2.14") < parse("GLIBC_2.17"));
    assert!(parse("GLIBC_2.17") < parse("GLIBC_2.34"));
    assert_eq!(FLOOR.to_string(), "2.17");
    assert_eq!(GlibcVersion(2, 3, 4).to_string(), "2.3.4");

    let need = |file: &str, version: &str| VersionNeed {
        file: file.into(),
        version: version.into(),
    };
    let requirements = Requirements {
        machine: 62,
        needed: vec!["libc.so.6".into(), "libgcc_s.so.1".into()],
        versions: vec![
            need("libc.so.6", "GLIBC_2.2.5"),
            need("libc.so.6", "GLIBC_2.17"),
            need("libc.so.6", "GLIBC_2.34"),
            need("libc.so.6", "GLIBC_PRIVATE"),
            need("libgcc_s.so.1", "GCC_3.0"),
        ],
    };
    assert!(requirements.is_x86_64());
    assert_eq!(
        requirements.problems_on(FLOOR),
        [
            "library libgcc_s.so.1 (not part of glibc)",
            "GLIBC_2.34 from libc.so.6",
            "GLIBC_PRIVATE from libc.so.6",
        ]
    );
    assert_eq!(requirements.oldest_glibc(), Some(GlibcVersion(2, 34, 0)));
    assert_eq!(
        requirements.problems_on(GlibcVersion(2, 34, 0)).len(),
        2,
        "2.34 itself is fine; the private version and libgcc_s stay problems"
    );
}

// ---------------------------------------------------------------------------------------
// The portable build computes what the host build computes.

/// Communication step (s), experiment end (s) and steps: the paper scene's default
/// experiment, as in `import`.
const H: f64 = 1e-3;
const STOP: f64 = 1.2;
const STEPS: usize = 1200;

fn scratch_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stickslip-portable-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The two FMUs of `kind` to compare: the packaged one and one packaged the same way
/// around the host build of the library.
fn both(kind: FmuKind, dir: &Path) -> [(&'static str, Fmi2Import); 2] {
    let packaged = packaged_binary(kind);
    assert!(
        packaged != host_library(),
        "the packaged binary is the host build itself (fmu-build --host-toolchain?): nothing to compare"
    );
    let host_fmu = fmu_build::package(
        kind,
        &[(
            fmu_build::platform::Platform::X86_64Linux,
            fmu_build::host_library_path(),
        )],
        dir,
    )
    .expect("package the host library");
    let open = |path: &Path| -> Fmi2Import {
        let import: Fmi2Import = fmi::import::from_path(path)
            .unwrap_or_else(|e| panic!("cannot import {}: {e}", path.display()));
        assert_eq!(
            import.model_description().guid,
            kind.guid(),
            "{} is stale: run `cargo run --release -p fmu-build`",
            path.display()
        );
        import
    };
    [
        ("packaged", open(&fmu_build::fmu_path(kind))),
        ("host", open(&host_fmu)),
    ]
}

/// One output variable: name, value reference and type.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Real,
    Integer,
    Boolean,
}

struct Output {
    name: String,
    vr: u32,
    kind: Kind,
}

/// Every output of the model description (String outputs: none in our FMUs).
fn outputs(import: &Fmi2Import) -> Vec<Output> {
    let outputs: Vec<Output> = import
        .model_description()
        .model_variables
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .map(|v| Output {
            name: v.name.clone(),
            vr: v.value_reference,
            kind: match v.elem {
                ScalarVariableElement::Real(_) => Kind::Real,
                ScalarVariableElement::Integer(_) | ScalarVariableElement::Enumeration => {
                    Kind::Integer
                }
                ScalarVariableElement::Boolean(_) => Kind::Boolean,
                ScalarVariableElement::String => panic!("{}: a String output", v.name),
            },
        })
        .collect();
    assert!(!outputs.is_empty(), "the FMU declares outputs");
    outputs
}

/// Every output now, as bits: equal bits mean the same result, +0 and -0 told apart.
fn sample(inst: &mut InstanceCS, outputs: &[Output]) -> Vec<u64> {
    outputs
        .iter()
        .map(|o| match o.kind {
            Kind::Real => {
                let mut v = [0.0];
                inst.get_real(&[o.vr], &mut v).expect("fmi2GetReal");
                v[0].to_bits()
            }
            Kind::Integer => {
                let mut v = [0];
                inst.get_integer(&[o.vr], &mut v).expect("fmi2GetInteger");
                v[0] as u32 as u64
            }
            Kind::Boolean => {
                let mut v = [0];
                inst.get_boolean(&[o.vr], &mut v).expect("fmi2GetBoolean");
                (v[0] != 0) as u64
            }
        })
        .collect()
}

/// Parameters set in initialization mode.
enum Parameter {
    Integer(&'static str, i32),
    String(&'static str, &'static str),
}

/// An initialised instance over [0, `stop`] (None: open-ended).
fn start(
    import: &Fmi2Import,
    name: &str,
    stop: Option<f64>,
    parameters: &[Parameter],
) -> InstanceCS {
    let mut inst = import
        .instantiate_cs(name, false, false)
        .unwrap_or_else(|e| panic!("{name}: fmi2Instantiate failed: {e}"));
    inst.setup_experiment(None, 0.0, stop)
        .expect("fmi2SetupExperiment");
    Common::enter_initialization_mode(&mut inst).expect("fmi2EnterInitializationMode");
    for parameter in parameters {
        match *parameter {
            Parameter::Integer(variable, value) => inst
                .set_integer(&[vr(import, variable)], &[value])
                .map(|_| ())
                .unwrap_or_else(|e| panic!("{name}: {variable} = {value}: {e}")),
            Parameter::String(variable, value) => inst
                .set_string(&[vr(import, variable)], &[CString::new(value).unwrap()])
                .unwrap_or_else(|e| panic!("{name}: {variable} = {value}: {e}")),
        }
    }
    Common::exit_initialization_mode(&mut inst).expect("fmi2ExitInitializationMode");
    inst
}

/// Asserts equal bits at every sample; names the first differing output.
fn assert_bitwise(what: &str, outputs: &[Output], packaged: &[Vec<u64>], host: &[Vec<u64>]) {
    assert_eq!(packaged.len(), host.len(), "{what}: sample counts");
    for (k, (p, h)) in packaged.iter().zip(host).enumerate() {
        if let Some(j) = (0..p.len()).find(|&j| p[j] != h[j]) {
            let show = |bits: u64| match outputs[j].kind {
                Kind::Real => format!("{:e}", f64::from_bits(bits)),
                _ => bits.to_string(),
            };
            panic!(
                "{what}: sample {k}, {}: packaged {} != host {} (bits {:#x} / {:#x})",
                outputs[j].name,
                show(p[j]),
                show(h[j]),
                p[j],
                h[j]
            );
        }
    }
}

/// The paper scene in StickSlipBeam at the modal and beam fidelity levels with the
/// exponential law, the plain network and the signed network: every output at every
/// communication point of [0, 1.2 s] is the same in the packaged FMU as in the host
/// build. The libm functions the physics calls (exp, tanh, ...) bind to other symbol
/// versions in the portable build (exp@GLIBC_2.2.5 instead of exp@GLIBC_2.29), so this
/// is where a different implementation would show.
#[test]
fn packaged_stick_slip_beam_equals_the_host_build_bit_for_bit() {
    let dir = scratch_dir("beam");
    let fmus = both(FmuKind::StickSlipBeam, &dir);
    let outputs = outputs(&fmus[0].1);
    let laws: [(&str, FrictionLawKind, Option<&'static str>); 3] = [
        ("exponential", FrictionLawKind::Exponential, None),
        (
            "neural-plain",
            FrictionLawKind::Neural,
            Some("paper-plain.json"),
        ),
        (
            "neural-signed",
            FrictionLawKind::Neural,
            Some("paper-signed.json"),
        ),
    ];
    for level in [FidelityLevel::Modal, FidelityLevel::Beam] {
        for (law_name, law, weights) in laws {
            let tag = format!("{}-{law_name}", level.name());
            let mut parameters = vec![
                Parameter::Integer("fidelity.level", level.code()),
                Parameter::Integer("friction.law", law.code()),
            ];
            if let Some(weights) = weights {
                parameters.push(Parameter::String("friction.weights", weights));
            }
            let runs: Vec<Vec<Vec<u64>>> = fmus
                .iter()
                .map(|(which, import)| {
                    let mut inst =
                        start(import, &format!("{which}-{tag}"), Some(STOP), &parameters);
                    let mut samples = vec![sample(&mut inst, &outputs)];
                    let mut t = 0.0;
                    for _ in 0..STEPS {
                        inst.do_step(t, H, true)
                            .unwrap_or_else(|e| panic!("{which} {tag}: fmi2DoStep at {t} s: {e}"));
                        t += H;
                        samples.push(sample(&mut inst, &outputs));
                    }
                    Common::terminate(&mut inst).expect("fmi2Terminate");
                    samples
                })
                .collect();
            assert_bitwise(&tag, &outputs, &runs[0], &runs[1]);

            // Not a trivial run: the tip sticks, breaks away and moves.
            let column = |name: &str| {
                outputs
                    .iter()
                    .position(|o| o.name == name)
                    .unwrap_or_else(|| panic!("no output {name}"))
            };
            let deflection = column("tip_deflection");
            let transitions = column("transitions");
            let peak = runs[0]
                .iter()
                .map(|s| f64::from_bits(s[deflection]).abs())
                .fold(0.0, f64::max);
            let count = runs[0][STEPS][transitions];
            assert!(
                peak > 1e-3 && count >= 2,
                "{tag}: peak {peak} m, {count} transitions"
            );
            println!(
                "{tag}: {} samples x {} outputs bitwise equal; peak tip deflection {:.4} mm, {count} transitions",
                STEPS + 1,
                outputs.len(),
                peak * 1e3
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// NeuralFriction with both laws over velocities from -0.5 to 0.5 m/s (through the
/// jump at 0 and past the network's clamped input range) and three normal forces: every
/// output equal bit for bit in the packaged FMU and the host build.
#[test]
fn packaged_neural_friction_equals_the_host_build_bit_for_bit() {
    let dir = scratch_dir("friction");
    let fmus = both(FmuKind::NeuralFriction, &dir);
    let outputs = outputs(&fmus[0].1);
    let velocities: Vec<f64> = (-500..=500)
        .map(|k| k as f64 * 1e-3)
        .chain([1e-9, -1e-9, 0.0, -0.0])
        .collect();
    for law in [NeuralFrictionLaw::EXPONENTIAL, NeuralFrictionLaw::NEURAL] {
        let parameters = [Parameter::Integer("law", law.code())];
        let runs: Vec<Vec<Vec<u64>>> = fmus
            .iter()
            .map(|(which, import)| {
                let name = format!("{which}-friction-{}", law.name());
                // Open-ended: the sweep takes 3015 steps of H, past the paper's 1.2 s.
                let mut inst = start(import, &name, None, &parameters);
                let inputs = [vr(import, "sliding_velocity"), vr(import, "normal_force")];
                let mut samples = Vec::new();
                let mut t = 0.0;
                for normal in [0.0, 50.0, 100.0] {
                    for &v in &velocities {
                        inst.set_real(&inputs, &[v, normal]).expect("set inputs");
                        inst.do_step(t, H, true)
                            .unwrap_or_else(|e| panic!("{name}: fmi2DoStep at {t} s: {e}"));
                        t += H;
                        samples.push(sample(&mut inst, &outputs));
                    }
                }
                Common::terminate(&mut inst).expect("fmi2Terminate");
                samples
            })
            .collect();
        assert_bitwise(law.name(), &outputs, &runs[0], &runs[1]);
        println!(
            "NeuralFriction, {}: {} samples x {} outputs bitwise equal",
            law.name(),
            runs[0].len(),
            outputs.len()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
