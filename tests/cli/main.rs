//! The `stickslip` command line contract, and `import-network`.

mod contract;
mod export_fmu;
mod files;
mod import;
mod law_parameters;
mod study_laws;
mod train_memory;
mod train_split;

use std::process::Command;

/// Runs the binary: (success, stdout, stderr).
fn stickslip(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(args)
        .output()
        .expect("run stickslip");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
