//! A small ONNX writer for tests and fuzz seeds: a protobuf encoder of the onnx.proto3
//! messages the importer reads, and exports of a `NeuralModel` in the forms PyTorch
//! (`torch.onnx.export` of an `nn.Sequential` MLP: Gemm with transB = 1, raw_data
//! initializers) and skl2onnx (an `MLPRegressor` behind a `StandardScaler`: `Scaler` in
//! f32 or Sub/Div in f64, MatMul + Add, typed float_data/double_data) write them.
//!
//! The graphs are plain data (`Onnx`, `Node`, `Tensor`) so that a test can break one
//! thing (an opset, a weight, an edge) before encoding.

use stickslip::neural::onnx::{FeatureInfo, TargetInfo, FEATURES_KEY, TARGET_KEY, VARIANT_KEY};
use stickslip::neural::{Activation, NeuralModel, Variant};

/// `TensorProto.DataType`.
pub const FLOAT: i32 = 1;
pub const INT64: i32 = 7;
pub const FLOAT16: i32 = 10;
pub const DOUBLE: i32 = 11;

/// A protobuf message being written.
#[derive(Clone, Debug, Default)]
pub struct Message(pub Vec<u8>);

impl Message {
    fn varint_raw(&mut self, mut v: u64) {
        while v >= 0x80 {
            self.0.push((v as u8) | 0x80);
            v >>= 7;
        }
        self.0.push(v as u8);
    }
    fn key(&mut self, field: u32, wire: u64) {
        self.varint_raw((u64::from(field) << 3) | wire);
    }
    pub fn int(&mut self, field: u32, v: i64) -> &mut Self {
        self.key(field, 0);
        self.varint_raw(v as u64);
        self
    }
    pub fn bytes(&mut self, field: u32, b: &[u8]) -> &mut Self {
        self.key(field, 2);
        self.varint_raw(b.len() as u64);
        self.0.extend_from_slice(b);
        self
    }
    pub fn string(&mut self, field: u32, s: &str) -> &mut Self {
        self.bytes(field, s.as_bytes())
    }
    pub fn message(&mut self, field: u32, m: &Message) -> &mut Self {
        self.bytes(field, &m.0)
    }
    pub fn float(&mut self, field: u32, v: f32) -> &mut Self {
        self.key(field, 5);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    pub fn packed_floats(&mut self, field: u32, v: &[f32]) -> &mut Self {
        let b: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.bytes(field, &b)
    }
    pub fn packed_doubles(&mut self, field: u32, v: &[f64]) -> &mut Self {
        let b: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.bytes(field, &b)
    }
    pub fn packed_ints(&mut self, field: u32, v: &[i64]) -> &mut Self {
        let mut packed = Message::default();
        for &x in v {
            packed.varint_raw(x as u64);
        }
        self.bytes(field, &packed.0)
    }
}

/// A tensor's values.
#[derive(Clone, Debug, PartialEq)]
pub enum Data {
    F32(Vec<f32>),
    F64(Vec<f64>),
    I64(Vec<i64>),
}

/// A `TensorProto`.
#[derive(Clone, Debug, PartialEq)]
pub struct Tensor {
    pub name: String,
    pub dims: Vec<i64>,
    pub data: Data,
    /// Written as raw_data (little-endian) instead of the typed field.
    pub raw: bool,
    /// Written as this data type instead of the one `data` implies.
    pub data_type: Option<i32>,
}

impl Tensor {
    pub fn new(name: &str, dims: &[i64], data: Data, raw: bool) -> Tensor {
        Tensor {
            name: name.into(),
            dims: dims.to_vec(),
            data,
            raw,
            data_type: None,
        }
    }

    pub fn encode(&self) -> Message {
        let mut m = Message::default();
        m.packed_ints(1, &self.dims);
        let (kind, raw): (i32, Vec<u8>) = match &self.data {
            Data::F32(v) => (FLOAT, v.iter().flat_map(|x| x.to_le_bytes()).collect()),
            Data::F64(v) => (DOUBLE, v.iter().flat_map(|x| x.to_le_bytes()).collect()),
            Data::I64(v) => (INT64, v.iter().flat_map(|x| x.to_le_bytes()).collect()),
        };
        m.int(2, i64::from(self.data_type.unwrap_or(kind)));
        m.string(8, &self.name);
        if self.raw {
            m.bytes(9, &raw);
        } else {
            match &self.data {
                Data::F32(v) => m.packed_floats(4, v),
                Data::F64(v) => m.packed_doubles(10, v),
                Data::I64(v) => m.packed_ints(7, v),
            };
        }
        m
    }
}

/// An `AttributeProto`.
#[derive(Clone, Debug, PartialEq)]
pub enum Attribute {
    Float(String, f32),
    Int(String, i64),
    Floats(String, Vec<f32>),
    Tensor(String, Tensor),
    Str(String, String),
}

impl Attribute {
    fn encode(&self) -> Message {
        let mut m = Message::default();
        match self {
            Attribute::Float(name, f) => m.string(1, name).float(2, *f).int(20, 1),
            Attribute::Int(name, i) => m.string(1, name).int(3, *i).int(20, 2),
            Attribute::Floats(name, v) => m.string(1, name).packed_floats(7, v).int(20, 6),
            Attribute::Tensor(name, t) => m.string(1, name).message(5, &t.encode()).int(20, 4),
            Attribute::Str(name, v) => m.string(1, name).string(4, v).int(20, 3),
        };
        m
    }
}

/// A `NodeProto`.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub op_type: String,
    pub name: String,
    pub domain: String,
    pub inputs: Vec<String>,
    pub outputs: Vec<String>,
    pub attributes: Vec<Attribute>,
}

