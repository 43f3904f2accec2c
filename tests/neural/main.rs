//! The neural friction law: inference, weights files, training and search.

mod training;
