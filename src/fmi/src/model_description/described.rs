//! What a description says of one FMU: the data both versions' writers read, apart from
//! the writers themselves (`model_description` adds the methods that call them).

use crate::model::Model;

/// What a description says of one FMU of model `M`: its modelName and
/// modelIdentifier, its description, and the model whose values are the start values.
/// A built-in FMU is `M::INFO` with `M::with_defaults()`; an exported FMU
/// (`crate::export`) is the same table with its own name and start values.
pub struct Described<M> {
    pub model_identifier: String,
    pub description: String,
    pub defaults: M,
}

impl<M: Model> Described<M> {
    /// The built-in FMU of model `M`.
    pub fn built_in() -> Self {
        Self {
            model_identifier: M::INFO.model_identifier.to_owned(),
            description: M::INFO.description.to_owned(),
            defaults: M::with_defaults(),
        }
    }
}