impl Node {
    pub fn new(op_type: &str, name: &str, inputs: &[&str], output: &str) -> Node {
        Node {
            op_type: op_type.into(),
            name: name.into(),
            domain: String::new(),
            inputs: inputs.iter().map(|s| s.to_string()).collect(),
            outputs: vec![output.into()],
            attributes: Vec::new(),
        }
    }

    pub fn with(mut self, attribute: Attribute) -> Node {
        self.attributes.push(attribute);
        self
    }

    fn encode(&self) -> Message {
        let mut m = Message::default();
        for i in &self.inputs {
            m.string(1, i);
        }
        for o in &self.outputs {
            m.string(2, o);
        }
        m.string(3, &self.name).string(4, &self.op_type);
        for a in &self.attributes {
            m.message(5, &a.encode());
        }
        if !self.domain.is_empty() {
            m.string(7, &self.domain);
        }
        m
    }
}

/// A `ValueInfoProto` of a [batch, width] tensor (width None: symbolic).
#[derive(Clone, Debug, PartialEq)]
pub struct Value {
    pub name: String,
    pub elem_type: i32,
    pub width: Option<i64>,
}

impl Value {
    fn encode(&self) -> Message {
        let mut batch = Message::default();
        batch.string(2, "batch");
        let mut width = Message::default();
        match self.width {
            Some(w) => width.int(1, w),
            None => width.string(2, "features"),
        };
        let mut shape = Message::default();
        shape.message(1, &batch).message(1, &width);
        let mut tensor = Message::default();
        tensor.int(1, i64::from(self.elem_type)).message(2, &shape);
        let mut kind = Message::default();
        kind.message(1, &tensor);
        let mut m = Message::default();
        m.string(1, &self.name).message(2, &kind);
        m
    }
}

/// A `ModelProto` with its graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Onnx {
    pub ir_version: i64,
    pub producer: (String, String),
    pub opsets: Vec<(String, i64)>,
    pub nodes: Vec<Node>,
    pub initializers: Vec<Tensor>,
    pub inputs: Vec<Value>,
    pub outputs: Vec<Value>,
    pub metadata: Vec<(String, String)>,
}

impl Onnx {
    pub fn encode(&self) -> Vec<u8> {
        let mut graph = Message::default();
        for n in &self.nodes {
            graph.message(1, &n.encode());
        }
        graph.string(2, "mlp");
        for t in &self.initializers {
            graph.message(5, &t.encode());
        }
        for v in &self.inputs {
            graph.message(11, &v.encode());
        }
        for v in &self.outputs {
            graph.message(12, &v.encode());
        }
        let mut m = Message::default();
        m.int(1, self.ir_version)
            .string(2, &self.producer.0)
            .string(3, &self.producer.1)
            .message(7, &graph);
        for (domain, version) in &self.opsets {
            let mut o = Message::default();
            o.string(1, domain).int(2, *version);
            m.message(8, &o);
        }
        for (k, v) in &self.metadata {
            let mut e = Message::default();
            e.string(1, k).string(2, v);
            m.message(14, &e);
        }
        m.0
    }

    /// The node named `name`.
    pub fn node(&mut self, name: &str) -> &mut Node {
        self.nodes
            .iter_mut()
            .find(|n| n.name == name)
            .unwrap_or_else(|| panic!("no node {name}"))
    }

    /// The initializer named `name`.
    pub fn initializer(&mut self, name: &str) -> &mut Tensor {
        self.initializers
            .iter_mut()
            .find(|t| t.name == name)
            .unwrap_or_else(|| panic!("no initializer {name}"))
    }
}

