//! `OnnxError`: why an ONNX file could not be read into a dense chain, naming the
//! culprit.

/// Why an ONNX model could not be read. Every message names what is wrong (node by
/// name and operator type, attribute, tensor, data type, shapes, opset) so that the user
/// can tell which part of the export to change.
#[derive(Debug, thiserror::Error)]
pub enum OnnxError {
    /// The bytes are not a valid protobuf encoding of the ONNX schema (truncated,
    /// corrupted, or not an ONNX file).
    #[error("{source_name}: not a valid ONNX file: in {context}, {reason}")]
    Wire {
        source_name: String,
        context: String,
        reason: String,
    },

    /// The IR version is outside what this reader understands.
    #[error("{source_name}: ONNX IR version {found} is not supported (accepted: {min} to {max}; IR 3 introduced opset imports, which the operator semantics depend on; IR 12 to 14 only added data types)")]
    IrVersion {
        source_name: String,
        found: i64,
        min: i64,
        max: i64,
    },

    /// An opset import is missing, or of a version whose operators this reader does
    /// not know.
    #[error("{source_name}: {problem}; accepted: {accepted}")]
    Opset {
        source_name: String,
        problem: String,
        accepted: String,
    },

    /// An operator whose version, under the opset the model imports, means something
    /// other than what the converter reads (an old definition, or one newer than the
    /// definitions checked).
    #[error("{source_name}: node {node} under {domain} opset {opset}: {reason}")]
    OperatorVersion {
        source_name: String,
        node: String,
        domain: &'static str,
        opset: i64,
        reason: String,
    },

    /// The file has no graph, or not exactly one input (besides initializers) or one
    /// output, or nodes that do not form one chain from the input to the output.
    #[error("{source_name}: unsupported graph: {message}")]
    Graph {
        source_name: String,
        message: String,
    },

    /// A node reads a value that a node after it (or itself) writes.
    #[error("{source_name}: node {node} reads '{value}', which is written by {writer} at or after it: the graph has a cycle or is not in topological order")]
    Cycle {
        source_name: String,
        node: String,
        value: String,
        writer: String,
    },

    /// A node reads a value nothing defines.
    #[error("{source_name}: node {node} reads '{value}', which is neither the graph input, an initializer nor the output of a node")]
    DanglingInput {
        source_name: String,
        node: String,
        value: String,
    },

    /// An operator that gives the network state (a recurrent cell or a loop): the ONNX
    /// import reads memoryless networks F(v, F_n, features) only, and a friction law
    /// with memory has its own format.
    #[error("{source_name}: node {node}: operator '{op_type}' makes a network with state (recurrent); the ONNX import reads memoryless networks F(v, F_n, features) only. A friction law with memory comes as a stickslip-state-friction weights file: train one on force records with `stickslip train-memory` (docs/learned-friction-with-memory.md), or use friction.law = lugre or rate-and-state")]
    Recurrent {
        source_name: String,
        node: String,
        op_type: String,
    },

    /// An operator outside the supported set.
    #[error("{source_name}: node {node}: operator '{op_type}' of domain '{domain}' is not supported (supported: {supported})")]
    UnknownOperator {
        source_name: String,
        node: String,
        op_type: String,
        domain: String,
        supported: &'static str,
    },

    /// An attribute the converter cannot honour (name, value, why).
    #[error("{source_name}: node {node}: attribute '{attribute}': {reason}")]
    Attribute {
        source_name: String,
        node: String,
        attribute: String,
        reason: String,
    },

    /// A tensor or value of a data type other than FLOAT and DOUBLE (or INT64 for a
    /// shape).
    #[error("{source_name}: {what} has data type {data_type}; {accepted}")]
    DataType {
        source_name: String,
        what: String,
        data_type: String,
        accepted: &'static str,
    },

    /// Shapes that do not fit (both named).
    #[error("{source_name}: node {node}: {message}")]
    Shape {
        source_name: String,
        node: String,
        message: String,
    },

    /// A weight or constant that is NaN or infinite.
    #[error("{source_name}: tensor '{tensor}' element {index} is {value}, not a finite number")]
    NonFinite {
        source_name: String,
        tensor: String,
        index: usize,
        value: f64,
    },

    /// A chain of operators that is not dense layers with one activation. (The message
    /// names the physics' `NeuralModel`, the one user of this reader, as it always
    /// has: users' scripts and the tests match it.)
    #[error("{source_name}: the network is not one our NeuralModel can hold: {message}")]
    Structure {
        source_name: String,
        message: String,
    },
}
