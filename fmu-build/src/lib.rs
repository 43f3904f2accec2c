//! Packages the FMUs: `modelDescription.xml` (generated from the Rust variable tables),
//! the stickslip-fmi cdylib of each platform under each model's name
//! (`binaries/linux64/<modelIdentifier>.so`, `binaries/win64/<modelIdentifier>.dll`,
//! `binaries/aarch64-linux/<modelIdentifier>.so` in FMI 2.0; [`platform`]) and
//! `resources/` (the network weights). Then the SSP system files
//! around them and fmucontainer's link lists (`ssp`).
//!
//! The packaged cdylib is the portable one ([`build_portable_library`]): linked by zig
//! through cargo-zigbuild against glibc 2.17 symbol versions, so it loads on glibc 2.17
//! and later (RHEL/CentOS 7, Debian 8, Ubuntu 14.04 and newer), not only on the build
//! machine's glibc. Same rustc, same code generation: only the linker and the glibc
//! symbol versions it binds to differ from the host build ([`build_library`]), which
//! stays the reference the tests compare the packaged FMUs with.
//!
//! Archives are reproducible: entries in a fixed order with a fixed timestamp.

pub mod archive;
pub mod export;
pub mod glibc;
pub mod platform;
pub mod ssp;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus};
use stickslip_fmi::FmuKind;
use zip::result::ZipError;

use archive::{write_zip, Entry};
use platform::Platform;

/// Why the FMUs could not be built; `main` prints it as `fmu-build: {e}`.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    #[error(
        "unknown arguments {0:?}; usage: fmu-build [--update-model-descriptions] [--host-toolchain]"
    )]
    Usage(Vec<String>),
    /// Checked-in model descriptions that differ from the generated ones.
    #[error(
        "{} differ from what the Rust tables generate; run `cargo run --release -p fmu-build -- --update-model-descriptions` and review the diff",
        .0.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
    )]
    Drift(Vec<PathBuf>),
    /// A system file's names or values do not fit the FMUs' tables.
    #[error(transparent)]
    Ssp(#[from] ssp::SspError),
    /// `cargo build` of the library could not be started.
    #[error("cannot run cargo: {0}")]
    CargoNotRun(#[source] std::io::Error),
    #[error("cargo build of the stickslip-fmi library failed ({0})")]
    CargoFailed(ExitStatus),
    /// The build succeeded but left no library where it was expected.
    #[error("{} was not built", .0.display())]
    NotBuilt(PathBuf),
    /// Neither `.venv-zig/bin` nor PATH has cargo-zigbuild.
    #[error(
        "cargo-zigbuild was not found in {} nor on PATH; it links the portable (glibc 2.17) FMU binary. Install it and zig once with `bash scripts/zig-env.sh` (pinned PyPI wheels, about 15 s), or pass --host-toolchain to package a binary that needs this machine's glibc (not for distribution)",
        .0.display()
    )]
    ZigbuildMissing(PathBuf),
    /// cargo-zigbuild could not be started.
    #[error("cannot run {}: {source}", .path.display())]
    ZigbuildNotRun {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cargo zigbuild of the portable stickslip-fmi library failed ({0})")]
    ZigbuildFailed(ExitStatus),
    /// The foreign build's cargo could not be started.
    #[error("cannot run the {platform} build: {source}")]
    CrossNotRun {
        platform: &'static str,
        source: std::io::Error,
    },
    #[error("the {platform} build of the stickslip-fmi library failed ({status})")]
    CrossFailed {
        platform: &'static str,
        status: ExitStatus,
    },
    /// Debian packages of the foreign builds are not installed.
    #[error(
        "the win64 and aarch64 builds need {}; install them with `bash scripts/cross-deps.sh`, or set {}=1 to package the x86_64 Linux binary only",
        .0.join(", "), platform::HOST_ONLY_VAR
    )]
    CrossToolsMissing(Vec<String>),
    /// The library is not an ELF file this module can read.
    #[error("{}: {source}", .path.display())]
    Elf {
        path: PathBuf,
        source: glibc::ElfError,
    },
    /// The portable build needs more than glibc 2.17 provides.
    #[error(
        "{} would not load on glibc {}: it needs {}",
        .path.display(), glibc::FLOOR, .problems.join(", ")
    )]
    NotPortable {
        path: PathBuf,
        problems: Vec<String>,
    },
    /// An output file (an FMU, an SSP file, a model description) that could not be
    /// written; nothing was put in its place.
    #[error(transparent)]
    Output(#[from] stickslip::files::OutputFileError),
    /// Reading or writing a file or folder.
    #[error("{}: {source}", .path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// Reading a file the FMU carries in `resources/`.
    #[error("resource {}: {source}", .path.display())]
    Resource {
        path: PathBuf,
        source: std::io::Error,
    },
    /// Starting an entry of the archive `path`, or finishing it (`entry` None).
    #[error(
        "{}: {}{source}",
        .path.display(),
        .entry.as_ref().map_or(String::new(), |name| format!("{name}: "))
    )]
    Zip {
        path: PathBuf,
        entry: Option<String>,
        source: ZipError,
    },
    /// Writing the contents of an entry of the archive `path`.
    #[error("{}: {entry}: {source}", .path.display())]
    ZipWrite {
        path: PathBuf,
        entry: String,
        source: std::io::Error,
    },
}

