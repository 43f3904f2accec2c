//! Helpers shared by the test binaries (`physics`, `fmu`, `neural`, `cli`) and the
//! benchmarks.

use std::path::PathBuf;
use stickslip_fmi::model::Model;

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

/// The value reference of `M`'s variable `name`, read from its variable table (which the
/// modelDescription.xml is generated from), so that tests name variables instead of
/// retyping their numbers.
pub fn vr<M: Model>(name: &str) -> u32 {
    M::variables()
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("{} has no variable {name}", M::INFO.model_identifier))
        .value_reference
}
