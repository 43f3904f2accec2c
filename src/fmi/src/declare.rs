//! The macros both models write their variable tables with (`beam::variables`,
//! `friction`): one row of [`crate::variables::Variable`] per call, from the value
//! reference, the name, the unit, the description and the place in the model that
//! holds the value, written `|m: Model| m.place`.
//!
//! Rows that fit none of these (a String, a Boolean, a parameter with its own check)
//! are written out as `Variable { .. }` in the table itself.

/// A Real parameter (`fixed`), read and written at the place.
macro_rules! real_parameter {
    ($vr:expr, $name:expr, $unit:expr, $description:expr, |$m:ident: $model:ty| $place:expr) => {
        $crate::variables::Variable {
            name: $name,
            value_reference: $vr,
            causality: $crate::variables::Causality::Parameter,
            variability: $crate::variables::Variability::Fixed,
            description: $description,
            access: $crate::variables::Access::Real {
                unit: $unit,
                get: |$m: &$model| $place,
                set: Some(|$m: &mut $model, v: f64| {
                    $place = v;
                    Ok(())
                }),
            },
            depends_on: None,
        }
    };
}

/// A parameter holding a choice `$choice`: its codes, words and the value's code are
/// all read off the choice.
macro_rules! choice_parameter {
    ($vr:expr, $name:expr, $choice:ty, $description:expr, |$m:ident: $model:ty| $place:expr) => {
        $crate::variables::Variable {
            name: $name,
            value_reference: $vr,
            causality: $crate::variables::Causality::Parameter,
            variability: $crate::variables::Variability::Fixed,
            description: $description,
            access: $crate::variables::Access::Choice {
                kind: $crate::variables::ChoiceType::of::<$choice>(),
                get: |$m: &$model| {
                    use ::stickslip::choice::Choice as _;
                    $place.code()
                },
                set: Some(|$m: &mut $model, v: i32| {
                    $place = $crate::variables::choice_at::<$choice>(v)?;
                    Ok(())
                }),
            },
            depends_on: None,
        }
    };
}

/// A count parameter (FMI Integer from 1 to `$max`) held as a `usize`.
macro_rules! count_parameter {
    ($vr:expr, $name:expr, $max:expr, $description:expr, |$m:ident: $model:ty| $place:expr) => {
        $crate::variables::Variable {
            name: $name,
            value_reference: $vr,
            causality: $crate::variables::Causality::Parameter,
            variability: $crate::variables::Variability::Fixed,
            description: $description,
            access: $crate::variables::Access::Integer {
                min: 1,
                max: $max,
                get: |$m: &$model| $place as i32,
                set: Some(|$m: &mut $model, v: i32| {
                    $place = v as usize;
                    Ok(())
                }),
            },
            depends_on: None,
        }
    };
}

/// A Real input (`continuous`), read and written at the place. `check` refuses a value
/// before it is written; `then` runs after it is (both optional, in this order).
macro_rules! real_input {
    ($vr:expr, $name:expr, $unit:expr, $description:expr, |$m:ident: $model:ty| $place:expr
        $(, check = $check:expr)? $(, then = $then:expr)? $(,)?) => {
        $crate::variables::Variable {
            name: $name,
            value_reference: $vr,
            causality: $crate::variables::Causality::Input,
            variability: $crate::variables::Variability::Continuous,
            description: $description,
            access: $crate::variables::Access::Real {
                unit: $unit,
                get: |$m: &$model| $place,
                set: Some(|$m: &mut $model, v: f64| {
                    $(
                        let check: fn(f64) -> Result<(), String> = $check;
                        check(v)?;
                    )?
                    $place = v;
                    $($then;)?
                    Ok(())
                }),
            },
            depends_on: None,
        }
    };
}

/// A Real output (`continuous`), read off the model, depending on `$depends_on`.
macro_rules! real_output {
    ($vr:expr, $name:expr, $unit:expr, $description:expr, $depends_on:expr, |$m:ident: $model:ty| $value:expr) => {
        $crate::variables::Variable {
            name: $name,
            value_reference: $vr,
            causality: $crate::variables::Causality::Output,
            variability: $crate::variables::Variability::Continuous,
            description: $description,
            access: $crate::variables::Access::Real {
                unit: $unit,
                get: |$m: &$model| $value,
                set: None,
            },
            depends_on: Some($depends_on),
        }
    };
}

/// An input's check: the value must not be negative (a force, a magnitude).
pub fn non_negative(v: f64) -> Result<(), String> {
    if v < 0.0 {
        Err(format!("{v} must be >= 0"))
    } else {
        Ok(())
    }
}

pub(crate) use {choice_parameter, count_parameter, real_input, real_output, real_parameter};
