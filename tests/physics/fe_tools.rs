//! The external FE tools (CalculiX's `ccx`, `gmsh`) that some tests run to regenerate
//! committed files. Where a tool is missing such a test is skipped with a note; under
//! `STICKSLIP_REQUIRE_FE_TOOLS` (set by scripts/test.sh after scripts/system-deps.sh
//! installed them) a missing tool fails the test instead, so that CI cannot pass a
//! regeneration check by skipping it.

use std::process::Command;

/// Whether `tool` runs (with `probe` as its arguments). False only outside CI's test
/// job: there a missing tool panics with the package that provides it.
pub fn available(tool: &str, probe: &[&str], package: &str) -> bool {
    if Command::new(tool).args(probe).output().is_ok() {
        return true;
    }
    assert!(
        std::env::var_os("STICKSLIP_REQUIRE_FE_TOOLS").is_none(),
        "{tool} is not installed, and STICKSLIP_REQUIRE_FE_TOOLS says the FE tools must be \
         (bash scripts/system-deps.sh installs {package})"
    );
    println!(
        "note: skipped: {tool} is not installed (bash scripts/system-deps.sh installs {package})"
    );
    false
}
