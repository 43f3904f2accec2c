//! How a law's parameter out of range is told: every law's parameter check
//! (`registry::LawParameter::problem`, a law's joint check) returns a
//! [`ParameterProblem`], so that the scene check, the command line and both FMUs give
//! the same words.

use crate::short::Short;
use std::fmt;

/// A parameter out of its range: its dotted name, its value and what it must be.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterProblem {
    pub field: &'static str,
    pub value: f64,
    pub requirement: String,
}

impl fmt::Display for ParameterProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} = {}; it must be {}",
            self.field,
            Short(self.value),
            self.requirement
        )
    }
}