/// Which exporter's graph to imitate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exporter {
    /// torch.onnx.export: Sub/Div normalisation, Gemm (transB = 1), Mul/Add output
    /// scaling, raw_data initializers; opset 17, IR 8.
    Torch,
    /// skl2onnx: Scaler (f32) or Sub/Div (f64), MatMul + Add, Mul/Add, a final Reshape to
    /// [-1, 1]; typed data fields; opset 15 + ai.onnx.ml 1, IR 8.
    Skl,
}

/// The metadata keys describing `model`'s features, target and variant.
pub fn metadata(model: &NeuralModel) -> Vec<(String, String)> {
    let features: Vec<FeatureInfo> = model
        .features
        .iter()
        .map(|f| FeatureInfo {
            name: f.name.clone(),
            unit: f.unit.clone(),
            role: f.role,
            min: f.min,
            max: f.max,
        })
        .collect();
    let target = TargetInfo {
        name: model.target.name.clone(),
        unit: model.target.unit.clone(),
        min: model.target.min,
        max: model.target.max,
    };
    let variant = match model.variant {
        Variant::Plain => "plain",
        Variant::Signed => "signed",
    };
    vec![
        (
            FEATURES_KEY.into(),
            serde_json::to_string(&features).unwrap(),
        ),
        (TARGET_KEY.into(), serde_json::to_string(&target).unwrap()),
        (VARIANT_KEY.into(), variant.into()),
    ]
}

/// `model` as `exporter` writes it, in f32 (`single`) or f64. In f32 every constant is
/// rounded to f32; skl2onnx's Scaler holds 1/std (rounded), the others std.
pub fn export(model: &NeuralModel, exporter: Exporter, single: bool) -> Onnx {
    let data = |v: Vec<f64>| {
        if single {
            Data::F32(v.iter().map(|&x| x as f32).collect())
        } else {
            Data::F64(v)
        }
    };
    let raw = exporter == Exporter::Torch;
    let elem = if single { FLOAT } else { DOUBLE };
    let d = model.features.len() as i64;
    let mut nodes = Vec::new();
    let mut initializers = Vec::new();
    let mut current = "input".to_string();
    let step = |nodes: &mut Vec<Node>, node: Node| {
        let out = node.outputs[0].clone();
        nodes.push(node);
        out
    };
    let means: Vec<f64> = model.features.iter().map(|f| f.input_mean).collect();
    let stds: Vec<f64> = model.features.iter().map(|f| f.input_std).collect();
    if exporter == Exporter::Skl && single {
        let node = Node::new("Scaler", "scaler", &[&current], "scaled")
            .with(Attribute::Floats(
                "offset".into(),
                means.iter().map(|&m| m as f32).collect(),
            ))
            .with(Attribute::Floats(
                "scale".into(),
                stds.iter().map(|&s| (1.0 / s) as f32).collect(),
            ));
        let node = Node {
            domain: "ai.onnx.ml".into(),
            ..node
        };
        current = step(&mut nodes, node);
    } else {
        initializers.push(Tensor::new("mean", &[d], data(means), raw));
        initializers.push(Tensor::new("std", &[d], data(stds), raw));
        current = step(
            &mut nodes,
            Node::new("Sub", "sub", &[&current, "mean"], "centred"),
        );
        current = step(
            &mut nodes,
            Node::new("Div", "div", &[&current, "std"], "standard"),
        );
    }
    let activation = match model.activation {
        Activation::Tanh => "Tanh",
        Activation::Relu => "Relu",
        Activation::Sigmoid => "Sigmoid",
    };
    let last = model.layers.len() - 1;
    for (l, layer) in model.layers.iter().enumerate() {
        let (n, k) = (layer.weights.len(), layer.weights[0].len());
        let (w, b) = (format!("W{l}"), format!("b{l}"));
        initializers.push(Tensor::new(
            &b,
            &[n as i64],
            data(layer.biases.clone()),
            raw,
        ));
        let z = format!("z{l}");
        match exporter {
            Exporter::Torch => {
                let rows: Vec<f64> = layer.weights.iter().flatten().copied().collect();
                initializers.push(Tensor::new(&w, &[n as i64, k as i64], data(rows), raw));
                let gemm = Node::new("Gemm", &format!("gemm{l}"), &[&current, &w, &b], &z)
                    .with(Attribute::Float("alpha".into(), 1.0))
                    .with(Attribute::Float("beta".into(), 1.0))
                    .with(Attribute::Int("transB".into(), 1));
                current = step(&mut nodes, gemm);
            }
            Exporter::Skl => {
                let columns: Vec<f64> = (0..k)
                    .flat_map(|i| layer.weights.iter().map(move |row| row[i]))
                    .collect();
                initializers.push(Tensor::new(&w, &[k as i64, n as i64], data(columns), raw));
                let product = format!("p{l}");
                current = step(
                    &mut nodes,
                    Node::new("MatMul", &format!("matmul{l}"), &[&current, &w], &product),
                );
                current = step(
                    &mut nodes,
                    Node::new("Add", &format!("add{l}"), &[&current, &b], &z),
                );
            }
        }
        if l < last {
            current = step(
                &mut nodes,
                Node::new(
                    activation,
                    &format!("act{l}"),
                    &[&current],
                    &format!("a{l}"),
                ),
            );
        }
    }
    initializers.push(Tensor::new(
        "out_std",
        &[1],
        data(vec![model.target.output_std]),
        raw,
    ));
    initializers.push(Tensor::new(
        "out_mean",
        &[1],
        data(vec![model.target.output_mean]),
        raw,
    ));
    current = step(
        &mut nodes,
        Node::new("Mul", "unscale", &[&current, "out_std"], "scaled_out"),
    );
    let tail = if exporter == Exporter::Skl {
        "shifted"
    } else {
        "force"
    };
    current = step(
        &mut nodes,
        Node::new("Add", "shift", &[&current, "out_mean"], tail),
    );
    if exporter == Exporter::Skl {
        initializers.push(Tensor::new("shape", &[2], Data::I64(vec![-1, 1]), false));
        step(
            &mut nodes,
            Node::new("Reshape", "reshape", &[&current, "shape"], "force"),
        );
    }
    let (producer, opsets) = match exporter {
        Exporter::Torch => (("pytorch", "2.5.0"), vec![(String::new(), 17)]),
        Exporter::Skl => (
            ("skl2onnx", "1.17.0"),
            vec![(String::new(), 15), ("ai.onnx.ml".to_string(), 1)],
        ),
    };
    Onnx {
        ir_version: 8,
        producer: (producer.0.into(), producer.1.into()),
        opsets,
        nodes,
        initializers,
        inputs: vec![Value {
            name: "input".into(),
            elem_type: elem,
            width: if exporter == Exporter::Torch {
                Some(d)
            } else {
                None
            },
        }],
        outputs: vec![Value {
            name: "force".into(),
            elem_type: elem,
            width: Some(1),
        }],
        metadata: metadata(model),
    }
}

