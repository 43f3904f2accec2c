//! Directional derivatives (FMI 2.0 section 2.1.9, FMI 3.0 section 2.2.11): the
//! sensitivity dv_unknown = (dh/dv_known) dv_known of outputs (the unknowns of Step
//! Mode, listed in ModelStructure/Outputs) with respect to inputs (the knowns), from the
//! model's partial derivatives at the current inputs.
//!
//! Decisions where the standards leave room:
//! - Legal where the reads are (`Call::GetDirectionalDerivative`), also in
//!   Initialization Mode, where the unknowns would be the InitialUnknowns: there too only
//!   outputs with respect to inputs are given; a parameter as a known is refused with a
//!   reason (the FMUs do not differentiate with respect to parameters).
//! - Every value reference is checked: an unknown must be a Real output, a known a Real
//!   input; seeds must be finite. Any violation is fmi2Error/fmi3Error with the reason.
//! - A result that is not finite is refused the same way (no silent NaN).

use super::base::{CallResult, Instance};
use super::machine::Call;
use crate::model::Model;
use crate::variables::{lookup, BaseType, Causality};

impl<M: Model> Instance<M> {
    /// Refuses a directional derivative of a model without them (its capability flag is
    /// false) or in a mode that does not allow one.
    pub fn directional_derivative_allowed(&mut self) -> CallResult<()> {
        let names = self.names();
        if !M::INFO.provides_directional_derivatives {
            let reason = format!(
                "not supported: {} is false",
                names.directional_derivative_flag
            );
            return Err(self.fail(names.get_directional_derivative, &reason));
        }
        self.check(Call::GetDirectionalDerivative)
    }

    /// Fills `sensitivity` (one value per unknown) with the directional derivative of
    /// the outputs `unknowns` along `seed` (one value per known) of the inputs `knowns`.
    pub fn get_directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> CallResult<()> {
        self.directional_derivative_allowed()?;
        let call = self.names().get_directional_derivative;
        if seed.len() != knowns.len() || sensitivity.len() != unknowns.len() {
            let reason = format!(
                "{} seed values for {} knowns, room for {} sensitivities for {} unknowns",
                seed.len(),
                knowns.len(),
                sensitivity.len(),
                unknowns.len()
            );
            return Err(self.fail(call, &reason));
        }
        if let Err(reason) = check_references::<M>(unknowns, knowns, seed) {
            return Err(self.fail(call, &reason));
        }
        let partials = self
            .model
            .partial_derivatives()
            .map_err(|reason| self.fail(call, &reason))?;
        let mut values = Vec::with_capacity(unknowns.len());
        for &output in unknowns {
            let value: f64 = knowns
                .iter()
                .zip(seed)
                .map(|(&input, s)| partials.get(output, input) * s)
                .sum();
            if !value.is_finite() {
                let reason = format!(
                    "the directional derivative of value reference {output} is {value} (partial derivatives {partials:?})"
                );
                return Err(self.fail(call, &reason));
            }
            values.push(value);
        }
        sensitivity.copy_from_slice(&values);
        Ok(())
    }
}

/// Why the request cannot be answered: an unknown that is not a Real output, a known
/// that is not a Real input, a seed that is not finite.
fn check_references<M: Model>(
    unknowns: &[u32],
    knowns: &[u32],
    seed: &[f64],
) -> Result<(), String> {
    let variables = M::variables();
    for &vr in unknowns {
        let variable =
            lookup(variables, vr, BaseType::Real).map_err(|e| format!("unknown: {e}"))?;
        if variable.causality != Causality::Output {
            return Err(format!(
                "unknown {} (value reference {vr}) is not an output: the unknowns are the outputs of ModelStructure",
                variable.name
            ));
        }
    }
    for (&vr, s) in knowns.iter().zip(seed) {
        let variable = lookup(variables, vr, BaseType::Real).map_err(|e| format!("known: {e}"))?;
        if variable.causality != Causality::Input {
            return Err(format!(
                "known {} (value reference {vr}) is not an input: derivatives are given with respect to inputs only",
                variable.name
            ));
        }
        if !s.is_finite() {
            return Err(format!(
                "the seed of {} (value reference {vr}) is {s}: seeds must be finite",
                variable.name
            ));
        }
    }
    Ok(())
}
