//! The constants a node reads (initializers and `Constant` nodes), as checked f64 or
//! i64 values, and the element types the graph computes in.

use super::super::error::OnnxError;
use super::super::model::{data_type, TensorProto};
use super::chain::Converter;

pub(super) fn shape_text(dims: &[i64]) -> String {
    format!("{dims:?}")
}

/// A constant's values with its dims.
pub(super) struct Constant {
    pub(super) name: String,
    pub(super) dims: Vec<i64>,
    pub(super) values: Vec<f64>,
}

impl Constant {
    /// The dims without leading 1s (numpy broadcasting against [batch, width]).
    pub(super) fn trailing(&self) -> &[i64] {
        let first = self
            .dims
            .iter()
            .position(|&d| d != 1)
            .unwrap_or(self.dims.len());
        &self.dims[first..]
    }
}

impl Converter<'_> {
    /// Notes an element type: FLOAT or DOUBLE, anything else refused by name.
    pub(super) fn check_float(&mut self, elem_type: i32, what: &str) -> Result<(), OnnxError> {
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
    pub(super) fn element_count(&self, tensor: &TensorProto) -> Result<usize, OnnxError> {
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

    pub(super) fn stored_in_file(&self, tensor: &TensorProto) -> Result<(), OnnxError> {
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

    pub(super) fn count_mismatch(
        &self,
        tensor: &TensorProto,
        count: usize,
        found: usize,
    ) -> OnnxError {
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
    pub(super) fn float_values(&mut self, tensor: &TensorProto) -> Result<Vec<f64>, OnnxError> {
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
    pub(super) fn int_values(&self, tensor: &TensorProto) -> Result<Vec<i64>, OnnxError> {
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

    pub(super) fn constant(&mut self, name: &str, node: &str) -> Result<Constant, OnnxError> {
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
}
