//! Helpers shared by the test binaries (`physics`, `fmu`, `neural`, `cli`) and the
//! benchmarks.

use std::path::PathBuf;

pub mod bench;
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