/// An I/O error on `path`.
pub(crate) fn io(path: &Path) -> impl FnOnce(std::io::Error) -> BuildError + '_ {
    move |source| BuildError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The workspace root (where Cargo.toml with `[workspace]` lives).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."))
}

/// The cargo target directory (CARGO_TARGET_DIR or `<root>/target`).
pub fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|p| {
            if p.is_absolute() {
                p
            } else {
                workspace_root().join(p)
            }
        })
        .unwrap_or_else(|| workspace_root().join("target"))
}

/// The folder of everything fmu-build writes: `target/fmu/`, with one folder per FMI
/// version, as Reference-FMUs sorts its builds (`2.0/`, `3.0/`). Nothing is written
/// at its top level ([`remove_old_layout`]).
pub fn fmu_root() -> PathBuf {
    target_dir().join("fmu")
}

/// Where the FMI 2.0 FMUs are written: `target/fmu/2.0/`. The SSP systems and
/// fmucontainer's link lists are written next to them: an SSP 1.0 system embeds FMI 2.0
/// FMUs (these), and fmucontainer reads the FMUs a link list names from the list's own
/// folder.
pub fn fmu_dir() -> PathBuf {
    fmu_root().join("2.0")
}

/// Path of the packaged FMI 2.0 FMU of `kind`.
pub fn fmu_path(kind: FmuKind) -> PathBuf {
    fmu_dir().join(format!("{}.fmu", kind.model_identifier()))
}

/// Where the FMI 3.0 FMUs are written: `target/fmu/3.0/`.
pub fn fmu3_dir() -> PathBuf {
    fmu_root().join("3.0")
}

/// Removes what an older fmu-build wrote at the top of `root` (`target/fmu/*.fmu`,
/// `*.ssp`, `*.csv`, from before the FMUs moved to `2.0/`), so that a script or a
/// master pointed at an old path fails instead of running a stale FMU. Returns what it
/// removed.
pub fn remove_old_layout(root: &Path) -> Result<Vec<PathBuf>, BuildError> {
    let mut removed = Vec::new();
    let entries = match std::fs::read_dir(root) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(removed),
        Err(e) => return Err(io(root)(e)),
    };
    for entry in entries {
        let path = entry.map_err(io(root))?.path();
        let old = path.is_file()
            && matches!(
                path.extension().and_then(|e| e.to_str()),
                Some("fmu" | "ssp" | "csv")
            );
        if old {
            std::fs::remove_file(&path).map_err(io(&path))?;
            removed.push(path);
        }
    }
    removed.sort();
    Ok(removed)
}

/// Path of the packaged FMI 3.0 FMU of `kind`.
pub fn fmu3_path(kind: FmuKind) -> PathBuf {
    fmu3_dir().join(format!("{}.fmu", kind.model_identifier()))
}

/// The checked-in copy of a model description.
pub fn checked_in_description(kind: FmuKind) -> PathBuf {
    workspace_root()
        .join("modelDescription")
        .join(format!("{}.xml", kind.model_identifier()))
}

