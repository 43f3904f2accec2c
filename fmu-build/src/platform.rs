//! The platforms every FMU carries a binary for: x86_64 Linux (glibc 2.17, the portable
//! build in `lib.rs`), x86_64 Windows and aarch64 Linux (glibc 2.17), and how the two
//! foreign binaries are built here (docs/cross-platform.md).
//!
//! Rustup on these machines has only the x86_64 Linux standard library, so the foreign
//! builds compile std from source (`-Zbuild-std=std`) with Debian's rustc-web 1.96, whose
//! sysroot `/usr` holds std's sources (`rust-web-src`); `scripts/cross-deps.sh` installs
//! it with the linkers. They use their own target directory ([`cross_target_dir`]) so
//! that neither the host build nor the portable build is invalidated by them, and a
//! second run of fmu-build rebuilds nothing.

use crate::{BuildError, Zigbuild};
use std::ffi::OsString;
use std::path::PathBuf;
use std::process::Command;

/// A platform an FMU carries a binary for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Platform {
    X86_64Linux,
    X86_64Windows,
    Aarch64Linux,
}

/// The environment variable that packages the x86_64 Linux binary only (quick
/// iteration; the packaged-FMU tests then expect only it).
pub const HOST_ONLY_VAR: &str = "STICKSLIP_HOST_ONLY";

/// Debian's compiler with std's sources (rustc-web): `-Zbuild-std` needs both from one
/// release.
const SOURCE_RUSTC: &str = "/usr/bin/rustc";
/// Debian's cargo of the same release; rustup's (older) cargo would build std 1.96 with
/// a std lock file it may not read.
const SOURCE_CARGO: &str = "/usr/bin/cargo";

impl Platform {
    pub const ALL: [Platform; 3] = [
        Platform::X86_64Linux,
        Platform::X86_64Windows,
        Platform::Aarch64Linux,
    ];

    /// The folder under `binaries/` in an FMI 2.0 FMU. FMI 2.0 names only win32/64,
    /// linux32/64 and darwin32/64, all x86; FMI 2.0.5 (sec. 2.3) says other platforms use
    /// FMI 3.0's platform tuples, hence `aarch64-linux` (docs/decisions.md).
    pub fn fmi2_folder(self) -> &'static str {
        match self {
            Platform::X86_64Linux => "linux64",
            Platform::X86_64Windows => "win64",
            Platform::Aarch64Linux => "aarch64-linux",
        }
    }

    /// The folder under `binaries/` in an FMI 3.0 FMU: the platform tuple (FMI 3.0
    /// sec. 2.5.1.4.1).
    pub fn fmi3_folder(self) -> &'static str {
        match self {
            Platform::X86_64Linux => "x86_64-linux",
            Platform::X86_64Windows => "x86_64-windows",
            Platform::Aarch64Linux => "aarch64-linux",
        }
    }

    /// The shared library's extension on this platform.
    pub fn extension(self) -> &'static str {
        match self {
            Platform::X86_64Windows => "dll",
            Platform::X86_64Linux | Platform::Aarch64Linux => "so",
        }
    }

    /// The Rust target triple.
    pub fn rust_target(self) -> &'static str {
        match self {
            Platform::X86_64Linux => crate::PORTABLE_TARGET,
            Platform::X86_64Windows => "x86_64-pc-windows-gnu",
            Platform::Aarch64Linux => "aarch64-unknown-linux-gnu",
        }
    }

    /// The packaged binary's path inside an FMU of FMI `version` (2 or 3).
    pub fn binary_entry(self, version: u8, model_identifier: &str) -> String {
        let folder = if version == 2 {
            self.fmi2_folder()
        } else {
            self.fmi3_folder()
        };
        format!("binaries/{folder}/{model_identifier}.{}", self.extension())
    }

    /// Where the foreign build leaves the library (the x86_64 Linux one is
    /// [`crate::portable_library_path`]).
    pub fn cross_library_path(self) -> PathBuf {
        let file = match self {
            Platform::X86_64Windows => "stickslip_fmi.dll",
            Platform::X86_64Linux | Platform::Aarch64Linux => "libstickslip_fmi.so",
        };
        cross_target_dir()
            .join(self.rust_target())
            .join("release")
            .join(file)
    }
}

/// True when [`HOST_ONLY_VAR`] is set to anything but empty or `0`.
pub fn host_only() -> bool {
    std::env::var_os(HOST_ONLY_VAR).is_some_and(|v| !v.is_empty() && v != "0")
}

