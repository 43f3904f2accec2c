//! The subset of onnx.proto3 the converter reads, decoded from the wire format.
//!
//! Field numbers are those of onnx.proto3 (ONNX IR version 3 and later, unchanged since).
//! Fields outside the subset are skipped, whatever they hold: sub-graphs of attributes,
//! training information, functions, sparse initializers (a graph that uses one then
//! fails in the converter as a dangling input). Values are kept as read; their meaning
//! (data types, shapes, finiteness) is checked by the converter, where the node that
//! uses them can be named.

use super::wire::{Reader, Value, WireError};

/// `TensorProto.DataType` values the converter names; the rest are named by number.
pub mod data_type {
    pub const FLOAT: i32 = 1;
    pub const INT64: i32 = 7;
    pub const DOUBLE: i32 = 11;

    /// The name of a `TensorProto.DataType` value, as in onnx.proto3.
    pub fn name(value: i32) -> String {
        let known = [
            "UNDEFINED",
            "FLOAT",
            "UINT8",
            "INT8",
            "UINT16",
            "INT16",
            "INT32",
            "INT64",
            "STRING",
            "BOOL",
            "FLOAT16",
            "DOUBLE",
            "UINT32",
            "UINT64",
            "COMPLEX64",
            "COMPLEX128",
            "BFLOAT16",
            "FLOAT8E4M3FN",
            "FLOAT8E4M3FNUZ",
            "FLOAT8E5M2",
            "FLOAT8E5M2FNUZ",
            "UINT4",
            "INT4",
            "FLOAT4E2M1",
        ];
        match usize::try_from(value).ok().and_then(|v| known.get(v)) {
            Some(name) => format!("{name} ({value})"),
            None => format!("data type {value}"),
        }
    }
}

/// `ModelProto`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelProto {
    pub ir_version: i64,
    pub producer_name: String,
    pub producer_version: String,
    pub opset_import: Vec<OperatorSetId>,
    pub graph: Option<GraphProto>,
    /// `metadata_props` as (key, value).
    pub metadata_props: Vec<(String, String)>,
}

/// `OperatorSetIdProto`; the empty domain is the default `ai.onnx`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OperatorSetId {
    pub domain: String,
    pub version: i64,
}

/// `GraphProto`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GraphProto {
    pub name: String,
    pub node: Vec<NodeProto>,
    pub initializer: Vec<TensorProto>,
    pub input: Vec<ValueInfo>,
    pub output: Vec<ValueInfo>,
}

/// How a node is named in messages: 'name' (op), or #index (op) when unnamed. Here, beside
/// the node, because the converter's chain, node and opset checks all name nodes.
pub(crate) fn node_label(index: usize, node: &NodeProto) -> String {
    if node.name.is_empty() {
        format!("#{index} ({})", node.op_type)
    } else {
        format!("'{}' ({})", node.name, node.op_type)
    }
}

/// `NodeProto`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeProto {
    pub input: Vec<String>,
    pub output: Vec<String>,
    pub name: String,
    pub op_type: String,
    pub domain: String,
    pub attribute: Vec<AttributeProto>,
}

/// `AttributeProto`, the fields for the attribute types the converter uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AttributeProto {
    pub name: String,
    /// `AttributeType`: FLOAT 1, INT 2, STRING 3, TENSOR 4, FLOATS 6, INTS 7, ...
    pub kind: i32,
    pub f: f32,
    pub i: i64,
    pub t: Option<TensorProto>,
    pub floats: Vec<f32>,
    pub ints: Vec<i64>,
}

/// `AttributeProto.AttributeType` values read by the converter.
pub mod attribute_type {
    pub const FLOAT: i32 = 1;
    pub const INT: i32 = 2;
    pub const STRING: i32 = 3;
    pub const TENSOR: i32 = 4;
    pub const FLOATS: i32 = 6;
    pub const INTS: i32 = 7;
}

/// `TensorProto` (dense, stored in the file).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TensorProto {
    pub name: String,
    pub dims: Vec<i64>,
    pub data_type: i32,
    pub float_data: Vec<f32>,
    pub double_data: Vec<f64>,
    pub int64_data: Vec<i64>,
    /// Some when the field is present (even empty).
    pub raw_data: Option<Vec<u8>>,
    /// Set when the tensor has `int32_data`, `string_data` or `uint64_data`, which no
    /// accepted data type uses.
    pub other_data: bool,
    /// `data_location`: 1 = EXTERNAL (the values are in another file).
    pub data_location: i32,
}

/// `ValueInfoProto` of a tensor: name, element type and shape where given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ValueInfo {
    pub name: String,
    /// `TypeProto.Tensor.elem_type`, when the value is a tensor with a type.
    pub elem_type: Option<i32>,
    /// `TypeProto.Tensor.shape`, when given.
    pub shape: Option<Vec<Dimension>>,
}

