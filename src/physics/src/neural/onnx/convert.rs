//! A decoded ONNX graph to a chain of dense layers: input normalisation, layers with one
//! hidden activation, output scaling (`OnnxNetwork`).
//!
//! The graph must be one chain from its one input to its one output; each node on it
//! reads the running value plus constants (initializers or `Constant` nodes). The chain
//! is read as
//!
//! ```text
//! [normalisation] Dense (Activation Dense)* [output scaling]
//! ```
//!
//! where a Dense is `Gemm` or `MatMul` (+ `Add` of the bias), the normalisation is any
//! sequence of `Sub`/`Div`/`Mul`/`Add` by per-feature or scalar constants and
//! `ai.onnx.ml` `Scaler`, the output scaling any sequence of those by scalars, and
//! `Identity`, `Cast` (between FLOAT and DOUBLE), `Flatten` (axis 1) and `Reshape` (to
//! [-1, width] or [0, width]) may stand anywhere as no-ops. Everything else is refused.
//!
//! # Rounding
//! The common exports map exactly, so that an f64 network is imported bit for bit:
//! `Sub(mean)` then `Div(std)` gives `input_mean = mean`, `input_std = std`; `Mul(s)` then
//! `Add(m)` at the output gives `output_std = s`, `output_mean = m`; Gemm with alpha =
//! beta = 1 and MatMul give the weights as stored (transposed as needed). Other forms
//! are folded with a rounding per constant: `Scaler`'s scale (and `Mul` at the input)
//! becomes std = 1 / scale, Gemm's alpha and beta multiply B and C, an `Add` before a
//! `Mul` at the output is moved behind it. A negative scale at the input or output is
//! moved into the adjacent layer's weights by negation, which is exact.

use std::collections::{HashMap, HashSet};

use super::super::network::Activation;
use super::super::weights::LayerWeights;
use super::error::OnnxError;
use super::model::{
    attribute_type, data_type, AttributeProto, Dimension, ModelProto, NodeProto, TensorProto,
};

/// IR versions accepted: from 3 (opset imports, on which the operators' meaning depends)
/// to 11 (ONNX 1.18); the messages read here did not change in between.
pub const IR_VERSIONS: (i64, i64) = (3, 11);
/// Versions of the default (`ai.onnx`) opset accepted: from 7, where Add/Sub/Mul/Div
/// broadcast like numpy without the older `broadcast`/`axis` attributes and Gemm's C
/// broadcasts, to 23, the newest whose operator definitions this reader was checked
/// against (later versions of these operators only added data types so far, but a
/// future one may change their meaning).
pub const DEFAULT_OPSETS: (i64, i64) = (7, 23);
/// Versions of `ai.onnx.ml` accepted (for `Scaler`, defined in version 1 and unchanged).
pub const ML_OPSETS: (i64, i64) = (1, 5);

const SUPPORTED: &str = "Gemm, MatMul, Add, Sub, Mul, Div, Tanh, Relu, Sigmoid, Identity, Cast, \
Flatten, Reshape, Constant (ai.onnx) and Scaler (ai.onnx.ml)";

/// The precision the ONNX graph computes in: f32 when any weight, the input or a Cast
/// is FLOAT, else f64. The imported model evaluates in f64 either way; an f32 graph
/// agrees with it to f32 rounding (see the module documentation of `onnx`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    F32,
    F64,
}

/// The network an ONNX graph holds, in our terms: network input k is
/// (x_k - input_mean[k]) / input_std[k], the layers `weights[o][i]` as in the weights
/// file with `activation` on every hidden layer, and the output is
/// output_mean + output_std * z.
#[derive(Clone, Debug, PartialEq)]
pub struct OnnxNetwork {
    pub precision: Precision,
    /// Name of the graph input and output.
    pub input_name: String,
    pub output_name: String,
    pub input_mean: Vec<f64>,
    /// Positive.
    pub input_std: Vec<f64>,
    pub layers: Vec<LayerWeights>,
    /// The hidden layers' activation (Tanh when there is no hidden layer).
    pub activation: Activation,
    pub output_mean: f64,
    /// Positive.
    pub output_std: f64,
    /// "producer_name producer_version" of the file.
    pub producer: String,
    /// `metadata_props` of the file.
    pub metadata: Vec<(String, String)>,
}

impl OnnxNetwork {
    /// [inputs, hidden..., outputs].
    pub fn layer_sizes(&self) -> Vec<usize> {
        let mut sizes = vec![self.input_mean.len()];
        sizes.extend(self.layers.iter().map(|l| l.biases.len()));
        sizes
    }
}

fn domain_of(domain: &str) -> Option<bool> {
    // Some(false): the default opset; Some(true): ai.onnx.ml.
    match domain {
        "" | "ai.onnx" => Some(false),
        "ai.onnx.ml" => Some(true),
        _ => None,
    }
}

