//! The macros both models write their variable tables with (`beam::variables`,
//! `friction`): one row of [`crate::variables::Variable`] per call, from the value
//! reference, the name, the unit, the description and the place in the model that
//! holds the value, written `|m: Model| m.place`.
//!
//! Rows that fit none of these (a String, a Boolean, a parameter with its own check)
//! are written out as `Variable { .. }` in the table itself.

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
                get: |$m: &$model| $place,
                set: Some(|$m: &mut $model, v: f64| {
                    $place = v;
                    Ok(())
                }),
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
                get: |$m: &$model| {
                    use ::stickslip::choice::Choice as _;
                    $place.code()
                },
                set: Some(|$m: &mut $model, v: i32| {
                    $place = $crate::variables::choice_at::<$choice>(v)?;
                    Ok(())
                }),
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
                get: |$m: &$model| i32::try_from($place).unwrap_or(i32::MAX),
                set: Some(|$m: &mut $model, v: i32| {
                    $place = v as usize;
                    Ok(())
                }),
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
                get: |$m: &$model| $value,
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
                get: |$m: &$model| $place.clone(),
                set: Some(|$m: &mut $model, v: &str| {
                    $place = $crate::networks::weights_name(v)?;
                    Ok(())
                }),
            },
            None
        )
    };
}

/// The value references of LuGre's parameters (sigma0, sigma1, sigma2) in every model
/// that has them ([`with_memory_law_parameters`]).
pub const LUGRE_PARAMETERS: [u32; 3] = [70, 71, 72];
/// The value references of rate-and-state's parameters (a, b, D_c, V_0, mu_0, the
/// evolution law).
pub const RATE_STATE_PARAMETERS: [u32; 6] = [80, 81, 82, 83, 84, 85];

/// A table with the parameters of the laws with state (`stickslip::friction::lugre`, `stickslip::friction::rate_and_state`)
/// between its rows `$head` and `$tail`: value references [`LUGRE_PARAMETERS`] and
/// [`RATE_STATE_PARAMETERS`], under the scene file's names. One declaration for every model
/// that has them; `$lugre` and `$rate_state` are the model's `LuGreParameters` and
/// `RateStateParameters`.
macro_rules! with_memory_law_parameters {
    ($law:literal, |$m:ident: $model:ty| $lugre:expr, $rate_state:expr;
        [$($head:expr),* $(,)?] [$($tail:expr),* $(,)?]) => {
        [
            $($head,)*
            $crate::declare::real_parameter!(
                $crate::declare::LUGRE_PARAMETERS[0],
                "friction.lugre.bristle_stiffness",
                Some("N/m"),
                concat!("LuGre bristle stiffness sigma0 (", $law, " = lugre)"),
                |$m: $model| $lugre.bristle_stiffness
            ),
            $crate::declare::real_parameter!(
                $crate::declare::LUGRE_PARAMETERS[1],
                "friction.lugre.bristle_damping",
                Some("N.s/m"),
                "LuGre bristle damping sigma1",
                |$m: $model| $lugre.bristle_damping
            ),
            $crate::declare::real_parameter!(
                $crate::declare::LUGRE_PARAMETERS[2],
                "friction.lugre.viscous_damping",
                Some("N.s/m"),
                "LuGre viscous damping sigma2",
                |$m: $model| $lugre.viscous_damping
            ),
            $crate::declare::real_parameter!(
                $crate::declare::RATE_STATE_PARAMETERS[0],
                "friction.rate_and_state.direct_effect",
                None,
                concat!("Rate-and-state direct effect a (", $law, " = rate-and-state)"),
                |$m: $model| $rate_state.direct_effect
            ),
            $crate::declare::real_parameter!(
                $crate::declare::RATE_STATE_PARAMETERS[1],
                "friction.rate_and_state.evolution_effect",
                None,
                "Rate-and-state evolution effect b",
                |$m: $model| $rate_state.evolution_effect
            ),
            $crate::declare::real_parameter!(
                $crate::declare::RATE_STATE_PARAMETERS[2],
                "friction.rate_and_state.characteristic_slip",
                Some("m"),
                "Rate-and-state characteristic slip D_c",
                |$m: $model| $rate_state.characteristic_slip
            ),
            $crate::declare::real_parameter!(
                $crate::declare::RATE_STATE_PARAMETERS[3],
                "friction.rate_and_state.reference_velocity",
                Some("m/s"),
                "Rate-and-state reference velocity V_0",
                |$m: $model| $rate_state.reference_velocity
            ),
            $crate::declare::real_parameter!(
                $crate::declare::RATE_STATE_PARAMETERS[4],
                "friction.rate_and_state.reference_coefficient",
                None,
                "Rate-and-state steady coefficient mu_0 at V_0",
                |$m: $model| $rate_state.reference_coefficient
            ),
            $crate::declare::choice_parameter!(
                $crate::declare::RATE_STATE_PARAMETERS[5],
                "friction.rate_and_state.state_evolution",
                ::stickslip::friction::rate_and_state::StateEvolution,
                "Rate-and-state evolution law of theta",
                |$m: $model| $rate_state.state_evolution
            ),
            $($tail,)*
        ]
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

pub(crate) use {
    choice_parameter, count_parameter, real_input, real_output, real_parameter, row,
    weights_parameter, with_memory_law_parameters,
};
