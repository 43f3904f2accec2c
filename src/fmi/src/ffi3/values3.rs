//! What an FMI 3.0 Float64 request means in terms of the tables: fmi3GetFloat64 and
//! fmi3SetFloat64 take value references and a flat buffer of `nValues` values (FMI 3.0:
//! the values of all variables in the order of the value references, each array
//! serialized in row-major order). Besides the tables' scalar Reals, a
//! value reference there can name:
//! - the independent variable `time` (value reference 0,
//!   [`model_description::TIME_VALUE_REFERENCE`]): the instance's current time, which
//!   can be read (as Reference-FMUs do) and not set: fmi3DoStep advances it;
//! - an array variable ([`Model::arrays`]): its elements, in element order.
//!
//! The elements of an array are not FMI 3.0 variables of their own: their FMI 2.0
//! value references are refused here with the array to use instead. Everything else
//! goes through the instance's scalar accessors (those of fmi2GetReal and fmi2SetReal),
//! so the state machine and the checks are the same, and the log names the FMI 3.0
//! function. fmi3GetDirectionalDerivative's seed and sensitivity are such flat buffers
//! too.

use crate::instance::{Call, CallResult, Instance};
use crate::model::Model;
use crate::model_description::TIME_VALUE_REFERENCE;
use crate::variables::ArrayVariable;

/// One value of the flat buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// The instance's time.
    Time,
    /// A scalar Real of the table, by value reference.
    Scalar(u32),
}

/// The values a request for `vrs` stands for, in buffer order; or why a value reference
/// cannot be used in FMI 3.0 (an array element named by its FMI 2.0 value reference).
/// Unknown value references and ones of other types are left to the table's lookup,
/// which names them.
pub fn slots<M: Model>(vrs: &[u32]) -> Result<Vec<Slot>, String> {
    let mut slots = Vec::with_capacity(vrs.len());
    for &vr in vrs {
        if vr == TIME_VALUE_REFERENCE {
            slots.push(Slot::Time);
        } else if let Some(array) = M::arrays().iter().find(|a| a.value_reference == vr) {
            slots.extend(array.elements.iter().map(|&e| Slot::Scalar(e)));
        } else if let Some((array, index)) = ArrayVariable::containing(M::arrays(), vr) {
            return Err(format!(
                "no variable has value reference {vr} in FMI 3.0: it is element {index} of the array {} (value reference {}, {} values)",
                array.name,
                array.value_reference,
                array.elements.len()
            ));
        } else {
            slots.push(Slot::Scalar(vr));
        }
    }
    Ok(slots)
}

/// Checks that the buffer holds exactly the values the value references stand for.
fn count_matches(vrs: &[u32], slots: &[Slot], n_values: usize) -> Result<(), String> {
    if slots.len() == n_values {
        return Ok(());
    }
    Err(format!(
        "nValues = {n_values}, but the value references {vrs:?} stand for {} values (an array counts its elements, a scalar and time one each)",
        slots.len()
    ))
}

/// The value references of the scalar slots, in order.
fn scalars(slots: &[Slot]) -> Vec<u32> {
    slots
        .iter()
        .filter_map(|s| match s {
            Slot::Scalar(vr) => Some(*vr),
            Slot::Time => None,
        })
        .collect()
}

/// fmi3GetFloat64: fills `out` (its length is nValues).
pub fn get<M: Model>(instance: &mut Instance<M>, vrs: &[u32], out: &mut [f64]) -> CallResult<()> {
    instance.check(Call::Get)?;
    let slots = slots::<M>(vrs)
        .and_then(|slots| count_matches(vrs, &slots, out.len()).map(|()| slots))
        .map_err(|reason| instance.fail(instance.names().get_real, &reason))?;
    let scalar_vrs = scalars(&slots);
    let mut values = vec![0.0; scalar_vrs.len()];
    instance.get_real(&scalar_vrs, &mut values)?;
    let mut values = values.into_iter();
    for (slot, value) in slots.iter().zip(out.iter_mut()) {
        *value = match slot {
            Slot::Time => instance.time(),
            // As many scalar values as scalar slots.
            Slot::Scalar(_) => values.next().unwrap_or(f64::NAN),
        };
    }
    Ok(())
}