/// One dimension of a `TensorShapeProto`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Dimension {
    Value(i64),
    /// A symbolic size, such as the batch.
    Param(String),
    Unknown,
}

/// A decoding error with the message being decoded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DecodeError {
    /// E.g. "ModelProto.graph.node".
    pub context: String,
    pub error: WireError,
}

type Decoded<T> = Result<T, DecodeError>;

fn at(context: &str) -> impl Fn(WireError) -> DecodeError + '_ {
    move |error| DecodeError {
        context: context.to_string(),
        error,
    }
}

/// Runs `field` on each field of the message `reader` reads.
fn each_field<'a>(
    mut reader: Reader<'a>,
    context: &str,
    mut field: impl FnMut(&Reader<'a>, u32, Value<'a>) -> Decoded<()>,
) -> Decoded<()> {
    while let Some((number, value)) = reader.next_field().map_err(at(context))? {
        field(&reader, number, value)?;
    }
    Ok(())
}

/// Decodes the nested message `value` of field `name` of `parent` with `decode`.
fn message<'a, T>(
    parent: &Reader<'a>,
    value: Value<'a>,
    context: &str,
    decode: impl FnOnce(Reader<'a>, &str) -> Decoded<T>,
) -> Decoded<T> {
    let bytes = value.bytes(parent, context).map_err(at(context))?;
    let reader = parent.nested(bytes).map_err(at(context))?;
    decode(reader, context)
}

impl ModelProto {
    /// Decodes a whole `.onnx` file.
    pub fn decode(bytes: &[u8]) -> Decoded<ModelProto> {
        let mut model = ModelProto::default();
        let c = "ModelProto";
        each_field(Reader::new(bytes), c, |r, number, value| {
            let e = at(c);
            match number {
                1 => model.ir_version = value.int(r, "ir_version").map_err(e)?,
                2 => model.producer_name = value.string(r, "producer_name").map_err(e)?,
                3 => model.producer_version = value.string(r, "producer_version").map_err(e)?,
                7 => model.graph = Some(message(r, value, "ModelProto.graph", GraphProto::decode)?),
                8 => model.opset_import.push(message(
                    r,
                    value,
                    "ModelProto.opset_import",
                    OperatorSetId::decode,
                )?),
                14 => model.metadata_props.push(message(
                    r,
                    value,
                    "ModelProto.metadata_props",
                    decode_entry,
                )?),
                _ => {}
            }
            Ok(())
        })?;
        Ok(model)
    }
}

impl OperatorSetId {
    fn decode(reader: Reader<'_>, c: &str) -> Decoded<OperatorSetId> {
        let mut id = OperatorSetId::default();
        each_field(reader, c, |r, number, value| {
            match number {
                1 => id.domain = value.string(r, "domain").map_err(at(c))?,
                2 => id.version = value.int(r, "version").map_err(at(c))?,
                _ => {}
            }
            Ok(())
        })?;
        Ok(id)
    }
}

/// `StringStringEntryProto` as (key, value).
fn decode_entry(reader: Reader<'_>, c: &str) -> Decoded<(String, String)> {
    let mut entry = (String::new(), String::new());
    each_field(reader, c, |r, number, value| {
        match number {
            1 => entry.0 = value.string(r, "key").map_err(at(c))?,
            2 => entry.1 = value.string(r, "value").map_err(at(c))?,
            _ => {}
        }
        Ok(())
    })?;
    Ok(entry)
}

impl GraphProto {
    fn decode(reader: Reader<'_>, c: &str) -> Decoded<GraphProto> {
        let mut graph = GraphProto::default();
        each_field(reader, c, |r, number, value| {
            match number {
                1 => graph
                    .node
                    .push(message(r, value, "GraphProto.node", NodeProto::decode)?),
                2 => graph.name = value.string(r, "name").map_err(at(c))?,
                5 => graph.initializer.push(message(
                    r,
                    value,
                    "GraphProto.initializer",
                    TensorProto::decode,
                )?),
                11 => graph
                    .input
                    .push(message(r, value, "GraphProto.input", ValueInfo::decode)?),
                12 => graph
                    .output
                    .push(message(r, value, "GraphProto.output", ValueInfo::decode)?),
                _ => {}
            }
            Ok(())
        })?;
        Ok(graph)
    }
}