/// The checked-in copy of an FMI 3.0 model description (`modelDescription/3.0/`).
pub fn checked_in_description3(kind: FmuKind) -> PathBuf {
    workspace_root()
        .join("modelDescription")
        .join("3.0")
        .join(format!("{}.xml", kind.model_identifier()))
}

/// Every checked-in description with what the tables generate for it.
fn descriptions() -> Vec<(PathBuf, String)> {
    FmuKind::ALL
        .into_iter()
        .flat_map(|kind| {
            [
                (checked_in_description(kind), kind.model_description()),
                (checked_in_description3(kind), kind.model_description3()),
            ]
        })
        .collect()
}

/// Builds the release cdylib with cargo and the host's linker and glibc, and returns its
/// path ([`host_library_path`]). Not what the FMUs carry (unless `--host-toolchain`): the
/// reference the packaged portable library is compared with, bit for bit.
pub fn build_library() -> Result<PathBuf, BuildError> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .args(["build", "--release", "--lib", "-p", "stickslip-fmi"])
        .current_dir(workspace_root())
        .status()
        .map_err(BuildError::CargoNotRun)?;
    if !status.success() {
        return Err(BuildError::CargoFailed(status));
    }
    let library = host_library_path();
    if !library.is_file() {
        return Err(BuildError::NotBuilt(library));
    }
    Ok(library)
}

/// The host build of the cdylib ([`build_library`]).
pub fn host_library_path() -> PathBuf {
    target_dir().join("release").join("libstickslip_fmi.so")
}

/// The Rust target of the packaged binary: `binaries/linux64` is x86_64 Linux, and only
/// that standard library is installed with the toolchain on these machines.
pub const PORTABLE_TARGET: &str = "x86_64-unknown-linux-gnu";

/// The target directory of the portable build: a separate one, because cargo-zigbuild
/// also links the build scripts and proc macros with zig when the target is the host's
/// own triple; sharing `target/release` would make the host build and the portable
/// build invalidate each other's build-script artifacts.
pub fn portable_target_dir() -> PathBuf {
    target_dir().join("portable")
}

/// The portable build of the cdylib ([`build_portable_library`]).
pub fn portable_library_path() -> PathBuf {
    portable_target_dir()
        .join(PORTABLE_TARGET)
        .join("release")
        .join("libstickslip_fmi.so")
}

/// The zig toolchain of the portable build.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Zigbuild {
    /// The cargo-zigbuild executable.
    pub cargo_zigbuild: PathBuf,
    /// The zig executable to use; None: cargo-zigbuild finds one itself (`zig` on PATH,
    /// else `python3 -m ziglang`).
    pub zig: Option<PathBuf>,
}

/// The build venv `scripts/zig-env.sh` creates.
pub fn zig_venv_bin() -> PathBuf {
    workspace_root().join(".venv-zig").join("bin")
}

/// Finds cargo-zigbuild: first in the build venv (with the venv's pinned zig), then on
/// PATH.
pub fn find_zigbuild() -> Result<Zigbuild, BuildError> {
    let venv = zig_venv_bin();
    let in_venv = venv.join("cargo-zigbuild");
    if in_venv.is_file() {
        let zig = venv.join("zig");
        return Ok(Zigbuild {
            cargo_zigbuild: in_venv,
            zig: zig.is_file().then_some(zig),
        });
    }
    std::env::var_os("PATH")
        .iter()
        .flat_map(std::env::split_paths)
        .map(|dir| dir.join("cargo-zigbuild"))
        .find(|path| path.is_file())
        .map(|cargo_zigbuild| Zigbuild {
            cargo_zigbuild,
            zig: None,
        })
        .ok_or(BuildError::ZigbuildMissing(venv))
}