/// fmi3SetFloat64: `values` has length nValues. Setting `time` is refused.
pub fn set<M: Model>(instance: &mut Instance<M>, vrs: &[u32], values: &[f64]) -> CallResult<()> {
    instance.check(Call::Set)?;
    let slots = slots::<M>(vrs)
        .and_then(|slots| count_matches(vrs, &slots, values.len()).map(|()| slots))
        .map_err(|reason| instance.fail(instance.names().set_real, &reason))?;
    if slots.contains(&Slot::Time) {
        return Err(instance.fail(
            instance.names().set_real,
            "time (value reference 0) is the independent variable: the instance's clock, which only fmi3DoStep advances; it cannot be set",
        ));
    }
    let scalar_values: Vec<f64> = slots
        .iter()
        .zip(values)
        .filter(|(slot, _)| matches!(slot, Slot::Scalar(_)))
        .map(|(_, &v)| v)
        .collect();
    instance.set_real(&scalars(&slots), &scalar_values)
}

/// fmi3GetDirectionalDerivative: `seed` holds the values the `knowns` stand for (an
/// array its elements), `sensitivity` those the `unknowns` stand for; `time` is neither
/// an input nor an output, and is refused as either.
pub fn directional_derivative<M: Model>(
    instance: &mut Instance<M>,
    unknowns: &[u32],
    knowns: &[u32],
    seed: &[f64],
    sensitivity: &mut [f64],
) -> CallResult<()> {
    instance.directional_derivative_allowed()?;
    let scalars_of = |vrs: &[u32], n_values: usize| -> Result<Vec<u32>, String> {
        let slots = slots::<M>(vrs)?;
        count_matches(vrs, &slots, n_values)?;
        if slots.contains(&Slot::Time) {
            return Err("time (value reference 0) is neither an input nor an output: the outputs do not depend on it".into());
        }
        Ok(scalars(&slots))
    };
    let expanded = scalars_of(unknowns, sensitivity.len())
        .map_err(|reason| format!("unknowns: {reason} (nSensitivity)"))
        .and_then(|u| {
            scalars_of(knowns, seed.len())
                .map(|k| (u, k))
                .map_err(|reason| format!("knowns: {reason} (nSeed)"))
        });
    match expanded {
        Ok((unknowns, knowns)) => {
            instance.get_directional_derivative(&unknowns, &knowns, seed, sensitivity)
        }
        Err(reason) => {
            let call = instance.names().get_directional_derivative;
            Err(instance.fail(call, &reason))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::StickSlipBeam;
    use crate::friction::{NeuralFriction, EXTRA_FEATURE_ARRAY};

    #[test]
    fn an_array_stands_for_its_elements_in_order() {
        assert_eq!(
            slots::<NeuralFriction>(&[10, EXTRA_FEATURE_ARRAY, 0]).unwrap(),
            vec![
                Slot::Scalar(10),
                Slot::Scalar(12),
                Slot::Scalar(13),
                Slot::Scalar(14),
                Slot::Scalar(15),
                Slot::Time
            ]
        );
    }

    #[test]
    fn an_element_is_no_fmi3_variable() {
        let reason = slots::<NeuralFriction>(&[13]).unwrap_err();
        assert!(
            reason.contains("element 2 of the array extra_feature"),
            "{reason}"
        );
        assert!(reason.contains("value reference 16"), "{reason}");
    }

    #[test]
    fn the_beam_has_no_arrays() {
        assert!(StickSlipBeam::arrays().is_empty());
        assert_eq!(
            slots::<StickSlipBeam>(&[16]).unwrap(),
            vec![Slot::Scalar(16)]
        );
    }

    #[test]
    fn every_array_fits_its_table() {
        for array in NeuralFriction::arrays() {
            array.check(NeuralFriction::variables()).unwrap();
        }
    }

    #[test]
    fn a_wrong_count_names_what_was_expected() {
        let vrs = [EXTRA_FEATURE_ARRAY, 10];
        let slots = slots::<NeuralFriction>(&vrs).unwrap();
        assert!(count_matches(&vrs, &slots, 5).is_ok());
        let reason = count_matches(&vrs, &slots, 2).unwrap_err();
        assert!(
            reason.contains("nValues = 2") && reason.contains("5 values"),
            "{reason}"
        );
    }
}
