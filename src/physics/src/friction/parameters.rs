//! How a law's parameter out of range is told: every law's parameter check
//! (`LuGreParameters::problem`, `RateStateParameters::problem`) returns a
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

/// A parameter's check: (dotted name, value, whether its range holds, requirement).
pub(crate) type Check = (&'static str, f64, bool, &'static str);

/// The first check whose value is not finite or out of range.
pub(crate) fn first_problem<const N: usize>(checks: [Check; N]) -> Option<ParameterProblem> {
    checks
        .into_iter()
        .find(|(_, value, ok, _)| !(value.is_finite() && *ok))
        .map(|(field, value, _, requirement)| ParameterProblem {
            field,
            value,
            requirement: requirement.into(),
        })
}
