//! Dense layers from weight and bias constants, and the elementwise scalings by
//! constants collected for the input normalisation and output scaling.

use super::super::error::OnnxError;
use super::chain::{Converter, Elementwise, Stage};
use super::network::DenseLayer;
use super::tensors::{shape_text, Constant};

impl Converter<'_> {
    /// x op c by a constant: normalisation before the first layer, a MatMul's bias, or
    /// output scaling after a layer.
    pub(super) fn elementwise(
        &mut self,
        name: &str,
        op: Elementwise,
        c: Constant,
    ) -> Result<(), OnnxError> {
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
    pub(super) fn dense(
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
        self.layers.push(DenseLayer {
            weights,
            biases: vec![0.0; n],
        });
        self.width = Some(n);
        Ok(())
    }

    /// Adds beta * c to the last layer's biases.
    pub(super) fn bias(&mut self, name: &str, c: &Constant, beta: f64) -> Result<(), OnnxError> {
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
}
