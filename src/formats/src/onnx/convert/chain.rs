//! The walk along the graph: the converter's state, the graph's input and output and
//! constants, the node order, and the one chain from input to output.

use std::collections::{HashMap, HashSet};

use super::super::error::OnnxError;
use super::super::model::{node_label, Dimension, GraphProto, NodeProto, TensorProto, ValueInfo};
use super::network::Activation;
use super::network::DenseLayer;
use super::network::OnnxNetwork;
use super::opset::domain_of;

/// Where the chain is: before the first dense layer, right after a dense layer (and its
/// bias may still come), or after an activation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Stage {
    Input,
    Dense { bias_pending: bool },
    Activated,
}

/// An elementwise operation by a constant, x op c.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Elementwise {
    Sub,
    Div,
    Mul,
    Add,
}

pub(super) struct Converter<'g> {
    pub(super) source_name: String,
    pub(super) nodes: &'g [NodeProto],
    pub(super) input: String,
    pub(super) output: String,
    /// Constant values by name: initializers and `Constant` node outputs.
    pub(super) constants: HashMap<&'g str, &'g TensorProto>,
    pub(super) saw_f32: bool,
    pub(super) width: Option<usize>,
    pub(super) stage: Stage,
    pub(super) input_ops: Vec<(Elementwise, Vec<f64>, String)>,
    pub(super) layers: Vec<DenseLayer>,
    pub(super) activations: Vec<(Activation, String)>,
    pub(super) output_ops: Vec<(Elementwise, f64)>,
}

impl<'g> Converter<'g> {
    /// The converter of `graph`, once its one input and output, their types and the
    /// input's width, its `Constant` nodes and its node order are checked.
    pub(super) fn new(
        graph: &'g GraphProto,
        source_name: &str,
    ) -> Result<Converter<'g>, OnnxError> {
        let mut constants: HashMap<&str, &TensorProto> = graph
            .initializer
            .iter()
            .map(|t| (t.name.as_str(), t))
            .collect();
        let input = one_input_and_output(graph, &constants, source_name)?;
        let mut converter = Converter {
            source_name: source_name.to_string(),
            nodes: &graph.node,
            input: input.name.clone(),
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
        converter.check_ends(input, &graph.output[0])?;
        constant_nodes(graph, source_name, &mut constants)?;
        converter.constants = constants;
        converter.check_order(graph)?;
        Ok(converter)
    }

    /// The graph input's and output's element types (FLOAT or DOUBLE when given), and
    /// the input's rank 2, whose width is taken when it is a number.
    fn check_ends(&mut self, input: &ValueInfo, output: &ValueInfo) -> Result<(), OnnxError> {
        for (info, what) in [(input, "graph input"), (output, "graph output")] {
            if let Some(t) = info.elem_type {
                self.check_float(t, &format!("{what} '{}'", info.name))?;
            }
        }
        if let Some(shape) = &input.shape {
            match shape.as_slice() {
                [_, Dimension::Value(w)] if *w > 0 => self.width = Some(*w as usize),
                [_, _] => {}
                _ => {
                    return Err(self.shape_error(
                        "(graph input)",
                        format!(
                            "graph input '{}' has rank {}; [batch, features] is expected",
                            input.name,
                            shape.len()
                        ),
                    ))
                }
            }
        }
        Ok(())
    }