impl NodeProto {
    fn decode(reader: Reader<'_>, c: &str) -> Decoded<NodeProto> {
        let mut node = NodeProto::default();
        each_field(reader, c, |r, number, value| {
            let e = at(c);
            match number {
                1 => node.input.push(value.string(r, "input").map_err(e)?),
                2 => node.output.push(value.string(r, "output").map_err(e)?),
                3 => node.name = value.string(r, "name").map_err(e)?,
                4 => node.op_type = value.string(r, "op_type").map_err(e)?,
                5 => node.attribute.push(message(
                    r,
                    value,
                    "NodeProto.attribute",
                    AttributeProto::decode,
                )?),
                7 => node.domain = value.string(r, "domain").map_err(e)?,
                _ => {}
            }
            Ok(())
        })?;
        Ok(node)
    }
}

impl AttributeProto {
    fn decode(reader: Reader<'_>, c: &str) -> Decoded<AttributeProto> {
        let mut a = AttributeProto::default();
        each_field(reader, c, |r, number, value| {
            let e = at(c);
            match number {
                1 => a.name = value.string(r, "name").map_err(e)?,
                2 => a.f = value.float(r, "f").map_err(e)?,
                3 => a.i = value.int(r, "i").map_err(e)?,
                5 => a.t = Some(message(r, value, "AttributeProto.t", TensorProto::decode)?),
                7 => value.floats(r, "floats", &mut a.floats).map_err(e)?,
                8 => value.ints(r, "ints", &mut a.ints).map_err(e)?,
                20 => a.kind = value.int(r, "type").map_err(e)? as i32,
                _ => {}
            }
            Ok(())
        })?;
        Ok(a)
    }
}

impl TensorProto {
    fn decode(reader: Reader<'_>, c: &str) -> Decoded<TensorProto> {
        let mut t = TensorProto::default();
        each_field(reader, c, |r, number, value| {
            let e = at(c);
            match number {
                1 => value.ints(r, "dims", &mut t.dims).map_err(e)?,
                2 => t.data_type = value.int(r, "data_type").map_err(e)? as i32,
                4 => value
                    .floats(r, "float_data", &mut t.float_data)
                    .map_err(e)?,
                5 | 6 | 11 => t.other_data = true,
                7 => value.ints(r, "int64_data", &mut t.int64_data).map_err(e)?,
                8 => t.name = value.string(r, "name").map_err(e)?,
                9 => t.raw_data = Some(value.bytes(r, "raw_data").map_err(e)?.to_vec()),
                10 => value
                    .doubles(r, "double_data", &mut t.double_data)
                    .map_err(e)?,
                14 => t.data_location = value.int(r, "data_location").map_err(e)? as i32,
                _ => {}
            }
            Ok(())
        })?;
        Ok(t)
    }
}

impl ValueInfo {
    fn decode(reader: Reader<'_>, c: &str) -> Decoded<ValueInfo> {
        let mut info = ValueInfo::default();
        each_field(reader, c, |r, number, value| {
            match number {
                1 => info.name = value.string(r, "name").map_err(at(c))?,
                // TypeProto: tensor_type = 1.
                2 => message(r, value, "ValueInfoProto.type", |reader, c| {
                    each_field(reader, c, |r, number, value| {
                        if number == 1 {
                            message(r, value, "TypeProto.tensor_type", |reader, c| {
                                info.decode_tensor_type(reader, c)
                            })?;
                        }
                        Ok(())
                    })
                })?,
                _ => {}
            }
            Ok(())
        })?;
        Ok(info)
    }

    /// `TypeProto.Tensor`: elem_type = 1, shape = 2 (`TensorShapeProto`: dim = 1).
    fn decode_tensor_type(&mut self, reader: Reader<'_>, c: &str) -> Decoded<()> {
        each_field(reader, c, |r, number, value| {
            match number {
                1 => self.elem_type = Some(value.int(r, "elem_type").map_err(at(c))? as i32),
                2 => {
                    let mut dims = Vec::new();
                    message(r, value, "TypeProto.Tensor.shape", |reader, c| {
                        each_field(reader, c, |r, number, value| {
                            if number == 1 {
                                dims.push(message(
                                    r,
                                    value,
                                    "TensorShapeProto.dim",
                                    decode_dimension,
                                )?);
                            }
                            Ok(())
                        })
                    })?;
                    self.shape = Some(dims);
                }
                _ => {}
            }
            Ok(())
        })
    }
}

/// `TensorShapeProto.Dimension`: dim_value = 1, dim_param = 2.
fn decode_dimension(reader: Reader<'_>, c: &str) -> Decoded<Dimension> {
    let mut dim = Dimension::Unknown;
    each_field(reader, c, |r, number, value| {
        match number {
            1 => dim = Dimension::Value(value.int(r, "dim_value").map_err(at(c))?),
            2 => dim = Dimension::Param(value.string(r, "dim_param").map_err(at(c))?),
            _ => {}
        }
        Ok(())
    })?;
    Ok(dim)
}
