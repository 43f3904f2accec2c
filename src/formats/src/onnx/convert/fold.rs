//! The end of the chain: the collected scalings folded into the input normalisation and
//! output scaling (see the `convert` documentation on rounding), and the network
//! checked.

use super::super::error::OnnxError;
use super::chain::{Converter, Elementwise, Stage};
use super::network::Activation;
use super::network::{OnnxNetwork, Precision};

impl Converter<'_> {
    /// The chain read to its end as the network: its ending and activations checked,
    /// the scalings folded, every folded number checked finite.
    pub(super) fn finish(
        mut self,
        producer: String,
        metadata: Vec<(String, String)>,
    ) -> Result<OnnxNetwork, OnnxError> {
        let activation = self.hidden_activation()?;
        let (mean, std) = self.input_normalisation()?;
        let (offset, scale) = self.output_scaling()?;
        self.check_layers_finite()?;
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

    /// The one activation of the hidden layers (Tanh when there is none), once the chain
    /// is known to end in a linear dense layer with one output.
    fn hidden_activation(&self) -> Result<Activation, OnnxError> {
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
        Ok(activation)
    }

    /// The input scalings as (x - mean) / std, composed op by op (see the module
    /// documentation); a negative std is moved into the first layer's weights.
    fn input_normalisation(&mut self) -> Result<(Vec<f64>, Vec<f64>), OnnxError> {
        let inputs = self.layers[0].weights[0].len();
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
        Ok((mean, std))
    }

    /// The output scalings as y = offset + scale z, composed op by op; a negative scale
    /// is moved into the last layer.
    fn output_scaling(&mut self) -> Result<(f64, f64), OnnxError> {
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
        Ok((offset, scale))
    }

    /// Every weight and bias finite: folding alpha/beta can overflow finite constants.
    fn check_layers_finite(&self) -> Result<(), OnnxError> {
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
        for (l, layer) in self.layers.iter().enumerate() {
            for row in &layer.weights {
                check(row, format!("layer {} weights (after alpha)", l + 1))?;
            }
            check(
                &layer.biases,
                format!("layer {} biases (after beta)", l + 1),
            )?;
        }
        Ok(())
    }
}