/// The platforms the FMUs carry: all, or x86_64 Linux alone when [`host_only`].
pub fn packaged_platforms() -> Vec<Platform> {
    if host_only() {
        vec![Platform::X86_64Linux]
    } else {
        Platform::ALL.to_vec()
    }
}

/// The target directory of the foreign builds: `target/cross/`.
pub fn cross_target_dir() -> PathBuf {
    crate::target_dir().join("cross")
}

/// Builds the cdylib for `platform` and returns its path: x86_64 Linux is the portable
/// build ([`crate::build_portable_library`]); the foreign ones compile std from source.
/// Windows links with mingw-w64's gcc, stripped of its symbol table (zig's links carry
/// none already); aarch64 Linux with zig for glibc 2.17, as the x86_64 Linux binary.
pub fn build(platform: Platform, zigbuild: &Zigbuild) -> Result<PathBuf, BuildError> {
    let mut command = match platform {
        Platform::X86_64Linux => return crate::build_portable_library(zigbuild),
        Platform::X86_64Windows => {
            let mut command = Command::new(SOURCE_CARGO);
            command
                .arg("build")
                .env(
                    "CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER",
                    "x86_64-w64-mingw32-gcc",
                )
                .env("CARGO_PROFILE_RELEASE_STRIP", "symbols")
                // GNU ld stamps a PE file with the link time by default; without it the
                // same sources give the same DLL.
                .env(
                    "CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUSTFLAGS",
                    "-C link-arg=-Wl,--no-insert-timestamp",
                );
            command
        }
        Platform::Aarch64Linux => {
            let mut command = Command::new(&zigbuild.cargo_zigbuild);
            command.arg("zigbuild").env("CARGO", SOURCE_CARGO);
            if let Some(zig) = &zigbuild.zig {
                command.env("CARGO_ZIGBUILD_ZIG_PATH", zig);
            }
            command
        }
    };
    let target = match platform {
        Platform::Aarch64Linux => format!(
            "{}.{}.{}",
            platform.rust_target(),
            crate::glibc::FLOOR.0,
            crate::glibc::FLOOR.1
        ),
        _ => platform.rust_target().to_string(),
    };
    command
        .args([
            "--release",
            "--lib",
            "-p",
            "stickslip-fmi",
            "-Zbuild-std=std",
        ])
        .arg("--target")
        .arg(target)
        .arg("--target-dir")
        .arg(cross_target_dir())
        .current_dir(crate::workspace_root())
        .env("RUSTC", SOURCE_RUSTC)
        // -Zbuild-std is unstable; the bootstrap switch allows it on a stable compiler.
        .env("RUSTC_BOOTSTRAP", "1")
        // /usr/bin first: rustup's proxies (cargo, rustc) must not win inside the build.
        .env("PATH", path_with_usr_bin_first())
        // `cargo run` sets the toolchain of rustup's proxies; Debian's tools have none.
        .env_remove("RUSTUP_TOOLCHAIN");
    let status = command.status().map_err(|source| BuildError::CrossNotRun {
        platform: platform.rust_target(),
        source,
    })?;
    if !status.success() {
        return Err(BuildError::CrossFailed {
            platform: platform.rust_target(),
            status,
        });
    }
    let library = platform.cross_library_path();
    if !library.is_file() {
        return Err(BuildError::NotBuilt(library));
    }
    Ok(library)
}

/// PATH with `/usr/bin` in front.
fn path_with_usr_bin_first() -> OsString {
    let rest = std::env::var_os("PATH").unwrap_or_default();
    let dirs = std::iter::once(PathBuf::from("/usr/bin")).chain(std::env::split_paths(&rest));
    std::env::join_paths(dirs).unwrap_or(rest)
}

/// Whether the Debian packages of the foreign builds are there: a clear error before a
/// long build fails on a missing compiler.
pub fn check_tools() -> Result<(), BuildError> {
    let missing: Vec<&str> = [
        SOURCE_RUSTC,
        SOURCE_CARGO,
        "/usr/lib/rustlib/src/rust/library/Cargo.lock",
        "/usr/bin/x86_64-w64-mingw32-gcc",
    ]
    .into_iter()
    .filter(|path| !std::path::Path::new(path).exists())
    .collect();
    if missing.is_empty() {
        Ok(())
    } else {
        Err(BuildError::CrossToolsMissing(
            missing.iter().map(|s| s.to_string()).collect(),
        ))
    }
}
