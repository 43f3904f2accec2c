//! The macros both models write their variable tables with (`beam::variables`,
//! `friction`): one row of [`crate::variables::Variable`] per call, from the value
//! reference, the name, the unit, the description and the place in the model that
//! holds the value, written `|m: Model| m.place`.
//!
//! Rows that fit none of these (a String, a Boolean, a parameter with its own check)
//! are written out as `Variable { .. }` in the table itself.

use stickslip::choice::Choice;
use stickslip::friction::registry::{self, LawDescription, LawParameter, LawTables, ParameterKind};

/// One row: what every macro below shares.
macro_rules! row {
    ($vr:expr, $name:expr, $causality:ident, $variability:ident, $description:expr, $access:expr, $depends_on:expr) => {
        $crate::variables::Variable {
            name: $name,
            value_reference: $vr,
            causality: $crate::variables::Causality::$causality,
            variability: $crate::variables::Variability::$variability,
            description: $description,
            access: $access,
            depends_on: $depends_on,
        }
    };
}

/// A Real parameter (`fixed`), read and written at the place.
macro_rules! real_parameter {
    ($vr:expr, $name:expr, $unit:expr, $description:expr, |$m:ident: $model:ty| $place:expr) => {
        $crate::declare::row!(
            $vr,
            $name,
            Parameter,
            Fixed,
            $description,
            $crate::variables::Access::Real {
                unit: $unit,
                get: Box::new(|$m: &$model| $place),
                set: Some(Box::new(|$m: &mut $model, v: f64| {
                    $place = v;
                    Ok(())
                })),
            },
            None
        )
    };
}

/// A parameter holding a choice `$choice`: its codes, words and the value's code are
/// all read off the choice.
macro_rules! choice_parameter {
    ($vr:expr, $name:expr, $choice:ty, $description:expr, |$m:ident: $model:ty| $place:expr) => {
        $crate::declare::row!(
            $vr,
            $name,
            Parameter,
            Fixed,
            $description,
            $crate::variables::Access::Choice {
                kind: $crate::variables::ChoiceType::of::<$choice>(),
                get: Box::new(|$m: &$model| {
                    use ::stickslip::choice::Choice as _;
                    $place.code()
                }),
                set: Some(Box::new(|$m: &mut $model, v: i32| {
                    $place = $crate::variables::choice_at::<$choice>(v)?;
                    Ok(())
                })),
            },
            None
        )
    };
}

/// A count parameter (FMI Integer from 1 to `$max`) held as a `usize`.
macro_rules! count_parameter {
    ($vr:expr, $name:expr, $max:expr, $description:expr, |$m:ident: $model:ty| $place:expr) => {
        $crate::declare::row!(
            $vr,
            $name,
            Parameter,
            Fixed,
            $description,
            $crate::variables::Access::Integer {
                min: 1,
                max: $max,
                // Saturating: a count beyond i32 (from a saved state) reads as out of range.
                get: Box::new(|$m: &$model| i32::try_from($place).unwrap_or(i32::MAX)),
                set: Some(Box::new(|$m: &mut $model, v: i32| {
                    $place = v as usize;
                    Ok(())
                })),
            },
            None
        )
    };
}

/// A Real input (`continuous`), read and written at the place. `check` refuses a value
/// before it is written; `then` runs after it is (both optional, in this order).
macro_rules! real_input {
    ($vr:expr, $name:expr, $unit:expr, $description:expr, |$m:ident: $model:ty| $place:expr
        $(, check = $check:expr)? $(, then = $then:expr)? $(,)?) => {
        $crate::declare::row!(
            $vr,
            $name,
            Input,
            Continuous,
            $description,
            $crate::variables::Access::Real {
            unit: $unit,
            get: Box::new(|$m: &$model| $place),
            set: Some(Box::new(|$m: &mut $model, v: f64| {
                $(
                    let check: fn(f64) -> Result<(), String> = $check;
                    check(v)?;
                )?
                $place = v;
                $($then;)?
                Ok(())
            })),
        },
            None
        )
    };
}

/// A Real output (`continuous`), read off the model, depending on `$depends_on`.
macro_rules! real_output {
    ($vr:expr, $name:expr, $unit:expr, $description:expr, $depends_on:expr, |$m:ident: $model:ty| $value:expr) => {
        $crate::declare::row!(
            $vr,
            $name,
            Output,
            Continuous,
            $description,
            $crate::variables::Access::Real {
                unit: $unit,
                get: Box::new(|$m: &$model| $value),
                set: None,
            },
            Some($depends_on)
        )
    };
}

/// A weights parameter (String): the name of a network file, refused when blank
/// (`networks::weights_name`; whether the file exists is checked when it is read).
macro_rules! weights_parameter {
    ($vr:expr, $name:expr, $description:expr, |$m:ident: $model:ty| $place:expr) => {
        $crate::declare::row!(
            $vr,
            $name,
            Parameter,
            Fixed,
            $description,
            $crate::variables::Access::String {
                get: Box::new(|$m: &$model| $place.clone()),
                set: Some(Box::new(|$m: &mut $model, v: &str| {
                    $place = $crate::networks::weights_name(v)?;
                    Ok(())
                })),
            },
            None
        )
    };
}

/// The rows of every law's parameters (`stickslip::friction::registry`), law by law,
/// under the scene file's names and the registry's value references: one declaration
/// for every model that has them. `law_variable` is the model's name of the law choice
/// (`friction.law`, `law`), named in the first row of each law; `tables` finds the
/// model's parameter tables.
pub fn law_parameters<M: 'static>(
    law_variable: &'static str,
    tables: fn(&M) -> &LawTables,
    tables_mut: fn(&mut M) -> &mut LawTables,
) -> Vec<crate::variables::Variable<M>> {
    use crate::variables::{Access, Causality, Variability, Variable};
    let row = |law: &LawDescription, index: usize, parameter: &'static LawParameter| {
        let description: &'static str = if index == 0 {
            // Once per row, when the table is first built.
            Box::leak(
                format!(
                    "{} ({law_variable} = {})",
                    parameter.description,
                    law.kind.name()
                )
                .into_boxed_str(),
            )
        } else {
            parameter.description
        };
        let access = match parameter.kind {
            ParameterKind::Real { unit, .. } => Access::Real {
                unit,
                get: Box::new(move |m: &M| tables(m).get(parameter)),
                set: Some(Box::new(move |m: &mut M, v: f64| {
                    tables_mut(m).set(parameter, v);
                    Ok(())
                })),
            },
            ParameterKind::Choice(kind) => Access::Choice {
                kind,
                get: Box::new(move |m: &M| tables(m).get(parameter) as i32),
                set: Some(Box::new(move |m: &mut M, v: i32| {
                    kind.item(v)?;
                    tables_mut(m).set(parameter, f64::from(v));
                    Ok(())
                })),
            },
        };
        Variable {
            name: parameter.name,
            value_reference: parameter.value_reference,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            description,
            access,
            depends_on: None,
        }
    };
    registry::laws()
        .flat_map(|law| {
            law.parameters
                .iter()
                .enumerate()
                .map(move |(index, parameter)| row(law, index, parameter))
        })
        .collect()
}

/// An input's check: the value must not be negative (a force, a magnitude).
pub fn non_negative(v: f64) -> Result<(), String> {
    if v < 0.0 {
        Err(format!("{v} must be >= 0"))
    } else {
        Ok(())
    }
}

pub(crate) use {
    choice_parameter, count_parameter, real_input, real_output, real_parameter, row,
    weights_parameter,
};
