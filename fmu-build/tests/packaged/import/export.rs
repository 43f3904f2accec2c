//! Exported FMUs (`stickslip export-fmu`, `fmu_build::export`) imported with the `fmi`
//! crate: the default paper scene and the CalculiX beam (examples/calculix-beam), run to
//! 0.5 s, equal bit for bit to the library's run of the same scene file read as
//! `stickslip simulate` reads it; a tampered resources/scene.toml refused at
//! instantiation.
//!
//! The `--from` FMU is packaged here from the host build of this source tree's library
//! (`fmu_build::build_library`, x86_64 Linux only), so that the binary is the code under
//! test, not whatever `target/fmu/` holds.

use super::*;
use fmu_build::archive::{write_zip, Entry};
use fmu_build::platform::Platform;
use std::io::Read as _;
use std::path::Path;
use std::sync::OnceLock;
use stickslip::scene::Scene;

/// Communication steps to 0.5 s: past the paper's breakaway (0.4 s) into slip.
pub(super) const EXPORT_STEPS: usize = 500;

/// A scratch folder of this test process.
fn scratch() -> PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("stickslip-export-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch folder");
        dir
    })
    .clone()
}

/// StickSlipBeam.fmu of FMI `version` (2 or 3) around the host build of this tree's
/// library.
fn from_fmu(version: u8) -> PathBuf {
    static LIBRARY: OnceLock<PathBuf> = OnceLock::new();
    static FMUS: Mutex<Vec<(u8, PathBuf)>> = Mutex::new(Vec::new());
    let library = LIBRARY
        .get_or_init(|| fmu_build::build_library().expect("the host build of stickslip-fmi"));
    let mut fmus = FMUS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, path)) = fmus.iter().find(|(v, _)| *v == version) {
        return path.clone();
    }
    let dir = scratch().join(format!("from{version}"));
    let binaries = [(Platform::X86_64Linux, library.clone())];
    let path = if version == 2 {
        fmu_build::package(FmuKind::StickSlipBeam, &binaries, &dir)
    } else {
        fmu_build::package3(FmuKind::StickSlipBeam, &binaries, &dir)
    }
    .expect("StickSlipBeam.fmu packaged from the host library");
    fmus.push((version, path.clone()));
    path
}

/// Exports `scene` as `<name>.fmu` (FMI 2.0) in the scratch folder.
fn export(scene: &Path, name: &str) -> PathBuf {
    export_as(scene, name, 2)
}

/// Exports `scene` as `<name>.fmu` of FMI `version` in the scratch folder.
pub(super) fn export_as(scene: &Path, name: &str, version: u8) -> PathBuf {
    let out = scratch().join(format!("{name}.fmu"));
    let exported = fmu_build::export::export_fmu(scene, &out, version, &from_fmu(version))
        .unwrap_or_else(|e| panic!("export of {}: {e}", scene.display()));
    assert_eq!(exported.model_identifier, name);
    assert_eq!(exported.platforms, [Platform::X86_64Linux]);
    out
}

/// The library's run of the scene file, read as `stickslip simulate` reads it, with
/// `advance_to` at the communication points 0, h, ... (the FMU's clock).
pub(super) fn library_run(scene: &Path, steps: usize) -> Vec<Outputs> {
    let scene = Scene::load(scene).expect("the scene loads");
    let law = stickslip::law_source::LawSource::resolve(&scene)
        .and_then(|law| law.law())
        .expect("an analytical law");
    let mut sim = Simulator::new(scene, law).expect("the scene builds");
    let mut out = vec![Outputs::of_simulator(&sim)];
    for &t in &communication_points(steps)[1..] {
        sim.advance_to(t).expect("advance_to");
        out.push(Outputs::of_simulator(&sim));
    }
    out
}