/// Converts a decoded model; `source_name` appears in errors.
pub fn convert(model: &ModelProto, source_name: &str) -> Result<OnnxNetwork, OnnxError> {
    let source = || source_name.to_string();
    let (min, max) = IR_VERSIONS;
    if !(min..=max).contains(&model.ir_version) {
        return Err(OnnxError::IrVersion {
            source_name: source(),
            found: model.ir_version,
            min,
            max,
        });
    }
    let opset = |ml: bool| {
        model
            .opset_import
            .iter()
            .filter(|o| domain_of(&o.domain) == Some(ml))
            .map(|o| o.version)
            .max()
    };
    let accepted = format!(
        "ai.onnx {} to {} (from 7 the elementwise operators broadcast like numpy; newer \
         versions are not checked), ai.onnx.ml {} to {} (Scaler)",
        DEFAULT_OPSETS.0, DEFAULT_OPSETS.1, ML_OPSETS.0, ML_OPSETS.1
    );
    let opset_error = |problem: String| OnnxError::Opset {
        source_name: source(),
        problem,
        accepted: accepted.clone(),
    };
    match opset(false) {
        None => return Err(opset_error("the model imports no ai.onnx opset".into())),
        Some(v) if !(DEFAULT_OPSETS.0..=DEFAULT_OPSETS.1).contains(&v) => {
            return Err(opset_error(format!("the model imports ai.onnx opset {v}")))
        }
        _ => {}
    }
    let graph = model.graph.as_ref().ok_or_else(|| OnnxError::Graph {
        source_name: source(),
        message: "the model has no graph".into(),
    })?;
    if graph
        .node
        .iter()
        .any(|n| domain_of(&n.domain) == Some(true))
    {
        match opset(true) {
            None => {
                return Err(opset_error(
                    "the graph uses ai.onnx.ml operators but imports no ai.onnx.ml opset".into(),
                ))
            }
            Some(v) if !(ML_OPSETS.0..=ML_OPSETS.1).contains(&v) => {
                return Err(opset_error(format!(
                    "the model imports ai.onnx.ml opset {v}"
                )))
            }
            _ => {}
        }
    }
    let producer = format!("{} {}", model.producer_name, model.producer_version)
        .trim()
        .to_string();
    Converter::new(graph, source_name)?.run(producer, model.metadata_props.clone())
}

/// How a node is named in messages: 'name' (op) or #index (op) when unnamed.
fn label(index: usize, node: &NodeProto) -> String {
    if node.name.is_empty() {
        format!("#{index} ({})", node.op_type)
    } else {
        format!("'{}' ({})", node.name, node.op_type)
    }
}

fn shape_text(dims: &[i64]) -> String {
    format!("{dims:?}")
}

/// A constant's values with its dims.
struct Constant {
    name: String,
    dims: Vec<i64>,
    values: Vec<f64>,
}

impl Constant {
    /// The dims without leading 1s (numpy broadcasting against [batch, width]).
    fn trailing(&self) -> &[i64] {
        let first = self
            .dims
            .iter()
            .position(|&d| d != 1)
            .unwrap_or(self.dims.len());
        &self.dims[first..]
    }
}

/// Where the chain is: before the first dense layer, right after a dense layer (and its
/// bias may still come), or after an activation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Input,
    Dense { bias_pending: bool },
    Activated,
}

/// An elementwise operation by a constant, x op c.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Elementwise {
    Sub,
    Div,
    Mul,
    Add,
}

struct Converter<'g> {
    source_name: String,
    nodes: &'g [NodeProto],
    input: String,
    output: String,
    /// Constant values by name: initializers and `Constant` node outputs.
    constants: HashMap<&'g str, &'g TensorProto>,
    saw_f32: bool,
    width: Option<usize>,
    stage: Stage,
    input_ops: Vec<(Elementwise, Vec<f64>, String)>,
    layers: Vec<LayerWeights>,
    activations: Vec<(Activation, String)>,
    output_ops: Vec<(Elementwise, f64)>,
}

