//! The one zip writer of the FMUs and the SSP files. Archives are reproducible: the
//! entries in the order given, every one dated zip's earliest time (1980-01-01 00:00,
//! `DateTime::default()`), so that the same contents give the same bytes.

use crate::BuildError;
use std::io::Write as _;
use std::path::Path;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

/// One file of an archive.
pub struct Entry {
    /// Its path inside the archive.
    pub name: String,
    pub bytes: Vec<u8>,
    /// Deflated, or stored (for contents that are compressed already, such as an FMU
    /// inside an SSP).
    pub method: CompressionMethod,
    /// Unix permissions (0o644 for data, 0o755 for a shared library).
    pub mode: u32,
}

impl Entry {
    /// A deflated entry with permissions 0o644.
    pub fn deflated(name: impl Into<String>, bytes: Vec<u8>) -> Self {
        Self {
            name: name.into(),
            bytes,
            method: CompressionMethod::Deflated,
            mode: 0o644,
        }
    }
}

/// Writes `entries`, in order, as the zip archive `path` (replacing it whole, or leaving
/// the older archive untouched when anything fails: `stickslip::files`).
pub fn write_zip(path: &Path, entries: Vec<Entry>) -> Result<(), BuildError> {
    let mut zip = ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default().last_modified_time(DateTime::default());
    for entry in entries {
        let options = options
            .compression_method(entry.method)
            .unix_permissions(entry.mode);
        zip.start_file(entry.name.as_str(), options)
            .map_err(|source| BuildError::Zip {
                path: path.to_path_buf(),
                entry: Some(entry.name.clone()),
                source,
            })?;
        zip.write_all(&entry.bytes)
            .map_err(|source| BuildError::ZipWrite {
                path: path.to_path_buf(),
                entry: entry.name.clone(),
                source,
            })?;
    }
    let archive = zip.finish().map_err(|source| BuildError::Zip {
        path: path.to_path_buf(),
        entry: None,
        source,
    })?;
    stickslip::files::write_atomically(path, archive.into_inner())?;
    Ok(())
}
