//! `stickslip export-fmu`'s refusals (docs/structures.md, "Exporting an FMU"): each bad
//! input gets its message, and nothing is left in the output folder (no FMU, no staging
//! folder). The exports that succeed are run in fmu-build/tests/packaged/import/export.rs,
//! which packages a StickSlipBeam.fmu of this tree to export from.

use super::stickslip;
use std::path::{Path, PathBuf};

fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stickslip-cli-export-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn bad_inputs_are_refused_with_their_reason_and_nothing_written() {
    let dir = scratch();
    let out_dir = dir.join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    let good = dir.join("good.toml");
    std::fs::write(&good, "[loading]\nbelt_speed = 0.03\n").unwrap();
    let unknown = dir.join("unknown.toml");
    std::fs::write(&unknown, "[loading]\nbelt_sped = 0.03\n").unwrap();
    let missing = dir.join("missing.toml");
    std::fs::write(
        &missing,
        "[structure]\nformat = \"calculix\"\njob = \"nothere\"\ncontact = { node = 502, direction = 2 }\n",
    )
    .unwrap();
    let not_fmu = dir.join("NotAnFmu.fmu");
    std::fs::write(&not_fmu, "not a zip archive").unwrap();
    let absent = dir.join("Absent.fmu");

    let path = |p: &Path| p.to_string_lossy().into_owned();
    let out = |name: &str| path(&out_dir.join(name));
    let cases: [(&str, Vec<String>, &str); 6] = [
        (
            "--out not a C identifier",
            vec![path(&good), out("my-beam.fmu"), path(&absent)],
            "the name \"my-beam\" becomes the modelIdentifier, which must be a C identifier",
        ),
        (
            "--out not .fmu",
            vec![path(&good), out("Beam.zip"), path(&absent)],
            "the file name must end in .fmu",
        ),
        (
            "unknown scene field",
            vec![path(&unknown), out("Beam.fmu"), path(&absent)],
            "unknown field `belt_sped`",
        ),
        (
            "missing structure file",
            vec![path(&missing), out("Beam.fmu"), path(&absent)],
            "nothere.dof",
        ),
        (
            "--from not a zip",
            vec![path(&good), out("Beam.fmu"), path(&not_fmu)],
            "not an FMU (zip archive)",
        ),
        (
            "--from absent",
            vec![path(&good), out("Beam.fmu"), path(&absent)],
            "Absent.fmu",
        ),
    ];
    for (what, args, expected) in cases {
        let (ok, _, stderr) = stickslip(&[
            "export-fmu",
            "--scene",
            &args[0],
            "--out",
            &args[1],
            "--from",
            &args[2],
        ]);
        assert!(!ok, "{what}: refused");
        assert!(
            stderr.contains(expected),
            "{what}: the message names the reason ({expected}): {stderr}"
        );
        assert!(listing(&out_dir).is_empty(), "{what}: nothing written");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
