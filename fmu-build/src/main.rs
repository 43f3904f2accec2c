//! `cargo run --release -p fmu-build`: builds the stickslip library and writes
//! `target/fmu/2.0/StickSlipBeam.fmu` and `target/fmu/2.0/NeuralFriction.fmu` (FMI 2.0),
//! their FMI 3.0 versions `target/fmu/3.0/*.fmu` (the same library), then the SSP
//! systems around the FMI 2.0 FMUs (`target/fmu/2.0/StickSlipCoupled.ssp`,
//! `target/fmu/2.0/StickSlipMonolithic.ssp`) and fmucontainer's link list of each
//! (`target/fmu/2.0/<system>.csv`). Files an older fmu-build left at the top of
//! `target/fmu/` are removed.
//!
//! `--update-model-descriptions` rewrites the checked-in `modelDescription/*.xml` and
//! `modelDescription/3.0/*.xml` from
//! the Rust tables (after an interface change); without it, a drifted copy is an error.
//!
//! The FMUs carry the portable build of the library (cargo-zigbuild, glibc 2.17 symbol
//! versions; `bash scripts/zig-env.sh` installs the tools). Without cargo-zigbuild this
//! is an error, not a quiet fallback: an FMU that needs this machine's glibc looks fine
//! here and fails to load on the older systems it is meant for. `--host-toolchain` is
//! the explicit way out for a developer without zig: it packages the host build, says so
//! loudly and names the glibc it needs; the packaged-binary tests then fail on it.
//!
//! Every FMU also carries the Windows x86_64 and the aarch64 Linux (glibc 2.17) binary
//! (`fmu_build::platform`; Debian packages from `bash scripts/cross-deps.sh`).
//! `STICKSLIP_HOST_ONLY=1` skips those two builds for quick iteration (the FMUs then
//! carry the x86_64 Linux binary only, and the packaged-FMU tests expect only it);
//! `--host-toolchain` implies it.

use fmu_build::platform::{self, Platform};
use fmu_build::{glibc, BuildError};
use std::path::PathBuf;
use std::process::ExitCode;
use stickslip_fmi::FmuKind;

fn run() -> Result<(), BuildError> {
    let host_toolchain = options()?;
    let drifted = fmu_build::drifted_descriptions();
    if !drifted.is_empty() {
        return Err(BuildError::Drift(drifted));
    }
    // Look for zig and the foreign toolchains before the long host build, so a missing
    // tool is reported at once.
    let zigbuild = if host_toolchain {
        None
    } else {
        Some(fmu_build::find_zigbuild()?)
    };
    let foreign: Vec<Platform> = match &zigbuild {
        Some(_) => platform::packaged_platforms()
            .into_iter()
            .filter(|p| *p != Platform::X86_64Linux)
            .collect(),
        None => Vec::new(),
    };
    if !foreign.is_empty() {
        platform::check_tools()?;
    }
    let library = linux_library(zigbuild.as_ref())?;
    let mut binaries = vec![(Platform::X86_64Linux, library)];
    if let Some(zigbuild) = &zigbuild {
        for platform in foreign {
            let library = platform::build(platform, zigbuild)?;
            if platform == Platform::Aarch64Linux {
                check_portable(&library)?;
            }
            println!("{}: {}", platform.rust_target(), library.display());
            binaries.push((platform, library));
        }
    }
    if binaries.len() == 1 && zigbuild.is_some() {
        println!(
            "{}: the FMUs carry the x86_64 Linux binary only",
            platform::HOST_ONLY_VAR
        );
    }
    write_packages(&binaries)
}

/// The command line: `--update-model-descriptions` rewrites the checked-in
/// descriptions at once; returns whether `--host-toolchain` was given.
fn options() -> Result<bool, BuildError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut host_toolchain = false;
    for arg in &args {
        match arg.as_str() {
            "--update-model-descriptions" => fmu_build::update_descriptions()?,
            "--host-toolchain" => host_toolchain = true,
            _ => return Err(BuildError::Usage(args)),
        }
    }
    Ok(host_toolchain)
}