/// `model` cut to layers [d, hidden..., 1] (rows and columns of its own weights, so the
/// numbers are realistic) with `activation`.
pub fn cut(model: &NeuralModel, hidden: &[usize], activation: Activation) -> NeuralModel {
    let mut m = model.clone();
    let mut sizes = vec![m.features.len()];
    sizes.extend_from_slice(hidden);
    sizes.push(1);
    m.layers = sizes
        .windows(2)
        .enumerate()
        .map(|(l, io)| {
            let source = &model.layers[l.min(model.layers.len() - 1)];
            stickslip::neural::weights::LayerWeights {
                weights: (0..io[1])
                    .map(|o| (0..io[0]).map(|i| source.weights[o][i]).collect())
                    .collect(),
                biases: source.biases[..io[1]].to_vec(),
            }
        })
        .collect();
    m.layer_sizes = sizes;
    m.activation = activation;
    m
}

/// The seed inputs of the `onnx` fuzz target (fuzz/seeds.rs writes them): small
/// networks cut from the shipped ones, in each exporter's form and precision, one
/// without metadata; each under 2 kB.
pub fn fuzz_seeds() -> Vec<(String, Vec<u8>)> {
    use stickslip::neural::NeuralLaw;
    let plain = NeuralLaw::paper_default().unwrap().model().clone();
    let signed = NeuralLaw::paper_signed().unwrap().model().clone();
    let cases = [
        (
            "torch-f64-tanh-2-4-1",
            cut(&plain, &[4], Activation::Tanh),
            Exporter::Torch,
            false,
        ),
        (
            "torch-f32-sigmoid-2-3-2-1",
            cut(&plain, &[3, 2], Activation::Sigmoid),
            Exporter::Torch,
            true,
        ),
        (
            "skl-f32-relu-2-4-1",
            cut(&plain, &[4], Activation::Relu),
            Exporter::Skl,
            true,
        ),
        (
            "skl-f64-linear-2-1",
            cut(&plain, &[], Activation::Tanh),
            Exporter::Skl,
            false,
        ),
        (
            "torch-f64-signed-2-3-1",
            cut(&signed, &[3], Activation::Tanh),
            Exporter::Torch,
            false,
        ),
    ];
    let mut seeds: Vec<(String, Vec<u8>)> = cases
        .iter()
        .map(|(name, model, exporter, single)| {
            (
                format!("{name}.onnx"),
                export(model, *exporter, *single).encode(),
            )
        })
        .collect();
    let mut bare = export(&cut(&plain, &[2], Activation::Tanh), Exporter::Torch, false);
    bare.metadata.clear();
    seeds.push(("torch-f64-no-metadata-2-2-1.onnx".into(), bare.encode()));
    seeds
}
