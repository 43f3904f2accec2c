//! Which reader a weights file needs, told from its name or its first bytes, so that a
//! file given where weights are read is never parsed by the wrong reader and a MATLAB
//! file gets the command that converts it rather than a JSON syntax error.

use std::path::Path;

/// The three kinds of network file a user may hand us.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WeightsFileKind {
    /// JSON text (the physics' own weights format, `stickslip::neural::weights`).
    Json,
    /// An ONNX `ModelProto` (`crate::onnx`).
    Onnx,
    /// A MATLAB MAT-file (a `fitrnet` network). Read by the Python package, not here:
    /// MATLAB stores the network as MCOS opaque data, an undocumented format.
    Matlab,
}

impl WeightsFileKind {
    /// By extension (`.onnx`, `.mat`, any case), when it says: a MAT-file is then refused
    /// without reading it.
    pub fn by_extension(path: &Path) -> Option<WeightsFileKind> {
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if extension.eq_ignore_ascii_case("onnx") {
            Some(WeightsFileKind::Onnx)
        } else if extension.eq_ignore_ascii_case("mat") {
            Some(WeightsFileKind::Matlab)
        } else {
            None
        }
    }

    /// By extension, else by the file's first bytes `head`:
    /// - ONNX: a first byte of 0x08, the protobuf key of `ModelProto.ir_version`
    ///   (field 1, varint) that exporters write first; JSON text never starts with that
    ///   control character;
    /// - MATLAB: the text header both MAT-file formats start with ("MATLAB 5.0 MAT-file"
    ///   for version 5 to 7, "MATLAB 7.3 MAT-file" in the HDF5 user block of 7.3).
    ///
    /// The caller reads the file (`stickslip::files`, which refuses devices and empty files
    /// first), so that telling the kind never opens what should not be read.
    pub fn of(path: &Path, head: &[u8]) -> WeightsFileKind {
        if let Some(kind) = Self::by_extension(path) {
            return kind;
        }
        if head.first() == Some(&0x08) {
            WeightsFileKind::Onnx
        } else if head.starts_with(b"MATLAB") {
            WeightsFileKind::Matlab
        } else {
            WeightsFileKind::Json
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kind_of(name: &str, bytes: &[u8]) -> WeightsFileKind {
        WeightsFileKind::of(Path::new(name), bytes)
    }

    #[test]
    fn extensions_decide_before_content() {
        assert_eq!(kind_of("a.ONNX", b"{}"), WeightsFileKind::Onnx);
        assert_eq!(kind_of("b.Mat", b"{}"), WeightsFileKind::Matlab);
    }

    #[test]
    fn content_decides_without_an_extension() {
        assert_eq!(kind_of("c", &[0x08, 0x08, 0x12]), WeightsFileKind::Onnx);
        assert_eq!(
            kind_of("d", b"MATLAB 5.0 MAT-file"),
            WeightsFileKind::Matlab
        );
        assert_eq!(kind_of("e.json", b"{\"format\": 1}"), WeightsFileKind::Json);
        assert_eq!(kind_of("f", b"MAT"), WeightsFileKind::Json);
        assert_eq!(kind_of("g", b""), WeightsFileKind::Json);
    }
}
