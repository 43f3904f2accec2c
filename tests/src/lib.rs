//! Helpers shared by the test binaries (`physics`, `fmu`, `neural`, `cli`) and the
//! benchmarks.

use std::path::PathBuf;

pub mod fmi_log;

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(".."))
}

/// The shipped networks, `weights/` (the FMUs' `resources/` folder holds the same files).
pub fn weights_dir() -> PathBuf {
    workspace_root().join("weights")
}

/// The `stickslip` binary of the same cargo profile as the running test. `cargo test
/// --workspace` builds it alongside the tests.
pub fn stickslip_binary() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    // target/<profile>/deps/<test> -> target/<profile>/stickslip
    let profile_dir = exe
        .parent()
        .and_then(|deps| deps.parent())
        .map(PathBuf::from)
        .unwrap_or_default();
    let binary = profile_dir.join("stickslip");
    assert!(
        binary.exists(),
        "{} is missing: build it with `cargo build -p stickslip-cli` in the same profile (cargo test --workspace does)",
        binary.display()
    );
    binary
}
