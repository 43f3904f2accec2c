//! Where fmu-build writes (`target/fmu/2.0/`, `target/fmu/3.0/`), and that nothing of the
//! old layout (FMI 2.0 files at the top of `target/fmu/`) survives a build, so that a
//! script pointed at an old path fails instead of running a stale FMU.

use fmu_build::{fmu3_dir, fmu_dir, fmu_path, fmu_root, remove_old_layout};
use std::fs;
use stickslip_fmi::FmuKind;

#[test]
fn each_fmi_version_has_its_folder() {
    assert_eq!(fmu_dir(), fmu_root().join("2.0"));
    assert_eq!(fmu3_dir(), fmu_root().join("3.0"));
    for kind in FmuKind::ALL {
        assert_eq!(fmu_path(kind).parent(), Some(fmu_dir().as_path()));
        assert!(fmu_path(kind).is_file(), "{}", fmu_path(kind).display());
    }
}

/// After `cargo run --release -p fmu-build`, the top of `target/fmu/` holds only folders.
#[test]
fn the_build_left_no_file_at_the_old_paths() {
    let stale: Vec<_> = fs::read_dir(fmu_root())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    assert!(stale.is_empty(), "left at the old paths: {stale:?}");
}

/// The files of the old layout go; the version folders and other files stay.
#[test]
fn remove_old_layout_takes_only_the_top_level_fmus_ssps_and_csvs() {
    let root = std::env::temp_dir().join(format!("fmu-build-layout-{}", std::process::id()));
    let _ = fs::remove_dir_all(&root);
    fs::create_dir_all(root.join("2.0")).unwrap();
    for name in [
        "StickSlipBeam.fmu",
        "StickSlipCoupled.ssp",
        "StickSlipCoupled.csv",
        "notes.txt",
        "2.0/StickSlipBeam.fmu",
    ] {
        fs::write(root.join(name), b"x").unwrap();
    }
    let removed = remove_old_layout(&root).unwrap();
    let names: Vec<String> = removed
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "StickSlipBeam.fmu",
            "StickSlipCoupled.csv",
            "StickSlipCoupled.ssp"
        ]
    );
    assert!(root.join("notes.txt").is_file());
    assert!(root.join("2.0/StickSlipBeam.fmu").is_file());
    assert!(remove_old_layout(&root.join("missing")).unwrap().is_empty());
    let _ = fs::remove_dir_all(&root);
}