/// The exported FMU's run from its start values (no parameter set).
fn fmu_run(fmu: &Path, name: &str, steps: usize) -> Vec<Outputs> {
    install_logger();
    let started = std::time::Instant::now();
    let import: Fmi2Import = fmi::import::from_path(fmu)
        .unwrap_or_else(|e| panic!("cannot import {}: {e}", fmu.display()));
    let cs = import.model_description().co_simulation.as_ref();
    assert_eq!(
        cs.expect("a <CoSimulation> element").model_identifier,
        fmu.file_stem().unwrap().to_string_lossy()
    );
    let mut beam = Beam::start(&import, name, &[]);
    println!(
        "{name}: unpack, load, instantiate and initialise {:.3} s",
        started.elapsed().as_secs_f64()
    );
    beam.run_from_start(steps)
}

fn compare(scene: &Path, name: &str) -> Vec<Outputs> {
    let fmu = export(scene, name);
    let started = std::time::Instant::now();
    let from_fmu = fmu_run(&fmu, &format!("{name}-run"), EXPORT_STEPS);
    let fmu_time = started.elapsed();
    let library = library_run(scene, EXPORT_STEPS);
    assert_bitwise(
        &format!("exported {name} against the library"),
        &from_fmu,
        &library,
    );
    println!(
        "{name}: {} bytes; unpack, load and run of {EXPORT_STEPS} communication steps through the FMU {:.3} s",
        std::fs::metadata(&fmu).map(|m| m.len()).unwrap_or(0),
        fmu_time.as_secs_f64()
    );
    from_fmu
}

#[test]
fn the_exported_paper_scene_runs_as_the_library() {
    let scene = scratch().join("paper.toml");
    std::fs::write(&scene, "# the paper scene: every section at its default\n").unwrap();
    let out = compare(&scene, "PaperScene");
    // Not a run that stays put: the tip broke away before 0.5 s.
    assert!(out.iter().any(|o| !o.stick));
}

#[test]
fn the_exported_calculix_beam_runs_as_the_library() {
    let scene = fmu_build::workspace_root().join("examples/calculix-beam/scene.toml");
    let out = compare(&scene, "CalculixBeam");
    assert!(out.iter().any(|o| !o.stick));
}

/// fmi2Reset returns to the scene's values, not StickSlipBeam's: a scene whose belt
/// runs at 0.03 m/s (StickSlipBeam's default: 0.02) runs the same before and after a
/// reset, and as the library runs the scene.
#[test]
fn reset_returns_to_the_scene() {
    let scene = scratch().join("fast-belt.toml");
    std::fs::write(&scene, "[loading]\nbelt_speed = 0.03\n").unwrap();
    let fmu = export(&scene, "FastBelt");
    install_logger();
    let import: Fmi2Import = fmi::import::from_path(&fmu).unwrap();
    let mut beam = Beam::start(&import, "fast-belt", &[]);
    let first = beam.run_from_start(EXPORT_STEPS);
    assert_bitwise(
        "FastBelt against the library",
        &first,
        &library_run(&scene, EXPORT_STEPS),
    );
    Common::reset(&mut beam.inst).expect("fmi2Reset");
    Beam::initialize(&mut beam.inst, &[]);
    beam.t = 0.0;
    let again = beam.run_from_start(EXPORT_STEPS);
    assert_bitwise("FastBelt after fmi2Reset", &again, &first);
}