/// The x86_64 Linux library the FMUs carry: the host build (the reference the tests
/// compare the packaged library with) always, and with `zigbuild` the portable build,
/// which must load on glibc [`glibc::FLOOR`]; without it the host build, with a warning
/// that names the glibc it needs.
fn linux_library(zigbuild: Option<&fmu_build::Zigbuild>) -> Result<PathBuf, BuildError> {
    let host_library = fmu_build::build_library()?;
    let library = match zigbuild {
        Some(zigbuild) => {
            println!(
                "portable build: {} (zig: {})",
                zigbuild.cargo_zigbuild.display(),
                zigbuild
                    .zig
                    .as_ref()
                    .map_or("found by cargo-zigbuild".into(), |z| z
                        .display()
                        .to_string())
            );
            fmu_build::build_portable_library(zigbuild)?
        }
        None => host_library,
    };
    let requirements = fmu_build::requirements(&library)?;
    let problems = requirements.problems_on(glibc::FLOOR);
    let oldest = requirements
        .oldest_glibc()
        .map_or("any".into(), |v| v.to_string());
    if zigbuild.is_some() {
        if !problems.is_empty() {
            return Err(BuildError::NotPortable {
                path: library,
                problems,
            });
        }
        println!(
            "{} needs glibc {oldest} or later (libraries: {})",
            library.display(),
            requirements.needed.join(", ")
        );
    } else if problems.is_empty() {
        eprintln!(
            "fmu-build: WARNING: --host-toolchain: the FMUs carry {}, linked against this machine's glibc (they need glibc {oldest} or later); the portable build is cargo-zigbuild's.",
            library.display()
        );
    } else {
        eprintln!(
            "fmu-build: WARNING: --host-toolchain: the FMUs carry {}, linked against this machine's glibc; they need glibc {oldest} or later and do not load on glibc {} ({}). Do not distribute them; the packaged-binary tests fail on them.",
            library.display(),
            glibc::FLOOR,
            problems.join(", ")
        );
    }
    Ok(library)
}

/// Writes both FMUs in both versions with `binaries` (platform and library), then the
/// SSP systems and their link lists; first removes what an older fmu-build left at the
/// top of `target/fmu/`.
fn write_packages(binaries: &[(Platform, PathBuf)]) -> Result<(), BuildError> {
    for path in fmu_build::remove_old_layout(&fmu_build::fmu_root())? {
        println!(
            "removed {} (the FMI 2.0 files are in 2.0/ now)",
            path.display()
        );
    }
    for kind in FmuKind::ALL {
        let path = fmu_build::package(kind, binaries, &fmu_build::fmu_dir())?;
        println!("wrote {} (GUID {})", path.display(), kind.guid());
        let path = fmu_build::package3(kind, binaries, &fmu_build::fmu3_dir())?;
        println!("wrote {} (FMI 3.0)", path.display());
    }
    let dir = fmu_build::fmu_dir();
    for system in fmu_build::ssp::systems() {
        let system = system.check()?;
        println!(
            "wrote {}",
            fmu_build::ssp::write_ssp(&system, &dir, &dir)?.display()
        );
        println!(
            "wrote {}",
            fmu_build::ssp::write_container_csv(&system, &dir)?.display()
        );
    }
    Ok(())
}

/// The aarch64 binary, linked by zig as the x86_64 one, must load on glibc 2.17 too.
fn check_portable(library: &std::path::Path) -> Result<(), BuildError> {
    let problems = fmu_build::requirements(library)?.problems_on(glibc::FLOOR);
    if problems.is_empty() {
        Ok(())
    } else {
        Err(BuildError::NotPortable {
            path: library.to_path_buf(),
            problems,
        })
    }
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("fmu-build: {error}");
            ExitCode::FAILURE
        }
    }
}
