//! The protobuf wire format, read-only: what `model` needs to decode the ONNX messages.
//!
//! A message is a sequence of fields, each a varint key (field number << 3 | wire type)
//! and a value: 0 varint, 1 little-endian 64 bits, 2 varint length then that many
//! bytes (strings, bytes, nested messages, packed repeated scalars), 5 little-endian
//! 32 bits. Wire types 3 and 4 (proto2 groups) do not occur in onnx.proto3 and are
//! refused. Every length is checked against the bytes left before it is used, so a
//! truncated or corrupted file gives a `WireError` naming the byte offset, never a
//! panic; nothing is allocated from a declared length (vectors grow with the values
//! actually read, each of which costs at least one input byte).

use std::fmt;

/// Nested messages deeper than this are refused. The subset decoded by `model` is at
/// most 7 deep (model, graph, node, attribute, tensor; value info, type, tensor type,
/// shape, dimension); the limit guards against a schema change making it recursive.
pub const MAX_DEPTH: usize = 16;

/// Why bytes are not a valid protobuf message, at which absolute byte offset.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WireError {
    pub offset: usize,
    pub reason: String,
}

impl fmt::Display for WireError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "byte {}: {}", self.offset, self.reason)
    }
}

/// One field's value as it is on the wire.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value<'a> {
    Varint(u64),
    Fixed64(u64),
    Bytes(&'a [u8]),
    Fixed32(u32),
}

/// Reads the fields of one message from `bytes`, which start at absolute offset
/// `base` of the file (for error messages).
#[derive(Clone, Debug)]
pub struct Reader<'a> {
    bytes: &'a [u8],
    position: usize,
    base: usize,
    depth: usize,
}

impl<'a> Reader<'a> {
    /// The top-level message of a file.
    pub fn new(bytes: &'a [u8]) -> Reader<'a> {
        Reader {
            bytes,
            position: 0,
            base: 0,
            depth: 0,
        }
    }

    /// Absolute offset of the next byte to read.
    pub fn offset(&self) -> usize {
        self.base + self.position
    }

    fn error(&self, reason: impl Into<String>) -> WireError {
        WireError {
            offset: self.offset(),
            reason: reason.into(),
        }
    }

    /// A reader of the nested message `bytes`, which `next_field` just returned as the
    /// value of a field of this one (so it lies inside `self.bytes`).
    pub fn nested(&self, bytes: &'a [u8]) -> Result<Reader<'a>, WireError> {
        if self.depth + 1 > MAX_DEPTH {
            return Err(self.error(format!("messages nested more than {MAX_DEPTH} deep")));
        }
        // The field's bytes end at the current position.
        let start = self.offset().saturating_sub(bytes.len());
        Ok(Reader {
            bytes,
            position: 0,
            base: start,
            depth: self.depth + 1,
        })
    }

    fn byte(&mut self) -> Result<u8, WireError> {
        let b = *self
            .bytes
            .get(self.position)
            .ok_or_else(|| self.error("the message ends inside a value"))?;
        self.position += 1;
        Ok(b)
    }

    /// A base-128 varint of at most 10 bytes.
    fn varint(&mut self) -> Result<u64, WireError> {
        let mut value: u64 = 0;
        for shift in (0..70).step_by(7) {
            let b = self.byte()?;
            if shift == 63 && b > 1 {
                return Err(self.error("a varint overflows 64 bits"));
            }
            value |= u64::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                return Ok(value);
            }
        }
        Err(self.error("a varint is longer than 10 bytes"))
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], WireError> {
        let left = self.bytes.len() - self.position;
        if n > left {
            return Err(self.error(format!(
                "a value of {n} bytes runs past the end of its message ({left} bytes left)"
            )));
        }
        let slice = &self.bytes[self.position..self.position + n];
        self.position += n;
        Ok(slice)
    }

    /// The next field (number, value), or None at the end of the message.
    pub fn next_field(&mut self) -> Result<Option<(u32, Value<'a>)>, WireError> {
        if self.position == self.bytes.len() {
            return Ok(None);
        }
        let key = self.varint()?;
        let number = key >> 3;
        if number == 0 || number > (1 << 29) - 1 {
            return Err(self.error(format!("field number {number} is out of range")));
        }
        let value = match key & 7 {
            0 => Value::Varint(self.varint()?),
            1 => Value::Fixed64(u64::from_le_bytes(fixed(self.take(8)?))),
            2 => {
                let length = self.varint()?;
                let length = usize::try_from(length)
                    .map_err(|_| self.error(format!("length {length} is too large")))?;
                Value::Bytes(self.take(length)?)
            }
            5 => Value::Fixed32(u32::from_le_bytes(fixed(self.take(4)?))),
            other => {
                return Err(self.error(format!(
                    "wire type {other} of field {number} is not used by onnx.proto3"
                )))
            }
        };
        Ok(Some((number as u32, value)))
    }
}

fn fixed<const N: usize>(bytes: &[u8]) -> [u8; N] {
    let mut out = [0; N];
    out.copy_from_slice(bytes);
    out
}

/// Typed access to a field's value, refusing a wire type the schema does not allow.
impl<'a> Value<'a> {
    fn kind(&self) -> &'static str {
        match self {
            Value::Varint(_) => "a varint",
            Value::Fixed64(_) => "64 bits",
            Value::Bytes(_) => "length-delimited bytes",
            Value::Fixed32(_) => "32 bits",
        }
    }

