//! What both self-describing JSON weights files (the network's, `weights`, and the law
//! with memory's, `memory::file`) check the same way: format and version first, so that
//! a foreign or newer file gets a precise message rather than a complaint about some
//! field; finite numbers, named by their field.

use super::error::NeuralError;

/// Parses `text` as JSON whose `format` is `format` and `version` is `version`, refused
/// with the reason otherwise.
pub(crate) fn check_header(
    text: &str,
    source_name: &str,
    format: &'static str,
    version: u32,
) -> Result<(), NeuralError> {
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| json_error(source_name, e))?;
    let found = value.get("format").and_then(|f| f.as_str());
    if found != Some(format) {
        return Err(NeuralError::Format {
            source_name: source_name.to_string(),
            found: found.map_or_else(|| "(missing)".to_string(), str::to_string),
            expected: format,
        });
    }
    let found = value.get("version").and_then(|v| v.as_u64());
    if found != Some(u64::from(version)) {
        return Err(NeuralError::Version {
            source_name: source_name.to_string(),
            found: found.map_or(0, |v| u32::try_from(v).unwrap_or(u32::MAX)),
            supported: version,
        });
    }
    Ok(())
}

/// A serde_json error as the weights file's `NeuralError::Json`.
pub(crate) fn json_error(source_name: &str, e: serde_json::Error) -> NeuralError {
    NeuralError::Json {
        source_name: source_name.to_string(),
        message: e.to_string(),
    }
}

/// `Ok` for a finite `value`, else `NeuralError::NonFinite` naming `field`.
pub(crate) fn finite(source_name: &str, field: String, value: f64) -> Result<(), NeuralError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(NeuralError::NonFinite {
            source_name: source_name.to_string(),
            field,
        })
    }
}

/// Pretty JSON with a final newline; numbers in shortest round-trip form, so the same
/// value always gives the same bytes.
pub(crate) fn to_pretty_json<T: serde::Serialize>(value: &T) -> Result<String, NeuralError> {
    let mut text = serde_json::to_string_pretty(value).map_err(|e| json_error("(in memory)", e))?;
    text.push('\n');
    Ok(text)
}

/// The text of the weights file at `path` (`crate::files` refuses what is not one).
pub(crate) fn read_text(path: &std::path::Path) -> Result<String, NeuralError> {
    Ok(crate::files::WEIGHTS_FILE.read_text(path)?)
}

/// Writes `text` to `path`, whole or not at all.
pub(crate) fn write_text(path: &std::path::Path, text: &str) -> Result<(), NeuralError> {
    Ok(crate::files::write_atomically(path, text)?)
}
