//! What a shared library asks of the C library it is loaded with: the libraries it names
//! (`DT_NEEDED`) and the symbol versions it needs from them (the `.gnu.version_r`
//! section, `SHT_GNU_VERNEED`).
//!
//! The dynamic loader refuses a library that needs a version its glibc does not define
//! ("version `GLIBC_2.34' not found"), so the newest `GLIBC_x.y` the library needs is the
//! oldest glibc it loads on. Source: the System V ABI's symbol versioning, as the Linux
//! Standard Base Core Specification describes `.gnu.version_r` (Elfxx_Verneed and
//! Elfxx_Vernaux records chained by byte offsets, names in the linked string table).

use object::elf::{FileHeader64, DT_NEEDED, EM_X86_64};
use object::read::elf::{Dyn, FileHeader};
use object::Endianness;
use std::fmt;

/// The oldest glibc the packaged binary is linked for: `cargo zigbuild --target
/// x86_64-unknown-linux-gnu.2.17`. It is also the oldest glibc the Rust standard library
/// supports on this target (the linux-gnu baseline: kernel 3.2, glibc 2.17).
pub const FLOOR: GlibcVersion = GlibcVersion(2, 17, 0);

/// The shared libraries of glibc 2.17 that the binary may name: the C library, the math
/// library, the dynamic loader and the threads and dl libraries, which glibc before 2.34
/// keeps separate from libc. Notably not libgcc_s (zig links its own unwinder in).
pub const GLIBC_LIBRARIES: [&str; 6] = [
    "libc.so.6",
    "libm.so.6",
    "ld-linux-x86-64.so.2",
    "libpthread.so.0",
    "libdl.so.2",
    "librt.so.1",
];

/// A glibc release `major.minor[.patch]`, ordered as releases are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct GlibcVersion(pub u32, pub u32, pub u32);

impl GlibcVersion {
    /// `GLIBC_2.3.4` -> 2.3.4; None for other names (`GLIBC_PRIVATE`, `GCC_3.0`, ...).
    pub fn from_symbol_version(name: &str) -> Option<Self> {
        let numbers = name.strip_prefix("GLIBC_")?;
        let mut parts = numbers.split('.').map(|p| p.parse::<u32>().ok());
        let major = parts.next()??;
        let minor = parts.next()??;
        let patch = parts.next().unwrap_or(Some(0))?;
        if parts.next().is_some() {
            return None;
        }
        Some(Self(major, minor, patch))
    }
}

impl fmt::Display for GlibcVersion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self(major, minor, 0) => write!(f, "{major}.{minor}"),
            Self(major, minor, patch) => write!(f, "{major}.{minor}.{patch}"),
        }
    }
}

/// One entry of `.gnu.version_r`: `version` (e.g. `GLIBC_2.14`) needed from `file`
/// (e.g. `libc.so.6`).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct VersionNeed {
    pub file: String,
    pub version: String,
}

impl fmt::Display for VersionNeed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} from {}", self.version, self.file)
    }
}

/// What a 64-bit ELF shared library needs from the system.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Requirements {
    /// `e_machine` (62 = x86_64).
    pub machine: u16,
    /// The `DT_NEEDED` libraries, in the order of the dynamic section.
    pub needed: Vec<String>,
    /// Every entry of `.gnu.version_r`, sorted.
    pub versions: Vec<VersionNeed>,
}

/// Why a file could not be read as a 64-bit ELF shared library.
#[derive(Debug, thiserror::Error)]
#[error("not a readable 64-bit ELF file: {0}")]
pub struct ElfError(#[from] object::read::Error);

impl Requirements {
    /// Reads the dynamic section and `.gnu.version_r` of a 64-bit ELF file.
    pub fn of_elf(data: &[u8]) -> Result<Self, ElfError> {
        let header = FileHeader64::<Endianness>::parse(data)?;
        let endian = header.endian()?;
        let sections = header.sections(endian, data)?;

        let mut needed = Vec::new();
        if let Some((entries, link)) = sections.dynamic(endian, data)? {
            let strings = sections.strings(endian, data, link)?;
            for entry in entries {
                if entry.tag(endian) == DT_NEEDED {
                    needed.push(text(entry.string(endian, strings)?));
                }
            }
        }

        let mut versions = Vec::new();
        if let Some((mut records, link)) = sections.gnu_verneed(endian, data)? {
            let strings = sections.strings(endian, data, link)?;
            while let Some((record, mut auxiliaries)) = records.next()? {
                let file = text(record.file(endian, strings)?);
                while let Some(auxiliary) = auxiliaries.next()? {
                    versions.push(VersionNeed {
                        file: file.clone(),
                        version: text(auxiliary.name(endian, strings)?),
                    });
                }
            }
        }
        versions.sort();

        Ok(Self {
            machine: header.e_machine.get(endian).0,
            needed,
            versions,
        })
    }

    /// True for an x86_64 binary, the one architecture packaged (`binaries/linux64`).
    pub fn is_x86_64(&self) -> bool {
        self.machine == EM_X86_64.0
    }

    /// The `GLIBC_x.y` versions needed, newest last.
    pub fn glibc_versions(&self) -> Vec<GlibcVersion> {
        let mut versions: Vec<GlibcVersion> = self
            .versions
            .iter()
            .filter_map(|need| GlibcVersion::from_symbol_version(&need.version))
            .collect();
        versions.sort();
        versions.dedup();
        versions
    }

    /// The oldest glibc this library loads on, as far as symbol versions tell: the newest
    /// `GLIBC_x.y` it needs (None if it needs none).
    pub fn oldest_glibc(&self) -> Option<GlibcVersion> {
        self.glibc_versions().last().copied()
    }

    /// Why the library would not load on glibc `floor`: every needed `GLIBC_` version
    /// newer than `floor`, every `GLIBC_PRIVATE` (internal to one glibc build) and every
    /// library that glibc `floor` does not provide. Empty when it loads.
    pub fn problems_on(&self, floor: GlibcVersion) -> Vec<String> {
        let mut problems: Vec<String> = self
            .needed
            .iter()
            .filter(|library| !GLIBC_LIBRARIES.contains(&library.as_str()))
            .map(|library| format!("library {library} (not part of glibc)"))
            .collect();
        for need in &self.versions {
            match GlibcVersion::from_symbol_version(&need.version) {
                Some(version) if version > floor => problems.push(need.to_string()),
                Some(_) => {}
                None if need.version.starts_with("GLIBC_") => problems.push(need.to_string()),
                // Versions of the other libraries are judged by the library check above.
                None => {}
            }
        }
        problems
    }
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}