    fn mismatch(&self, reader: &Reader<'_>, field: &str, expected: &str) -> WireError {
        reader.error(format!("{field} is {}, expected {expected}", self.kind()))
    }

    /// An int64/int32/enum field (two's complement in 64 bits).
    pub fn int(self, reader: &Reader<'_>, field: &str) -> Result<i64, WireError> {
        match self {
            Value::Varint(v) => Ok(v as i64),
            _ => Err(self.mismatch(reader, field, "a varint")),
        }
    }

    /// A string field (UTF-8 checked).
    pub fn string(self, reader: &Reader<'_>, field: &str) -> Result<String, WireError> {
        let bytes = self.bytes(reader, field)?;
        std::str::from_utf8(bytes)
            .map(str::to_string)
            .map_err(|_| reader.error(format!("{field} is not UTF-8 text")))
    }

    /// A bytes or nested-message field.
    pub fn bytes(self, reader: &Reader<'_>, field: &str) -> Result<&'a [u8], WireError> {
        match self {
            Value::Bytes(b) => Ok(b),
            _ => Err(self.mismatch(reader, field, "length-delimited bytes")),
        }
    }

    /// A float field.
    pub fn float(self, reader: &Reader<'_>, field: &str) -> Result<f32, WireError> {
        match self {
            Value::Fixed32(v) => Ok(f32::from_bits(v)),
            _ => Err(self.mismatch(reader, field, "32 bits")),
        }
    }

    /// Appends a repeated float field's values: one unpacked value or a packed run.
    pub fn floats(
        self,
        reader: &Reader<'_>,
        field: &str,
        out: &mut Vec<f32>,
    ) -> Result<(), WireError> {
        match self {
            Value::Fixed32(v) => out.push(f32::from_bits(v)),
            Value::Bytes(b) => {
                if b.len() % 4 != 0 {
                    return Err(reader.error(format!(
                        "packed {field} has {} bytes, not a multiple of 4",
                        b.len()
                    )));
                }
                out.extend(b.chunks_exact(4).map(|c| f32::from_le_bytes(fixed(c))));
            }
            _ => return Err(self.mismatch(reader, field, "32 bits or packed")),
        }
        Ok(())
    }

    /// Appends a repeated double field's values: one unpacked value or a packed run.
    pub fn doubles(
        self,
        reader: &Reader<'_>,
        field: &str,
        out: &mut Vec<f64>,
    ) -> Result<(), WireError> {
        match self {
            Value::Fixed64(v) => out.push(f64::from_bits(v)),
            Value::Bytes(b) => {
                if b.len() % 8 != 0 {
                    return Err(reader.error(format!(
                        "packed {field} has {} bytes, not a multiple of 8",
                        b.len()
                    )));
                }
                out.extend(b.chunks_exact(8).map(|c| f64::from_le_bytes(fixed(c))));
            }
            _ => return Err(self.mismatch(reader, field, "64 bits or packed")),
        }
        Ok(())
    }

    /// Appends a repeated int64 field's values: one unpacked varint or a packed run.
    pub fn ints(
        self,
        reader: &Reader<'_>,
        field: &str,
        out: &mut Vec<i64>,
    ) -> Result<(), WireError> {
        match self {
            Value::Varint(v) => out.push(v as i64),
            Value::Bytes(b) => {
                let mut packed = reader.nested(b)?;
                while packed.position < packed.bytes.len() {
                    out.push(packed.varint()? as i64);
                }
            }
            _ => return Err(self.mismatch(reader, field, "a varint or packed varints")),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn varints_decode_and_overflow_is_refused() {
        let mut r = Reader::new(&[0x08, 0x96, 0x01]);
        assert_eq!(r.next_field().unwrap(), Some((1, Value::Varint(150))));
        assert_eq!(r.next_field().unwrap(), None);
        // -1 as int64: ten bytes, the last 0x01.
        let mut minus_one = vec![0x10];
        minus_one.extend([0xff; 9]);
        minus_one.push(0x01);
        let mut r = Reader::new(&minus_one);
        let (n, v) = r.next_field().unwrap().unwrap();
        assert_eq!((n, v.int(&r, "x").unwrap()), (2, -1));
        let mut too_long = vec![0x10];
        too_long.extend([0xff; 9]);
        too_long.push(0x02);
        assert!(Reader::new(&too_long).next_field().is_err());
    }

    #[test]
    fn lengths_past_the_end_name_the_offset() {
        // Field 1, length-delimited, 5 bytes declared, 2 present.
        let bytes = [0x0a, 0x05, 0x01, 0x02];
        let error = Reader::new(&bytes).next_field().unwrap_err();
        assert_eq!(error.offset, 2);
        assert!(error.reason.contains("5 bytes"), "{error}");
        // A length that does not fit usize on any platform is refused too.
        let mut huge = vec![0x0a];
        huge.extend([0xff; 9]);
        huge.push(0x01);
        assert!(Reader::new(&huge).next_field().is_err());
    }

    #[test]
    fn groups_and_field_zero_are_refused() {
        assert!(Reader::new(&[0x0b]).next_field().is_err());
        assert!(Reader::new(&[0x00, 0x00]).next_field().is_err());
    }

    #[test]
    fn nesting_is_limited() {
        let bytes = [0u8; 4];
        let mut r = Reader::new(&bytes);
        for _ in 0..MAX_DEPTH {
            r = r.nested(&bytes).unwrap();
        }
        assert!(r.nested(&bytes).is_err());
    }
}