#[test]
fn a_tampered_scene_is_refused_at_instantiation() {
    let scene = scratch().join("tamper.toml");
    std::fs::write(&scene, "[loading]\nbelt_speed = 0.03\n").unwrap();
    let fmu = export(&scene, "Tampered");
    // The same archive with the belt speed in resources/scene.toml changed.
    let file = std::fs::File::open(&fmu).unwrap();
    let mut archive = zip::ZipArchive::new(file).unwrap();
    let mut entries = Vec::new();
    let mut changed = false;
    for k in 0..archive.len() {
        let mut entry = archive.by_index(k).unwrap();
        let name = entry.name().unwrap().into_owned();
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).unwrap();
        if name == "resources/scene.toml" {
            let text = String::from_utf8(bytes).unwrap();
            let edited = text.replace("belt_speed = 0.03", "belt_speed = 0.04");
            changed = edited != text;
            bytes = edited.into_bytes();
        }
        entries.push(Entry::deflated(name, bytes));
    }
    assert!(changed, "the exported scene names the belt speed");
    let tampered = scratch().join("TamperedEdit.fmu");
    write_zip(&tampered, entries).unwrap();

    install_logger();
    let import: Fmi2Import = fmi::import::from_path(&tampered).unwrap();
    let name = "tampered-instance";
    assert!(
        import.instantiate_cs(name, false, false).is_err(),
        "a tampered export must not instantiate"
    );
    let messages = messages_of(name);
    assert!(
        messages
            .iter()
            .any(|(level, text)| *level == log::Level::Error
                && text.contains("does not match the exported FMU Tampered")),
        "the refusal is logged with its reason: {messages:?}"
    );
}

/// The sensors of the sensor scenes: mid-span and the contact DOF in y, the contact
/// node in x.
pub(super) const SENSORS: [&str; 3] = ["mid_y", "contact_y", "tip_x"];

/// The CalculiX beam (examples/calculix-beam) at fidelity `level` with [`SENSORS`],
/// written to the scratch folder as `<name>.toml`.
pub(super) fn sensor_scene(name: &str, level: &str) -> PathBuf {
    let job = fmu_build::workspace_root().join("examples/calculix-beam/beam");
    let scene = scratch().join(format!("{name}.toml"));
    std::fs::write(
        &scene,
        format!(
            r#"[fidelity]
level = "{level}"
modes = 10
tolerance = 1e-4

[structure]
format = "calculix"
job = "{}"
contact = {{ node = 502, direction = 2 }}
sensors = [
  {{ name = "mid_y", node = 252, direction = 2 }},
  {{ name = "contact_y", node = 502, direction = 2 }},
  {{ name = "tip_x", node = 502, direction = 1 }},
]
"#,
            job.display()
        ),
    )
    .unwrap();
    scene
}

/// The library's sensor readings of the scene file at the communication points of
/// `library_run`: displacement and velocity of each sensor, in order.
pub(super) fn library_sensors(scene: &Path, steps: usize) -> Vec<Vec<f64>> {
    let scene = Scene::load(scene).expect("the scene loads");
    let law = stickslip::law_source::LawSource::resolve(&scene)
        .and_then(|law| law.law())
        .expect("an analytical law");
    let mut sim = Simulator::new(scene, law).expect("the scene builds");
    let read = |sim: &Simulator| -> Vec<f64> {
        sim.sensor_readings()
            .iter()
            .flat_map(|r| [r.displacement, r.velocity])
            .collect()
    };
    let mut out = vec![read(&sim)];
    for &t in &communication_points(steps)[1..] {
        sim.advance_to(t).expect("advance_to");
        out.push(read(&sim));
    }
    out
}

