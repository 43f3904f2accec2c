//! One node of the chain: its operator and attributes checked, and its meaning handed
//! to the layer assembly.

use std::collections::HashMap;

use super::super::error::OnnxError;
use super::super::model::{attribute_type, node_label, AttributeProto, NodeProto};
use super::chain::{Converter, Elementwise, Stage};
use super::network::Activation;
use super::opset::domain_of;
use super::tensors::Constant;

const SUPPORTED: &str = "Gemm, MatMul, Add, Sub, Mul, Div, Tanh, Relu, Sigmoid, Identity, Cast, \
Flatten, Reshape, Constant (ai.onnx) and Scaler (ai.onnx.ml)";

impl Converter<'_> {
    /// Checks a node's attributes against the ones its operator may have here.
    pub(super) fn attributes<'n>(
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

    pub(super) fn attribute_error(
        &self,
        label: &str,
        attribute: &str,
        reason: String,
    ) -> OnnxError {
        OnnxError::Attribute {
            source_name: self.source_name.clone(),
            node: label.to_string(),
            attribute: attribute.to_string(),
            reason,
        }
    }

    /// One node of the chain, reading the running value at input `position`: its
    /// operator's reader below, by domain and type.
    pub(super) fn apply(
        &mut self,
        index: usize,
        node: &NodeProto,
        position: usize,
    ) -> Result<(), OnnxError> {
        let name = node_label(index, node);
        let default = match domain_of(&node.domain) {
            Some(ml) => !ml,
            None => {
                return Err(self.unknown(&name, node));
            }
        };
        match (default, node.op_type.as_str()) {
            (true, "Identity") => {
                self.attributes(node, &name, &[])?;
            }
            (true, "Cast") => self.cast(node, &name)?,
            (true, "Flatten") => self.flatten(node, &name)?,
            (true, "Reshape") => self.reshape(node, &name, position)?,
            (true, "Sub" | "Div" | "Mul" | "Add") => self.arithmetic(node, &name, position)?,
            (false, "Scaler") => self.scaler(node, &name)?,
            (true, "MatMul") => self.matmul(node, &name, position)?,
            (true, "Gemm") => self.gemm(node, &name, position)?,
            (true, "Tanh" | "Relu" | "Sigmoid") => self.activation(node, name)?,
            _ => return Err(self.unknown(&name, node)),
        }
        Ok(())
    }

    /// `Cast`: a no-op between FLOAT and DOUBLE (the target type is checked).
    fn cast(&mut self, node: &NodeProto, name: &str) -> Result<(), OnnxError> {
        let a = self.attributes(
            node,
            name,
            &[
                ("to", attribute_type::INT),
                // Both act on float8 targets only, which the type check refuses.
                ("saturate", attribute_type::INT),
                ("round_mode", attribute_type::STRING),
            ],
        )?;
        let to = a.get("to").map(|a| a.i).ok_or_else(|| {
            self.attribute_error(name, "to", "a Cast needs its target type".into())
        })?;
        self.check_float(to as i32, &format!("node {name}: the cast's target"))
    }

    /// `Flatten`: a no-op on [batch, features] at axis 1 (or -1).
    fn flatten(&self, node: &NodeProto, name: &str) -> Result<(), OnnxError> {
        let a = self.attributes(node, name, &[("axis", attribute_type::INT)])?;
        let axis = a.get("axis").map_or(1, |a| a.i);
        if axis != 1 && axis != -1 {
            return Err(self.attribute_error(
                name,
                "axis",
                format!("axis {axis} would change [batch, features]; only 1 is supported"),
            ));
        }
        Ok(())
    }

    /// `Reshape`: a no-op to [-1, width] or [0, width] (which may tell the width).
    fn reshape(&mut self, node: &NodeProto, name: &str, position: usize) -> Result<(), OnnxError> {
        let a = self.attributes(node, name, &[("allowzero", attribute_type::INT)])?;
        let allowzero = a.get("allowzero").map_or(0, |a| a.i);
        let shape_name = operand(node, 1).filter(|_| position == 0).ok_or_else(|| {
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
                name,
                format!(
                    "reshape to {shape:?} of a [batch, {}] value; only [-1, width] or \
                     [0, width] (a no-op) is supported",
                    self.width.map_or("?".into(), |w| w.to_string())
                ),
            ));
        }
        Ok(())
    }

    /// `Sub`, `Div`, `Mul`, `Add`: the running value and a constant (in that order for
    /// `Sub` and `Div`).
    fn arithmetic(
        &mut self,
        node: &NodeProto,
        name: &str,
        position: usize,
    ) -> Result<(), OnnxError> {
        self.attributes(node, name, &[])?;
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
        let constant_name = operand(node, 1 - position)
            .ok_or_else(|| self.structure(format!("node {name} has no second operand")))?;
        let constant = self.constant(constant_name, name)?;
        self.elementwise(name, op, constant)
    }

    /// `ai.onnx.ml` `Scaler`, y = (x - offset) * scale, on the input only (FLOAT).
    fn scaler(&mut self, node: &NodeProto, name: &str) -> Result<(), OnnxError> {
        let a = self.attributes(
            node,
            name,
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
                return Err(self.attribute_error(name, key, "holds a NaN or infinity".into()));
            }
            Ok(values)
        };
        // Both default to no-op values.
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
                name,
                op,
                Constant {
                    name: format!("{key} attribute"),
                    dims,
                    values,
                },
            )?;
        }
        Ok(())
    }

    /// `MatMul`: running value x constant weights, a dense layer whose bias may follow.
    fn matmul(&mut self, node: &NodeProto, name: &str, position: usize) -> Result<(), OnnxError> {
        self.attributes(node, name, &[])?;
        if position != 0 {
            return Err(self.structure(format!(
                "node {name} multiplies a constant by the running value; only value x \
                 weights is supported"
            )));
        }
        let b_name =
            operand(node, 1).ok_or_else(|| self.structure(format!("node {name} has no B")))?;
        let b = self.constant(b_name, name)?;
        self.dense(name, &b, false, 1.0)?;
        self.stage = Stage::Dense { bias_pending: true };
        Ok(())
    }

    /// `Gemm`: alpha A B' + beta C with the running value as A, a whole dense layer.
    fn gemm(&mut self, node: &NodeProto, name: &str, position: usize) -> Result<(), OnnxError> {
        let a = self.attributes(
            node,
            name,
            &[
                ("alpha", attribute_type::FLOAT),
                ("beta", attribute_type::FLOAT),
                ("transA", attribute_type::INT),
                ("transB", attribute_type::INT),
            ],
        )?;
        let (alpha, trans_b, beta) = self.gemm_attributes(&a, name)?;
        if position != 0 {
            return Err(self.structure(format!(
                "node {name} reads the running value as B or C; only A is supported"
            )));
        }
        let b_name =
            operand(node, 1).ok_or_else(|| self.structure(format!("node {name} has no B")))?;
        let b = self.constant(b_name, name)?;
        self.dense(name, &b, trans_b, alpha)?;
        if let Some(c_name) = operand(node, 2) {
            let c = self.constant(c_name, name)?;
            self.bias(name, &c, beta)?;
        }
        self.stage = Stage::Dense {
            bias_pending: false,
        };
        Ok(())
    }

    /// Gemm's alpha, transB (as whether B is transposed) and beta, checked: alpha and
    /// beta finite, transA 0, transB 0 or 1.
    fn gemm_attributes(
        &self,
        a: &HashMap<&str, &AttributeProto>,
        name: &str,
    ) -> Result<(f64, bool, f64), OnnxError> {
        let alpha = a.get("alpha").map_or(1.0, |a| f64::from(a.f));
        let beta = a.get("beta").map_or(1.0, |a| f64::from(a.f));
        for (key, value) in [("alpha", alpha), ("beta", beta)] {
            if !value.is_finite() {
                return Err(self.attribute_error(name, key, format!("{value} is not finite")));
            }
        }
        if let Some(t) = a.get("transA").filter(|a| a.i != 0) {
            return Err(self.attribute_error(
                name,
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
                name,
                "transB",
                format!("transB = {trans_b}; 0 or 1 is expected"),
            ));
        }
        Ok((alpha, trans_b == 1, beta))
    }

    /// `Tanh`, `Relu`, `Sigmoid`: the hidden activation, right after a dense layer.
    fn activation(&mut self, node: &NodeProto, name: String) -> Result<(), OnnxError> {
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
                return Err(
                    self.structure(format!("activation {name} does not follow a dense layer"))
                )
            }
        }
        self.activations.push((activation, name));
        self.stage = Stage::Activated;
        Ok(())
    }

    pub(super) fn unknown(&self, name: &str, node: &NodeProto) -> OnnxError {
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
}

/// The node's input `k` when it names a value (an empty name is an omitted input).
fn operand(node: &NodeProto, k: usize) -> Option<&String> {
    node.input.get(k).filter(|i| !i.is_empty())
}
