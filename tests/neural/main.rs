//! The neural friction law: inference, weights files, training and search.

mod authors_data;
mod inference;
mod learned_state;
mod onnx;
mod training;
