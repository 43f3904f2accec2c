//! The neural friction law: inference, weights files, training and search.

mod authors_data;
mod inference;
mod memory;
mod onnx;
mod training;