/// The sensors' variables in an export's modelDescription.xml: their value references
/// (displacement, velocity per sensor), after checking each is declared an output of
/// unit m or m/s above the table's value references, with ModelStructure entries.
pub(super) fn sensor_vrs(fmu: &Path, version: u8) -> Vec<u32> {
    let file = std::fs::File::open(fmu).unwrap();
    let mut archive = zip::ZipArchive::new(file).unwrap();
    let mut xml = String::new();
    archive
        .by_name("modelDescription.xml")
        .unwrap()
        .read_to_string(&mut xml)
        .unwrap();
    let first = stickslip_fmi::beam::exported::first_sensor_value_reference();
    let mut vrs = Vec::new();
    for (k, sensor) in SENSORS.iter().enumerate() {
        for (j, (name, unit)) in [
            (sensor.to_string(), "m"),
            (format!("{sensor}_velocity"), "m/s"),
        ]
        .into_iter()
        .enumerate()
        {
            let vr = first + 2 * k as u32 + j as u32;
            let (declared, structure) = if version == 2 {
                (
                    format!(r#"<ScalarVariable name="{name}" valueReference="{vr}" description="#),
                    String::new(),
                )
            } else {
                (
                    format!(r#"<Float64 name="{name}" valueReference="{vr}" description="#),
                    format!(r#"<Output valueReference="{vr}" dependencies=""/>"#),
                )
            };
            let at = xml
                .find(&declared)
                .unwrap_or_else(|| panic!("{name} declared as {declared}"));
            let line = &xml[at..xml[at..].find('\n').unwrap() + at];
            assert!(
                line.contains(
                    r#"causality="output" variability="continuous" initial="calculated""#
                ),
                "{line}"
            );
            if version == 2 {
                let next = &xml[at..];
                let element = &next[next.find('\n').unwrap() + 1..];
                assert!(
                    element
                        .trim_start()
                        .starts_with(&format!(r#"<Real unit="{unit}"/>"#)),
                    "{name}: {}",
                    &element[..80]
                );
            } else {
                assert!(
                    line.contains(&format!(r#"declaredType="{unit}""#)),
                    "{line}"
                );
                assert!(xml.contains(&structure), "{name}: {structure}");
            }
            vrs.push(vr);
        }
    }
    if version == 2 {
        // Outputs and InitialUnknowns list every output by index: the sensors' six
        // ScalarVariables are the last.
        let variables = xml.matches("<ScalarVariable ").count();
        for index in variables - 5..=variables {
            assert_eq!(
                xml.matches(&format!(r#"<Unknown index="{index}" "#))
                    .count(),
                2,
                "index {index} in Outputs and InitialUnknowns"
            );
        }
    }
    vrs
}

/// Sensors as outputs of an exported FMU (FMI 2.0), on the full model and its modal
/// reduction (10 modes + static correction): every sensor output equals the library's
/// reading bit for bit at all 501 communication points through breakaway, with the
/// table's outputs; the sensor at the contact equals the tip's outputs.
#[test]
fn the_exported_sensors_equal_the_librarys_run() {
    for (level, name) in [("plane-stress", "SensorsFull"), ("modal", "SensorsModal")] {
        let scene = sensor_scene(name, level);
        let fmu = export(&scene, name);
        let vrs = sensor_vrs(&fmu, 2);
        install_logger();
        let import: Fmi2Import = fmi::import::from_path(&fmu).unwrap();
        let mut beam = Beam::start(&import, name, &[]);
        let mut outputs = vec![beam.outputs()];
        let read = |beam: &mut Beam| {
            let mut values = vec![0.0; vrs.len()];
            beam.inst.get_real(&vrs, &mut values).expect("fmi2GetReal");
            values
        };
        let mut sensors = vec![read(&mut beam)];
        for _ in 0..EXPORT_STEPS {
            beam.step();
            outputs.push(beam.outputs());
            sensors.push(read(&mut beam));
        }
        assert_bitwise(
            &format!("{name} against the library"),
            &outputs,
            &library_run(&scene, EXPORT_STEPS),
        );
        let library = library_sensors(&scene, EXPORT_STEPS);
        let bits = |rows: &[Vec<f64>]| -> Vec<Vec<u64>> {
            rows.iter()
                .map(|r| r.iter().map(|v| v.to_bits()).collect())
                .collect()
        };
        assert_eq!(bits(&sensors), bits(&library), "{name}: sensors");
        for (o, s) in outputs.iter().zip(&sensors) {
            assert_eq!(o.tip_deflection.to_bits(), s[2].to_bits(), "{name}");
            assert_eq!(o.tip_velocity.to_bits(), s[3].to_bits(), "{name}");
        }
        assert!(outputs.iter().any(|o| !o.stick), "{name}: a slip");
        // Sensors are outputs: setting one is refused.
        assert!(beam.inst.set_real(&vrs[..1], &[1.0]).is_err());
    }
}

/// `fidelity.level = auto` in an exported FMU: the FMU chooses at initialisation over
/// its experiment (0 to 1.2 s, the stop time `Beam::start` sets), as the library's
/// `auto::choose_cached` does for the same scene and horizon, and runs that choice bit
/// for bit as the library runs it (tip outputs and sensors, to 0.5 s). Tolerance 1e-4 m
/// (docs/structures.md: 5 modes at 5e-4 s on this beam; the smallest calibration).
#[test]
fn an_exported_auto_scene_runs_the_librarys_choice() {
    use stickslip::auto::{choose_cached, paper_front, Horizon};
    let scene = sensor_scene("SensorsAuto", "auto");
    let fmu = export(&scene, "SensorsAuto");
    let vrs = sensor_vrs(&fmu, 2);
    install_logger();
    let import: Fmi2Import = fmi::import::from_path(&fmu).unwrap();
    let mut beam = Beam::start(&import, "SensorsAuto", &[]);
    let read = |beam: &mut Beam| {
        let mut values = vec![0.0; vrs.len()];
        beam.inst.get_real(&vrs, &mut values).expect("fmi2GetReal");
        values
    };
    let mut outputs = vec![beam.outputs()];
    let mut sensors = vec![read(&mut beam)];
    for _ in 0..EXPORT_STEPS {
        beam.step();
        outputs.push(beam.outputs());
        sensors.push(read(&mut beam));
    }

    let loaded = Scene::load(&scene).expect("the scene loads");
    let mut request = loaded.scene().clone();
    request.time.end = STOP;
    let law = stickslip::law_source::LawSource::resolve(&loaded).unwrap();
    let choice = choose_cached(
        &request,
        &law,
        Horizon::Until(STOP),
        &paper_front().unwrap(),
        &mut |_| {},
    )
    .expect("a choice at 1e-4 m");
    println!("auto chose {:?}", choice.configuration);
    let chosen = choice.configuration.apply(&request).check().unwrap();
    assert_ne!(chosen.fidelity.level, FidelityLevel::Auto);
    let mut sim = Simulator::new(chosen, law.law().unwrap()).unwrap();
    let read_library = |sim: &Simulator| -> Vec<f64> {
        sim.sensor_readings()
            .iter()
            .flat_map(|r| [r.displacement, r.velocity])
            .collect()
    };
    let mut library = vec![Outputs::of_simulator(&sim)];
    let mut library_sensors = vec![read_library(&sim)];
    for &t in &communication_points(EXPORT_STEPS)[1..] {
        sim.advance_to(t).expect("advance_to");
        library.push(Outputs::of_simulator(&sim));
        library_sensors.push(read_library(&sim));
    }
    assert_bitwise(
        "exported auto scene against the library's choice",
        &outputs,
        &library,
    );
    let bits = |rows: &[Vec<f64>]| -> Vec<Vec<u64>> {
        rows.iter()
            .map(|r| r.iter().map(|v| v.to_bits()).collect())
            .collect()
    };
    assert_eq!(bits(&sensors), bits(&library_sensors), "auto: sensors");
    assert!(outputs.iter().any(|o| !o.stick), "auto: a slip");
}

/// A sensor named as a variable of the FMU is refused at export, naming both.
#[test]
fn a_sensor_named_like_a_variable_is_refused() {
    let scene = sensor_scene("Clash", "plane-stress");
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace(r#"name = "mid_y""#, r#"name = "friction_force""#);
    std::fs::write(&scene, text).unwrap();
    let out = scratch().join("Clash.fmu");
    let error = fmu_build::export::export_fmu(&scene, &out, 2, &from_fmu(2))
        .expect_err("refused")
        .to_string();
    assert_eq!(
        error,
        "the scene's structure: structure.sensors: the sensor output friction_force has the name of the exported FMU's output friction_force (StickSlipBeam's variables are all declared beside the sensors); rename the sensor"
    );
    assert!(!out.exists());
}
