//! The neural friction law: inference, weights files, training and search.

mod inference;
mod onnx;
mod training;
