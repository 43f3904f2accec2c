//! Command-line values of the scene's choices, read off the physics crate's
//! [`Choice`] enums: the words, their order and their help lines are not retyped here.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use stickslip::choice::Choice;

/// A clap value parser that accepts exactly the words of `T`, with each value's
/// description as its help line.
pub fn parser<T: Choice>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(
        T::ALL
            .iter()
            .map(|c| PossibleValue::new(c.name()).help(c.description())),
    )
    .try_map(|word: String| {
        T::from_name(&word).ok_or_else(|| format!("{word} is not a {} value", T::TYPE_NAME))
    })
}