/// Builds the release cdylib with `cargo zigbuild --target
/// x86_64-unknown-linux-gnu.2.17` (zig as the linker, glibc 2.17 symbol versions) into
/// [`portable_target_dir`] and returns its path.
pub fn build_portable_library(zigbuild: &Zigbuild) -> Result<PathBuf, BuildError> {
    let mut command = Command::new(&zigbuild.cargo_zigbuild);
    command
        .arg("zigbuild")
        .args(["--release", "--lib", "-p", "stickslip-fmi", "--target"])
        .arg(format!(
            "{PORTABLE_TARGET}.{}.{}",
            glibc::FLOOR.0,
            glibc::FLOOR.1
        ))
        .arg("--target-dir")
        .arg(portable_target_dir())
        .current_dir(workspace_root());
    // The venv's pinned zig, unless the caller chose one.
    if let Some(zig) = &zigbuild.zig {
        if std::env::var_os("CARGO_ZIGBUILD_ZIG_PATH").is_none() {
            command.env("CARGO_ZIGBUILD_ZIG_PATH", zig);
        }
    }
    let status = command
        .status()
        .map_err(|source| BuildError::ZigbuildNotRun {
            path: zigbuild.cargo_zigbuild.clone(),
            source,
        })?;
    if !status.success() {
        return Err(BuildError::ZigbuildFailed(status));
    }
    let library = portable_library_path();
    if !library.is_file() {
        return Err(BuildError::NotBuilt(library));
    }
    Ok(library)
}

/// What the library at `path` needs from the system's C library.
pub fn requirements(path: &Path) -> Result<glibc::Requirements, BuildError> {
    let data = fs::read(path).map_err(io(path))?;
    glibc::Requirements::of_elf(&data).map_err(|source| BuildError::Elf {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes the generated descriptions into `modelDescription/`.
pub fn update_descriptions() -> Result<(), BuildError> {
    for (path, text) in descriptions() {
        if let Some(dir) = path.parent() {
            fs::create_dir_all(dir).map_err(io(dir))?;
        }
        stickslip::files::write_atomically(&path, text)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The checked-in descriptions that differ from the generated ones.
pub fn drifted_descriptions() -> Vec<PathBuf> {
    descriptions()
        .into_iter()
        .filter(|(path, text)| fs::read_to_string(path).ok().as_deref() != Some(text.as_str()))
        .map(|(path, _)| path)
        .collect()
}

/// One packaged binary: the platform and the built library.
pub type Binary = (Platform, PathBuf);

/// Writes the FMI 2.0 FMU of `kind` around `binaries` into `out_dir`; returns its path.
pub fn package(kind: FmuKind, binaries: &[Binary], out_dir: &Path) -> Result<PathBuf, BuildError> {
    package_with(kind, binaries, out_dir, kind.model_description(), 2)
}

/// Writes the FMI 3.0 FMU of `kind` around the same `binaries` (they export the fmi3*
/// functions too) into `out_dir`; returns its path. FMI 3.0 names the platform folder
/// `<arch>-<sys>` (standard, section 2.5.1.2).
pub fn package3(kind: FmuKind, binaries: &[Binary], out_dir: &Path) -> Result<PathBuf, BuildError> {
    package_with(kind, binaries, out_dir, kind.model_description3(), 3)
}

fn package_with(
    kind: FmuKind,
    binaries: &[Binary],
    out_dir: &Path,
    description: String,
    version: u8,
) -> Result<PathBuf, BuildError> {
    // The binaries are read before anything is written: a missing one leaves no folder.
    let mut entries = vec![Entry::deflated(
        "modelDescription.xml",
        description.into_bytes(),
    )];
    for (platform, library) in binaries {
        let binary = fs::read(library).map_err(io(library))?;
        entries.push(Entry {
            mode: 0o755,
            ..Entry::deflated(
                platform.binary_entry(version, kind.model_identifier()),
                binary,
            )
        });
    }
    for name in kind.info().resources {
        let source = workspace_root().join("weights").join(name);
        let contents = fs::read(&source).map_err(|source_error| BuildError::Resource {
            path: source.clone(),
            source: source_error,
        })?;
        entries.push(Entry::deflated(format!("resources/{name}"), contents));
    }
    fs::create_dir_all(out_dir).map_err(io(out_dir))?;
    let path = out_dir.join(format!("{}.fmu", kind.model_identifier()));
    write_zip(&path, entries)?;
    Ok(path)
}