impl<'g> Converter<'g> {
    fn new(
        graph: &'g super::model::GraphProto,
        source_name: &str,
    ) -> Result<Converter<'g>, OnnxError> {
        let graph_error = |message: String| OnnxError::Graph {
            source_name: source_name.to_string(),
            message,
        };
        let mut constants: HashMap<&str, &TensorProto> = graph
            .initializer
            .iter()
            .map(|t| (t.name.as_str(), t))
            .collect();
        let inputs: Vec<&super::model::ValueInfo> = graph
            .input
            .iter()
            .filter(|i| !constants.contains_key(i.name.as_str()))
            .collect();
        if inputs.len() != 1 {
            let names: Vec<&str> = inputs.iter().map(|i| i.name.as_str()).collect();
            return Err(graph_error(format!(
                "the graph has {} inputs besides initializers ({}); exactly one (the \
                 features, [batch, features]) is supported",
                inputs.len(),
                names.join(", ")
            )));
        }
        if graph.output.len() != 1 {
            let names: Vec<&str> = graph.output.iter().map(|o| o.name.as_str()).collect();
            return Err(graph_error(format!(
                "the graph has {} outputs ({}); exactly one (the force) is supported",
                names.len(),
                names.join(", ")
            )));
        }
        let mut converter = Converter {
            source_name: source_name.to_string(),
            nodes: &graph.node,
            input: inputs[0].name.clone(),
            output: graph.output[0].name.clone(),
            constants: HashMap::new(),
            saw_f32: false,
            width: None,
            stage: Stage::Input,
            input_ops: Vec::new(),
            layers: Vec::new(),
            activations: Vec::new(),
            output_ops: Vec::new(),
        };
        for (info, what) in [
            (inputs[0], "graph input"),
            (&graph.output[0], "graph output"),
        ] {
            if let Some(t) = info.elem_type {
                converter.check_float(t, &format!("{what} '{}'", info.name))?;
            }
        }
        if let Some(shape) = &inputs[0].shape {
            match shape.as_slice() {
                [_, Dimension::Value(w)] if *w > 0 => converter.width = Some(*w as usize),
                [_, _] => {}
                _ => {
                    return Err(converter.shape_error(
                        "(graph input)",
                        format!(
                            "graph input '{}' has rank {}; [batch, features] is expected",
                            inputs[0].name,
                            shape.len()
                        ),
                    ))
                }
            }
        }
        for (index, node) in graph.node.iter().enumerate() {
            if node.op_type == "Constant" && domain_of(&node.domain) == Some(false) {
                let value = match node.attribute.as_slice() {
                    [a] if a.name == "value" && a.t.is_some() => a.t.as_ref(),
                    _ => None,
                };
                let (Some(tensor), [output]) = (value, node.output.as_slice()) else {
                    return Err(OnnxError::Attribute {
                        source_name: source_name.to_string(),
                        node: label(index, node),
                        attribute: node
                            .attribute
                            .first()
                            .map_or_else(|| "value".to_string(), |a| a.name.clone()),
                        reason: "a Constant must have one output and its value as the \
                                 tensor attribute 'value'"
                            .into(),
                    });
                };
                constants.insert(output.as_str(), tensor);
            }
        }
        converter.constants = constants;
        converter.check_order(graph)?;
        Ok(converter)
    }

    fn check_order(&self, graph: &super::model::GraphProto) -> Result<(), OnnxError> {
        let mut writer: HashMap<&str, usize> = HashMap::new();
        for (index, node) in self.nodes.iter().enumerate() {
            for output in node.output.iter().filter(|o| !o.is_empty()) {
                let taken = writer.insert(output.as_str(), index).is_some()
                    || output == &self.input
                    || graph.initializer.iter().any(|t| &t.name == output);
                if taken {
                    return Err(OnnxError::Graph {
                        source_name: self.source_name.clone(),
                        message: format!(
                            "node {} writes '{output}', which is already defined",
                            label(index, node)
                        ),
                    });
                }
            }
        }
        let mut defined: HashSet<&str> = HashSet::from([self.input.as_str()]);
        defined.extend(graph.initializer.iter().map(|t| t.name.as_str()));
        for (index, node) in self.nodes.iter().enumerate() {
            for input in node.input.iter().filter(|i| !i.is_empty()) {
                if defined.contains(input.as_str()) {
                    continue;
                }
                return Err(match writer.get(input.as_str()) {
                    Some(&w) => OnnxError::Cycle {
                        source_name: self.source_name.clone(),
                        node: label(index, node),
                        value: input.clone(),
                        writer: label(w, &self.nodes[w]),
                    },
                    None => OnnxError::DanglingInput {
                        source_name: self.source_name.clone(),
                        node: label(index, node),
                        value: input.clone(),
                    },
                });
            }
            defined.extend(node.output.iter().map(String::as_str));
        }
        Ok(())
    }

    fn shape_error(&self, node: &str, message: String) -> OnnxError {
        OnnxError::Shape {
            source_name: self.source_name.clone(),
            node: node.to_string(),
            message,
        }
    }

    fn structure(&self, message: String) -> OnnxError {
        OnnxError::Structure {
            source_name: self.source_name.clone(),
            message,
        }
    }

    /// Notes an element type: FLOAT or DOUBLE, anything else refused by name.
    fn check_float(&mut self, elem_type: i32, what: &str) -> Result<(), OnnxError> {
        match elem_type {
            data_type::FLOAT => self.saw_f32 = true,
            data_type::DOUBLE => {}
            other => {
                return Err(OnnxError::DataType {
                    source_name: self.source_name.clone(),
                    what: what.to_string(),
                    data_type: data_type::name(other),
                    accepted: "only FLOAT and DOUBLE are supported",
                })
            }
        }
        Ok(())
    }

    /// The number of elements `dims` declares, if sane.
    fn element_count(&self, tensor: &TensorProto) -> Result<usize, OnnxError> {
        tensor
            .dims
            .iter()
            .try_fold(1usize, |n, &d| {
                usize::try_from(d).ok().and_then(|d| n.checked_mul(d))
            })
            .ok_or_else(|| OnnxError::Graph {
                source_name: self.source_name.clone(),
                message: format!(
                    "tensor '{}' has invalid dims {}",
                    tensor.name,
                    shape_text(&tensor.dims)
                ),
            })
    }

    fn stored_in_file(&self, tensor: &TensorProto) -> Result<(), OnnxError> {
        if tensor.data_location == 1 {
            return Err(OnnxError::Graph {
                source_name: self.source_name.clone(),
                message: format!(
                    "tensor '{}' is stored in an external file, which is not supported \
                     (save the model with its weights inside)",
                    tensor.name
                ),
            });
        }
        Ok(())
    }

    fn count_mismatch(&self, tensor: &TensorProto, count: usize, found: usize) -> OnnxError {
        OnnxError::Graph {
            source_name: self.source_name.clone(),
            message: format!(
                "tensor '{}' has dims {} ({count} elements) but holds {found} values",
                tensor.name,
                shape_text(&tensor.dims)
            ),
        }
    }

    /// A FLOAT or DOUBLE tensor's values in f64 (FLOAT widened exactly), every one
    /// finite.
    fn float_values(&mut self, tensor: &TensorProto) -> Result<Vec<f64>, OnnxError> {
        self.stored_in_file(tensor)?;
        self.check_float(tensor.data_type, &format!("tensor '{}'", tensor.name))?;
        let count = self.element_count(tensor)?;
        let single = tensor.data_type == data_type::FLOAT;
        let values: Vec<f64> = match &tensor.raw_data {
            Some(raw) if single => raw
                .chunks(4)
                .map(|c| {
                    c.try_into()
                        .map_or(f64::NAN, |b| f64::from(f32::from_le_bytes(b)))
                })
                .collect(),
            Some(raw) => raw
                .chunks(8)
                .map(|c| c.try_into().map_or(f64::NAN, f64::from_le_bytes))
                .collect(),
            None if single => tensor.float_data.iter().map(|&v| f64::from(v)).collect(),
            None => tensor.double_data.clone(),
        };
        let bytes_ok = tensor
            .raw_data
            .as_ref()
            .is_none_or(|raw| raw.len() == count * if single { 4 } else { 8 });
        if values.len() != count || !bytes_ok {
            return Err(self.count_mismatch(tensor, count, values.len()));
        }
        if let Some((index, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(OnnxError::NonFinite {
                source_name: self.source_name.clone(),
                tensor: tensor.name.clone(),
                index,
                value,
            });
        }
        Ok(values)
    }

    /// An INT64 tensor's values (shapes).
    fn int_values(&self, tensor: &TensorProto) -> Result<Vec<i64>, OnnxError> {
        self.stored_in_file(tensor)?;
        if tensor.data_type != data_type::INT64 {
            return Err(OnnxError::DataType {
                source_name: self.source_name.clone(),
                what: format!("shape tensor '{}'", tensor.name),
                data_type: data_type::name(tensor.data_type),
                accepted: "a shape must be INT64",
            });
        }
        let count = self.element_count(tensor)?;
        let values: Vec<i64> = match &tensor.raw_data {
            Some(raw) if raw.len() == count * 8 => raw
                .chunks_exact(8)
                .map(|c| c.try_into().map_or(0, i64::from_le_bytes))
                .collect(),
            Some(raw) => return Err(self.count_mismatch(tensor, count, raw.len() / 8)),
            None => tensor.int64_data.clone(),
        };
        if values.len() != count {
            return Err(self.count_mismatch(tensor, count, values.len()));
        }
        Ok(values)
    }

    fn constant(&mut self, name: &str, node: &str) -> Result<Constant, OnnxError> {
        let tensor = *self.constants.get(name).ok_or_else(|| OnnxError::Graph {
            source_name: self.source_name.clone(),
            message: format!(
                "node {node} reads '{name}' besides the running value; it must be a \
                 constant (initializer or Constant node)"
            ),
        })?;
        Ok(Constant {
            name: name.to_string(),
            dims: tensor.dims.clone(),
            values: self.float_values(tensor)?,
        })
    }

    /// Follows the chain from the input to the output and assembles the network.
    fn run(
        mut self,
        producer: String,
        metadata: Vec<(String, String)>,
    ) -> Result<OnnxNetwork, OnnxError> {
        let mut readers: HashMap<&str, Vec<usize>> = HashMap::new();
        for (index, node) in self.nodes.iter().enumerate() {
            let mut seen = HashSet::new();
            for input in node.input.iter().filter(|i| !i.is_empty()) {
                if seen.insert(input.as_str()) {
                    readers.entry(input.as_str()).or_default().push(index);
                }
            }
        }
        let mut on_chain = vec![false; self.nodes.len()];
        let mut current = self.input.clone();
        while current != self.output {
            let index = match readers.get(current.as_str()).map(Vec::as_slice) {
                Some([index]) => *index,
                None | Some([]) => {
                    return Err(OnnxError::Graph {
                        source_name: self.source_name.clone(),
                        message: format!(
                            "'{current}' is read by no node and is not the graph output \
                             '{}'",
                            self.output
                        ),
                    })
                }
                Some(many) => {
                    let names: Vec<String> =
                        many.iter().map(|&i| label(i, &self.nodes[i])).collect();
                    return Err(OnnxError::Graph {
                        source_name: self.source_name.clone(),
                        message: format!(
                            "'{current}' is read by {} nodes ({}); only a chain of layers \
                             is supported",
                            many.len(),
                            names.join(", ")
                        ),
                    });
                }
            };
            // The order check makes the chain advance through the node list, so a node
            // cannot come twice; this guards the loop regardless.
            if std::mem::replace(&mut on_chain[index], true) {
                return Err(self.structure(format!(
                    "node {} is reached twice",
                    label(index, &self.nodes[index])
                )));
            }
            let node = &self.nodes[index];
            let outputs: Vec<&String> = node.output.iter().filter(|o| !o.is_empty()).collect();
            let [output] = outputs.as_slice() else {
                return Err(self.structure(format!(
                    "node {} has {} outputs; a layer has one",
                    label(index, node),
                    outputs.len()
                )));
            };
            let running: Vec<usize> = (0..node.input.len())
                .filter(|&k| node.input[k] == current)
                .collect();
            let [position] = running.as_slice() else {
                return Err(self.structure(format!(
                    "node {} reads the running value '{current}' {} times",
                    label(index, node),
                    running.len()
                )));
            };
            self.apply(index, node, *position)?;
            current = output.to_string();
        }
        for (index, node) in self.nodes.iter().enumerate() {
            if !on_chain[index] && node.op_type != "Constant" {
                return Err(OnnxError::Graph {
                    source_name: self.source_name.clone(),
                    message: format!(
                        "node {} is not on the path from the input '{}' to the output '{}'",
                        label(index, node),
                        self.input,
                        self.output
                    ),
                });
            }
        }
        self.finish(producer, metadata)
    }

    /// Checks a node's attributes against the ones its operator may have here.
    fn attributes<'n>(
        &self,
        node: &'n NodeProto,
        label: &str,
        allowed: &[(&str, i32)],
    ) -> Result<HashMap<&'n str, &'n AttributeProto>, OnnxError> {
        let mut found = HashMap::new();
        for a in &node.attribute {
            let error = |reason: String| OnnxError::Attribute {
                source_name: self.source_name.clone(),
                node: label.to_string(),
                attribute: a.name.clone(),
                reason,
            };
            match allowed.iter().find(|(name, _)| *name == a.name) {
                None => return Err(error(format!("not supported on {} here", node.op_type))),
                Some((_, kind)) if *kind != a.kind => {
                    return Err(error(format!(
                        "has attribute type {}, expected {kind}",
                        a.kind
                    )))
                }
                Some(_) => {
                    found.insert(a.name.as_str(), a);
                }
            }
        }
        Ok(found)
    }

    fn attribute_error(&self, label: &str, attribute: &str, reason: String) -> OnnxError {
        OnnxError::Attribute {
            source_name: self.source_name.clone(),
            node: label.to_string(),
            attribute: attribute.to_string(),
            reason,
        }
    }

    /// One node of the chain, reading the running value at input `position`.
    fn apply(&mut self, index: usize, node: &NodeProto, position: usize) -> Result<(), OnnxError> {
        let name = label(index, node);
        let default = match domain_of(&node.domain) {
            Some(ml) => !ml,
            None => {
                return Err(self.unknown(&name, node));
            }
        };
        let other = |k: usize| node.input.get(k).filter(|i| !i.is_empty());
        match (default, node.op_type.as_str()) {
            (true, "Identity") => {
                self.attributes(node, &name, &[])?;
            }
            (true, "Cast") => {
                let a = self.attributes(
                    node,
                    &name,
                    &[
                        ("to", attribute_type::INT),
                        ("saturate", attribute_type::INT),
                    ],
                )?;
                let to = a.get("to").map(|a| a.i).ok_or_else(|| {
                    self.attribute_error(&name, "to", "a Cast needs its target type".into())
                })?;
                self.check_float(to as i32, &format!("node {name}: the cast's target"))?;
            }
            (true, "Flatten") => {
                let a = self.attributes(node, &name, &[("axis", attribute_type::INT)])?;
                let axis = a.get("axis").map_or(1, |a| a.i);
                if axis != 1 && axis != -1 {
                    return Err(self.attribute_error(
                        &name,
                        "axis",
                        format!("axis {axis} would change [batch, features]; only 1 is supported"),
                    ));
                }
            }
            (true, "Reshape") => {
                let a = self.attributes(node, &name, &[("allowzero", attribute_type::INT)])?;
                let allowzero = a.get("allowzero").map_or(0, |a| a.i);
                let shape_name = other(1).filter(|_| position == 0).ok_or_else(|| {
                    self.structure(format!("node {name} does not reshape the running value"))
                })?;
                let tensor = *self.constants.get(shape_name.as_str()).ok_or_else(|| {
                    self.structure(format!(
                        "node {name}: the shape '{shape_name}' is not a constant"
                    ))
                })?;
                let shape = self.int_values(tensor)?;
                let keeps = match (shape.as_slice(), self.width) {
                    ([-1, w], Some(width)) => *w == width as i64,
                    ([-1, w], None) if *w > 0 => {
                        self.width = Some(*w as usize);
                        true
                    }
                    ([0, -1], _) => allowzero == 0,
                    ([0, w], Some(width)) => allowzero == 0 && *w == width as i64,
                    _ => false,
                };
                if !keeps {
                    return Err(self.shape_error(
                        &name,
                        format!(
                            "reshape to {shape:?} of a [batch, {}] value; only [-1, width] or \
                             [0, width] (a no-op) is supported",
                            self.width.map_or("?".into(), |w| w.to_string())
                        ),
                    ));
                }
            }
            (true, "Sub" | "Div" | "Mul" | "Add") => {
                self.attributes(node, &name, &[])?;
                let op = match node.op_type.as_str() {
                    "Sub" => Elementwise::Sub,
                    "Div" => Elementwise::Div,
                    "Mul" => Elementwise::Mul,
                    _ => Elementwise::Add,
                };
                let commutative = matches!(op, Elementwise::Mul | Elementwise::Add);
                if position > 1 || (position == 1 && !commutative) {
                    return Err(self.structure(format!(
                        "node {name} computes constant {} running value; only running value {} \
                         constant is supported",
                        node.op_type, node.op_type
                    )));
                }
                let constant_name = other(1 - position)
                    .ok_or_else(|| self.structure(format!("node {name} has no second operand")))?;
                let constant = self.constant(constant_name, &name)?;
                self.elementwise(&name, op, constant)?;
            }
            (false, "Scaler") => {
                let a = self.attributes(
                    node,
                    &name,
                    &[
                        ("offset", attribute_type::FLOATS),
                        ("scale", attribute_type::FLOATS),
                    ],
                )?;
                if self.stage != Stage::Input {
                    return Err(self.structure(format!(
                        "node {name} scales a value inside the network; a Scaler is supported \
                         only on the input"
                    )));
                }
                self.saw_f32 = true;
                let floats = |key: &str| -> Result<Vec<f64>, OnnxError> {
                    let values: Vec<f64> = a.get(key).map_or_else(Vec::new, |a| {
                        a.floats.iter().map(|&v| f64::from(v)).collect()
                    });
                    if values.iter().any(|v| !v.is_finite()) {
                        return Err(self.attribute_error(
                            &name,
                            key,
                            "holds a NaN or infinity".into(),
                        ));
                    }
                    Ok(values)
                };
                // Scaler: y = (x - offset) * scale; both default to no-op values.
                let offset = floats("offset")?;
                let scale = floats("scale")?;
                for (op, values, key) in [
                    (Elementwise::Sub, offset, "offset"),
                    (Elementwise::Mul, scale, "scale"),
                ] {
                    if values.is_empty() {
                        continue;
                    }
                    let dims = vec![values.len() as i64];
                    self.elementwise(
                        &name,
                        op,
                        Constant {
                            name: format!("{key} attribute"),
                            dims,
                            values,
                        },
                    )?;
                }
            }
            (true, "MatMul") => {
                self.attributes(node, &name, &[])?;
                if position != 0 {
                    return Err(self.structure(format!(
                        "node {name} multiplies a constant by the running value; only value x \
                         weights is supported"
                    )));
                }
                let b_name =
                    other(1).ok_or_else(|| self.structure(format!("node {name} has no B")))?;
                let b = self.constant(b_name, &name)?;
                self.dense(&name, &b, false, 1.0)?;
                self.stage = Stage::Dense { bias_pending: true };
            }
            (true, "Gemm") => {
                let a = self.attributes(
                    node,
                    &name,
                    &[
                        ("alpha", attribute_type::FLOAT),
                        ("beta", attribute_type::FLOAT),
                        ("transA", attribute_type::INT),
                        ("transB", attribute_type::INT),
                    ],
                )?;
                let alpha = a.get("alpha").map_or(1.0, |a| f64::from(a.f));
                let beta = a.get("beta").map_or(1.0, |a| f64::from(a.f));
                for (key, value) in [("alpha", alpha), ("beta", beta)] {
                    if !value.is_finite() {
                        return Err(self.attribute_error(
                            &name,
                            key,
                            format!("{value} is not finite"),
                        ));
                    }
                }
                if let Some(t) = a.get("transA").filter(|a| a.i != 0) {
                    return Err(self.attribute_error(
                        &name,
                        "transA",
                        format!(
                            "transA = {}: the input must be [batch, features] (transA = 0)",
                            t.i
                        ),
                    ));
                }
                let trans_b = a.get("transB").map_or(0, |a| a.i);
                if trans_b != 0 && trans_b != 1 {
                    return Err(self.attribute_error(
                        &name,
                        "transB",
                        format!("transB = {trans_b}; 0 or 1 is expected"),
                    ));
                }
                if position != 0 {
                    return Err(self.structure(format!(
                        "node {name} reads the running value as B or C; only A is supported"
                    )));
                }
                let b_name =
                    other(1).ok_or_else(|| self.structure(format!("node {name} has no B")))?;
                let b = self.constant(b_name, &name)?;
                self.dense(&name, &b, trans_b == 1, alpha)?;
                if let Some(c_name) = other(2) {
                    let c = self.constant(c_name, &name)?;
                    self.bias(&name, &c, beta)?;
                }
                self.stage = Stage::Dense {
                    bias_pending: false,
                };
            }
            (true, "Tanh" | "Relu" | "Sigmoid") => {
                self.attributes(node, &name, &[])?;
                let activation = match node.op_type.as_str() {
                    "Tanh" => Activation::Tanh,
                    "Relu" => Activation::Relu,
                    _ => Activation::Sigmoid,
                };
                match self.stage {
                    Stage::Dense { .. } if self.output_ops.is_empty() => {}
                    Stage::Dense { .. } => {
                        return Err(self.structure(format!(
                            "activation {name} follows a scaling of a dense layer's output; \
                             only the network's output may be scaled"
                        )))
                    }
                    _ => {
                        return Err(self
                            .structure(format!("activation {name} does not follow a dense layer")))
                    }
                }
                self.activations.push((activation, name));
                self.stage = Stage::Activated;
            }
            _ => return Err(self.unknown(&name, node)),
        }
        Ok(())
    }

    fn unknown(&self, name: &str, node: &NodeProto) -> OnnxError {
        OnnxError::UnknownOperator {
            source_name: self.source_name.clone(),
            node: name.to_string(),
            op_type: node.op_type.clone(),
            domain: if node.domain.is_empty() {
                "ai.onnx".into()
            } else {
                node.domain.clone()
            },
            supported: SUPPORTED,
        }
    }

    /// x op c by a constant: normalisation before the first layer, a MatMul's bias, or
    /// output scaling after a layer.
    fn elementwise(&mut self, name: &str, op: Elementwise, c: Constant) -> Result<(), OnnxError> {
        match self.stage {
            Stage::Input => {
                let length = match c.trailing() {
                    [] => 1,
                    [n] => *n as usize,
                    _ => 0,
                };
                let fits = match self.width {
                    Some(w) => length == 1 || length == w,
                    None => length >= 1,
                };
                if !fits {
                    return Err(self.shape_error(
                        name,
                        format!(
                            "constant '{}' of shape {} does not broadcast over the input \
                             [batch, {}] feature by feature",
                            c.name,
                            shape_text(&c.dims),
                            self.width.map_or("?".into(), |w| w.to_string())
                        ),
                    ));
                }
                if length > 1 {
                    self.width = Some(length);
                }
                self.input_ops.push((op, c.values, name.to_string()));
            }
            Stage::Dense { bias_pending: true } if op == Elementwise::Add => {
                self.bias(name, &c, 1.0)?;
                self.stage = Stage::Dense {
                    bias_pending: false,
                };
            }
            Stage::Dense { .. } => {
                if c.values.len() != 1 {
                    return Err(self.shape_error(
                        name,
                        format!(
                            "constant '{}' of shape {} scales a dense layer's output per unit; \
                             only a scalar scaling of the network's output is supported",
                            c.name,
                            shape_text(&c.dims)
                        ),
                    ));
                }
                self.output_ops.push((op, c.values[0]));
                self.stage = Stage::Dense {
                    bias_pending: false,
                };
            }
            Stage::Activated => {
                return Err(self.structure(format!(
                    "node {name} changes an activation's output; a dense layer must follow \
                     each activation"
                )))
            }
        }
        Ok(())
    }

    /// A dense layer x B (B given as [k, n], or [n, k] when `transposed`), times alpha.
    fn dense(
        &mut self,
        name: &str,
        b: &Constant,
        transposed: bool,
        alpha: f64,
    ) -> Result<(), OnnxError> {
        if let Stage::Dense { .. } = self.stage {
            return Err(self.structure(format!(
                "dense layer {name} follows a dense layer with no activation between them"
            )));
        }
        let [rows, columns] = b.dims.as_slice() else {
            return Err(self.shape_error(
                name,
                format!(
                    "weights '{}' have shape {}, not a matrix",
                    b.name,
                    shape_text(&b.dims)
                ),
            ));
        };
        let (k, n) = if transposed {
            (*columns, *rows)
        } else {
            (*rows, *columns)
        };
        let (k, n) = (k as usize, n as usize);
        if k == 0 || n == 0 || self.width.is_some_and(|w| w != k) {
            return Err(self.shape_error(
                name,
                format!(
                    "the running value is [batch, {}] but weights '{}' have shape {}{}",
                    self.width.map_or("?".into(), |w| w.to_string()),
                    b.name,
                    shape_text(&b.dims),
                    if transposed { " (transposed)" } else { "" }
                ),
            ));
        }
        let weights: Vec<Vec<f64>> = (0..n)
            .map(|o| {
                (0..k)
                    .map(|i| {
                        let w = if transposed {
                            b.values[o * k + i]
                        } else {
                            b.values[i * n + o]
                        };
                        if alpha == 1.0 {
                            w
                        } else {
                            alpha * w
                        }
                    })
                    .collect()
            })
            .collect();
        if self.layers.is_empty() {
            self.width = Some(k);
        }
        self.layers.push(LayerWeights {
            weights,
            biases: vec![0.0; n],
        });
        self.width = Some(n);
        Ok(())
    }

    /// Adds beta * c to the last layer's biases.
    fn bias(&mut self, name: &str, c: &Constant, beta: f64) -> Result<(), OnnxError> {
        let n = self.width.unwrap_or(0);
        let broadcast = match c.trailing() {
            [] => true,
            [m] => *m as usize == n || *m == 1,
            _ => false,
        };
        if !broadcast {
            return Err(self.shape_error(
                name,
                format!(
                    "bias '{}' of shape {} does not fit the layer's {n} outputs",
                    c.name,
                    shape_text(&c.dims)
                ),
            ));
        }
        let Some(layer) = self.layers.last_mut() else {
            return Err(self.structure(format!("node {name} adds a bias before any layer")));
        };
        for (o, b) in layer.biases.iter_mut().enumerate() {
            let value = c.values[if c.values.len() == 1 { 0 } else { o }];
            *b += if beta == 1.0 { value } else { beta * value };
        }
        Ok(())
    }

    fn finish(
        mut self,
        producer: String,
        metadata: Vec<(String, String)>,
    ) -> Result<OnnxNetwork, OnnxError> {
        match self.stage {
            Stage::Input => {
                return Err(self.structure("the graph has no dense layer (Gemm or MatMul)".into()))
            }
            Stage::Activated => {
                let (_, name) = self.activations.last().cloned().unwrap_or_default();
                return Err(self.structure(format!(
                    "the output layer ends with activation {name}; NeuralModel's output layer \
                     is linear"
                )));
            }
            Stage::Dense { .. } => {}
        }
        let activation = match self.activations.split_first() {
            None => Activation::Tanh,
            Some(((first, first_name), rest)) => {
                if let Some((other, other_name)) = rest.iter().find(|(a, _)| a != first) {
                    return Err(self.structure(format!(
                        "hidden layers use {first:?} ({first_name}) and {other:?} ({other_name}); \
                         NeuralModel has one activation for all hidden layers"
                    )));
                }
                *first
            }
        };
        let outputs = self.width.unwrap_or(0);
        if outputs != 1 {
            return Err(self.structure(format!(
                "the network has {outputs} outputs; a friction law has one"
            )));
        }
        let inputs = self.layers[0].weights[0].len();
        // (x - mean) / std, composed op by op (see the module documentation).
        let mut mean = vec![0.0; inputs];
        let mut std = vec![1.0; inputs];
        for (op, values, name) in &self.input_ops {
            if values.len() != 1 && values.len() != inputs {
                return Err(self.shape_error(
                    name,
                    format!(
                        "{} per-feature values for the first layer's {inputs} inputs",
                        values.len()
                    ),
                ));
            }
            for k in 0..inputs {
                let c = values[if values.len() == 1 { 0 } else { k }];
                match op {
                    Elementwise::Sub => mean[k] += c * std[k],
                    Elementwise::Add => mean[k] -= c * std[k],
                    Elementwise::Div => std[k] *= c,
                    Elementwise::Mul => std[k] /= c,
                }
            }
        }
        for k in 0..inputs {
            if !(std[k].is_finite() && std[k] != 0.0 && mean[k].is_finite()) {
                return Err(self.structure(format!(
                    "the input normalisation of feature {k} gives mean {} and scale 1/{}; a \
                     finite, non-zero scale is needed",
                    mean[k], std[k]
                )));
            }
            if std[k] < 0.0 {
                std[k] = -std[k];
                for row in &mut self.layers[0].weights {
                    row[k] = -row[k];
                }
            }
        }
        // y = offset + scale z, composed op by op.
        let (mut offset, mut scale) = (0.0, 1.0);
        for (op, c) in &self.output_ops {
            match op {
                Elementwise::Sub => offset -= c,
                Elementwise::Add => offset += c,
                Elementwise::Mul => {
                    offset *= c;
                    scale *= c;
                }
                Elementwise::Div => {
                    offset /= c;
                    scale /= c;
                }
            }
        }
        if !(scale.is_finite() && scale != 0.0 && offset.is_finite()) {
            return Err(self.structure(format!(
                "the output scaling gives {offset} + {scale} z; a finite, non-zero scale is needed"
            )));
        }
        if scale < 0.0 {
            scale = -scale;
            let last = self.layers.last_mut().expect("a dense layer was seen");
            for row in &mut last.weights {
                row.iter_mut().for_each(|w| *w = -*w);
            }
            last.biases.iter_mut().for_each(|b| *b = -*b);
        }
        let check = |values: &[f64], what: String| -> Result<(), OnnxError> {
            match values.iter().position(|v| !v.is_finite()) {
                Some(index) => Err(OnnxError::NonFinite {
                    source_name: self.source_name.clone(),
                    tensor: what,
                    index,
                    value: values[index],
                }),
                None => Ok(()),
            }
        };
        // Folding alpha/beta can overflow finite constants.
        for (l, layer) in self.layers.iter().enumerate() {
            for row in &layer.weights {
                check(row, format!("layer {} weights (after alpha)", l + 1))?;
            }
            check(
                &layer.biases,
                format!("layer {} biases (after beta)", l + 1),
            )?;
        }
        Ok(OnnxNetwork {
            precision: if self.saw_f32 {
                Precision::F32
            } else {
                Precision::F64
            },
            input_name: self.input,
            output_name: self.output,
            input_mean: mean,
            input_std: std,
            layers: self.layers,
            activation,
            output_mean: offset,
            output_std: scale,
            producer,
            metadata,
        })
    }
}
