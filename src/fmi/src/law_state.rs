//! The friction law's state as FMU outputs: one Real output per entry of
//! `stickslip::friction::state::STATE_VARIABLES` (LuGre's bristle deflection, rate-and-state's
//! theta, the learned law's psi), named, united and described by that entry, so that
//! the physics crate is the one place that says what a state variable is. A run whose
//! law has not the variable outputs 0, and the description says so.
//!
//! The rows are made from the list when a table is first built ([`law_state_outputs`]),
//! so a new entry of the list is an output of both FMUs with no row written for it.

use crate::variables::{Access, Causality, Dependencies, Variability, Variable};
use stickslip::friction::state::STATE_VARIABLES;

/// What every state output's description adds to its variable's: the value of a law
/// without it.
pub const ABSENT: &str = "; the friction law's state, 0 for a law without this variable";

/// A state variable's unit as an FMU unit: "1" (dimensionless) is no unit, as for every
/// other dimensionless variable of the tables.
pub const fn fmi_unit(unit: &'static str) -> Option<&'static str> {
    match unit.as_bytes() {
        b"1" => None,
        _ => Some(unit),
    }
}

/// One Real output per entry of `STATE_VARIABLES`, in its order: value references
/// `first_value_reference` + k, named and described by entry k, read off the model as
/// `value(model, k)`, depending on `depends_on(k)`.
pub fn law_state_outputs<M: 'static>(
    first_value_reference: u32,
    depends_on: impl Fn(usize) -> Dependencies,
    value: fn(&M, usize) -> f64,
) -> Vec<Variable<M>> {
    STATE_VARIABLES
        .iter()
        .enumerate()
        .map(|(k, variable)| Variable {
            name: variable.name,
            value_reference: first_value_reference + k as u32,
            causality: Causality::Output,
            variability: Variability::Continuous,
            // Once per row, when the table is first built.
            description: Box::leak(format!("{}{ABSENT}", variable.description).into_boxed_str()),
            access: Access::Real {
                unit: fmi_unit(variable.unit),
                get: Box::new(move |m: &M| value(m, k)),
                set: None,
            },
            depends_on: Some(depends_on(k)),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_map() {
        assert_eq!(fmi_unit("1"), None);
        assert_eq!(fmi_unit("m"), Some("m"));
    }
}