    pub(super) fn check_order(&self, graph: &GraphProto) -> Result<(), OnnxError> {
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
                            node_label(index, node)
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
                        node: node_label(index, node),
                        value: input.clone(),
                        writer: node_label(w, &self.nodes[w]),
                    },
                    None => OnnxError::DanglingInput {
                        source_name: self.source_name.clone(),
                        node: node_label(index, node),
                        value: input.clone(),
                    },
                });
            }
            defined.extend(node.output.iter().map(String::as_str));
        }
        Ok(())
    }

    pub(super) fn shape_error(&self, node: &str, message: String) -> OnnxError {
        OnnxError::Shape {
            source_name: self.source_name.clone(),
            node: node.to_string(),
            message,
        }
    }

    pub(super) fn structure(&self, message: String) -> OnnxError {
        OnnxError::Structure {
            source_name: self.source_name.clone(),
            message,
        }
    }

    /// Follows the chain from the input to the output and assembles the network.
    pub(super) fn run(
        mut self,
        producer: String,
        metadata: Vec<(String, String)>,
    ) -> Result<OnnxNetwork, OnnxError> {
        let readers = self.readers();
        let mut on_chain = vec![false; self.nodes.len()];
        let mut current = self.input.clone();
        while current != self.output {
            let index = self.reader_of(&readers, &current)?;
            // The order check makes the chain advance through the node list, so a node
            // cannot come twice; this guards the loop regardless.
            if std::mem::replace(&mut on_chain[index], true) {
                return Err(self.structure(format!(
                    "node {} is reached twice",
                    node_label(index, &self.nodes[index])
                )));
            }
            current = self.step(index, &current)?;
        }
        self.check_all_on_chain(&on_chain)?;
        self.finish(producer, metadata)
    }

    /// The nodes that read each value, each node once per value.
    fn readers(&self) -> HashMap<&'g str, Vec<usize>> {
        let mut readers: HashMap<&str, Vec<usize>> = HashMap::new();
        for (index, node) in self.nodes.iter().enumerate() {
            let mut seen = HashSet::new();
            for input in node.input.iter().filter(|i| !i.is_empty()) {
                if seen.insert(input.as_str()) {
                    readers.entry(input.as_str()).or_default().push(index);
                }
            }
        }
        readers
    }

    /// The one node that reads `current`, the running value.
    fn reader_of(
        &self,
        readers: &HashMap<&str, Vec<usize>>,
        current: &str,
    ) -> Result<usize, OnnxError> {
        match readers.get(current).map(Vec::as_slice) {
            Some([index]) => Ok(*index),
            None | Some([]) => Err(OnnxError::Graph {
                source_name: self.source_name.clone(),
                message: format!(
                    "'{current}' is read by no node and is not the graph output \
                     '{}'",
                    self.output
                ),
            }),
            Some(many) => {
                let names: Vec<String> = many
                    .iter()
                    .map(|&i| node_label(i, &self.nodes[i]))
                    .collect();
                Err(OnnxError::Graph {
                    source_name: self.source_name.clone(),
                    message: format!(
                        "'{current}' is read by {} nodes ({}); only a chain of layers \
                         is supported",
                        many.len(),
                        names.join(", ")
                    ),
                })
            }
        }
    }

    /// Node `index` applied to the running value `current`, which it reads once; its
    /// one output is the next running value.
    fn step(&mut self, index: usize, current: &str) -> Result<String, OnnxError> {
        let node = &self.nodes[index];
        let outputs: Vec<&String> = node.output.iter().filter(|o| !o.is_empty()).collect();
        let [output] = outputs.as_slice() else {
            return Err(self.structure(format!(
                "node {} has {} outputs; a layer has one",
                node_label(index, node),
                outputs.len()
            )));
        };
        let running: Vec<usize> = (0..node.input.len())
            .filter(|&k| node.input[k] == current)
            .collect();
        let [position] = running.as_slice() else {
            return Err(self.structure(format!(
                "node {} reads the running value '{current}' {} times",
                node_label(index, node),
                running.len()
            )));
        };
        self.apply(index, node, *position)?;
        Ok(output.to_string())
    }

    /// Every node but the `Constant`s lies on the chain.
    fn check_all_on_chain(&self, on_chain: &[bool]) -> Result<(), OnnxError> {
        for (index, node) in self.nodes.iter().enumerate() {
            if !on_chain[index] && node.op_type != "Constant" {
                return Err(OnnxError::Graph {
                    source_name: self.source_name.clone(),
                    message: format!(
                        "node {} is not on the path from the input '{}' to the output '{}'",
                        node_label(index, node),
                        self.input,
                        self.output
                    ),
                });
            }
        }
        Ok(())
    }
}

/// The graph's one input besides the initializers (`constants`), once the graph is
/// known to have exactly one of those and one output.
fn one_input_and_output<'g>(
    graph: &'g GraphProto,
    constants: &HashMap<&str, &TensorProto>,
    source_name: &str,
) -> Result<&'g ValueInfo, OnnxError> {
    let graph_error = |message: String| OnnxError::Graph {
        source_name: source_name.to_string(),
        message,
    };
    let inputs: Vec<&ValueInfo> = graph
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
    Ok(inputs[0])
}

/// The outputs of the graph's `Constant` nodes added to `constants`, each node checked
/// to hold its value as the tensor attribute `value`.
fn constant_nodes<'g>(
    graph: &'g GraphProto,
    source_name: &str,
    constants: &mut HashMap<&'g str, &'g TensorProto>,
) -> Result<(), OnnxError> {
    for (index, node) in graph.node.iter().enumerate() {
        if node.op_type == "Constant" && domain_of(&node.domain) == Some(false) {
            let value = match node.attribute.as_slice() {
                [a] if a.name == "value" && a.t.is_some() => a.t.as_ref(),
                _ => None,
            };
            let (Some(tensor), [output]) = (value, node.output.as_slice()) else {
                return Err(OnnxError::Attribute {
                    source_name: source_name.to_string(),
                    node: node_label(index, node),
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
    Ok(())
}
