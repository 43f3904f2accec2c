//! The parameters of the laws with state as the scene holds them (`[friction.lugre]`,
//! `[friction.rate_and_state]`), with their checks: plain data that the scene, the FMU
//! and the command line read, apart from the laws themselves (`lugre`, `rate_state`).
//! Every caller refuses a parameter through [`ParameterProblem`], so that the scene
//! check, the command line and both FMUs give the same words.

use crate::elementary;
use crate::short::Short;
use serde::{Deserialize, Serialize};
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
type Check = (&'static str, f64, bool, &'static str);

/// The first check whose value is not finite or out of range.
fn first_problem<const N: usize>(checks: [Check; N]) -> Option<ParameterProblem> {
    checks
        .into_iter()
        .find(|(_, value, ok, _)| !(value.is_finite() && *ok))
        .map(|(field, value, _, requirement)| ParameterProblem {
            field,
            value,
            requirement: requirement.into(),
        })
}

/// The largest ln E, E = exp(mu_0 / a) / (2 V_0) (s/m, V_0 in m/s), that a
/// rate-and-state law regularised as a asinh(v E ...) (Rice & Ben-Zion 1996) may have at
/// its initial state. Its slope at rest there is dF/dv(0) = F_n a E (N s/m): with
/// ln E <= 700 it is at most 1.0e304 a F_n, finite for a F_n below 1.8e4 N, while
/// beyond ln E = 709.8 E itself overflows and the slope is infinite. So this is the
/// range in which the law's outputs are finite numbers, not a cap on the law. (Measured
/// on the paper scene, modal, 1.2 s, aging law: every one of the 12 000 slip solves
/// converges at a = 7.2e-4, ln E = 700.7; at a = 7e-4, where E overflows, 54 do not,
/// and at a = 1e-6 4327.) The learned law with memory caps its ln E at the same value.
pub const LARGEST_LOG_SCALE: f64 = 700.0;

/// The regularisation check of a rate-and-state law with direct effect `direct_effect`
/// (a, 1), reference coefficient `reference_coefficient` (mu_0, 1) and reference
/// velocity `reference_velocity` (V_0, m/s), all finite and a, V_0 > 0 (checked
/// before): ln E = mu_0 / a - ln(2 V_0) <= [`LARGEST_LOG_SCALE`], the parameter at fault
/// named by `fields` (the names of a and V_0 where the caller holds them). a is named
/// with the smallest a that passes, mu_0 / (700 + ln(2 V_0)); V_0 where no a would do.
/// The bounds shown are raised by 1e-6 relative, so that their seven digits pass.
pub fn regularisation_problem(
    direct_effect: f64,
    reference_coefficient: f64,
    reference_velocity: f64,
    fields: [&'static str; 2],
) -> Option<ParameterProblem> {
    let (a, mu_0, v_0) = (direct_effect, reference_coefficient, reference_velocity);
    let log_two_v0 = elementary::ln(2.0 * v_0);
    if mu_0 / a - log_two_v0 <= LARGEST_LOG_SCALE {
        return None;
    }
    let slope =
        "the slope at v = 0, F_n a exp(mu_0 / a) / (2 V_0), exceeds 1e304 a F_n and overflows";
    let room = LARGEST_LOG_SCALE + log_two_v0;
    Some(if mu_0 > 0.0 && room > 0.0 {
        ParameterProblem {
            field: fields[0],
            value: a,
            requirement: format!(
                ">= {} (1) with mu_0 = {} and V_0 = {} m/s: below it {slope}",
                Short(mu_0 / room * (1.0 + 1e-6)),
                Short(mu_0),
                Short(v_0)
            ),
        }
    } else {
        ParameterProblem {
            field: fields[1],
            value: v_0,
            requirement: format!(
                ">= {} m/s with a = {} and mu_0 = {}: below it {slope}",
                Short(0.5 * elementary::exp(mu_0 / a - LARGEST_LOG_SCALE) * (1.0 + 1e-6)),
                Short(a),
                Short(mu_0)
            ),
        }
    })
}

/// The scene's `[friction.lugre]` table.
///
/// Defaults for the paper scene (tip stiffness 3 EI / L^3 = 6.25e3 N/m, first-mode tip
/// mass M / 4 = 5 kg, mu_s F_n = 50 N): sigma0 = 1e7 N/m is 1600 times the tip
/// stiffness, so that the presliding deflection at breakaway, mu_s F_n / sigma0 = 5 um,
/// is 0.06 % of the 8 mm the tip deflects in stick; sigma1 = 1e3 N s/m damps the bristle
/// mode against the tip mass (sqrt(sigma0 / m) ~ 1.4e3 rad/s) at about 7 % of critical;
/// sigma2 = 0 because the exponential law g already carries all of the paper's velocity
/// dependence. (The run converges to the memoryless one as sigma0 grows with sigma1 =
/// sigma2 = 0: docs/friction-with-memory.md.)
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LuGreParameters {
    /// sigma0 (N/m), > 0.
    pub bristle_stiffness: f64,
    /// sigma1 (N s/m), >= 0.
    pub bristle_damping: f64,
    /// sigma2 (N s/m), >= 0.
    pub viscous_damping: f64,
}

impl Default for LuGreParameters {
    fn default() -> Self {
        Self {
            bristle_stiffness: 1e7,
            bristle_damping: 1e3,
            viscous_damping: 0.0,
        }
    }
}

impl LuGreParameters {
    /// The first field that is out of range.
    pub fn problem(&self) -> Option<ParameterProblem> {
        let checks = [
            (
                "friction.lugre.bristle_stiffness",
                self.bristle_stiffness,
                self.bristle_stiffness > 0.0,
                "finite and > 0 (N/m)",
            ),
            (
                "friction.lugre.bristle_damping",
                self.bristle_damping,
                self.bristle_damping >= 0.0,
                "finite and >= 0 (N s/m)",
            ),
            (
                "friction.lugre.viscous_damping",
                self.viscous_damping,
                self.viscous_damping >= 0.0,
                "finite and >= 0 (N s/m)",
            ),
        ];
        first_problem(checks)
    }
}

crate::choice! {
    /// How the rate-and-state law's state theta evolves.
    #[choice(name = "StateEvolution", description = "Evolution law of the rate-and-state state theta")]
    #[derive(Default)]
    pub enum StateEvolution {
        /// Dieterich's aging law: theta grows as time in stick.
        #[default]
        Aging = "aging": "d theta/dt = 1 - V theta / D_c (Dieterich): theta heals in stick",
        /// Ruina's slip law: theta changes only with slip.
        Slip = "slip": "d theta/dt = -(V theta / D_c) ln(V theta / D_c) (Ruina): no healing without slip",
    }
}

/// The scene's `[friction.rate_and_state]` table.
///
/// Defaults for the paper scene (F_n = 100 N, belt speed 0.02 m/s, first-mode tip
/// stiffness omega_1^2 M / 4 = 6.44e3 N/m and mass M / 4 = 5 kg): a = 0.01 and b = 0.015 are laboratory
/// values for rock and metals (b - a = 0.005, velocity weakening); mu_0 = 0.5 at
/// V_0 = 1e-3 m/s puts mu_ss at the belt speed at 0.485, beside the exponential law's
/// 0.471 there; D_c = 1e-5 m lies well below the critical slip of the paper beam
/// (4.35e-4 m, docs/friction-with-memory.md), so that the default scene stick-slips.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RateStateParameters {
    /// a (1), > 0: the direct effect.
    pub direct_effect: f64,
    /// b (1), >= 0: the evolution effect.
    pub evolution_effect: f64,
    /// D_c (m), > 0.
    pub characteristic_slip: f64,
    /// V_0 (m/s), > 0.
    pub reference_velocity: f64,
    /// mu_0 (1), >= 0: steady-state coefficient at V_0.
    pub reference_coefficient: f64,
    pub state_evolution: StateEvolution,
}

impl Default for RateStateParameters {
    fn default() -> Self {
        Self {
            direct_effect: 0.01,
            evolution_effect: 0.015,
            characteristic_slip: 1e-5,
            reference_velocity: 1e-3,
            reference_coefficient: 0.5,
            state_evolution: StateEvolution::Aging,
        }
    }
}

impl RateStateParameters {
    /// The first field that is out of range: each on its own, then a, mu_0 and V_0
    /// together, whose law must have finite outputs ([`regularisation_problem`]).
    pub fn problem(&self) -> Option<ParameterProblem> {
        let checks = [
            (
                "friction.rate_and_state.direct_effect",
                self.direct_effect,
                self.direct_effect > 0.0,
                "finite and > 0 (1)",
            ),
            (
                "friction.rate_and_state.evolution_effect",
                self.evolution_effect,
                self.evolution_effect >= 0.0,
                "finite and >= 0 (1)",
            ),
            (
                "friction.rate_and_state.characteristic_slip",
                self.characteristic_slip,
                self.characteristic_slip > 0.0,
                "finite and > 0 (m)",
            ),
            (
                "friction.rate_and_state.reference_velocity",
                self.reference_velocity,
                self.reference_velocity > 0.0,
                "finite and > 0 (m/s)",
            ),
            (
                "friction.rate_and_state.reference_coefficient",
                self.reference_coefficient,
                self.reference_coefficient >= 0.0,
                "finite and >= 0 (1)",
            ),
        ];
        first_problem(checks).or_else(|| {
            regularisation_problem(
                self.direct_effect,
                self.reference_coefficient,
                self.reference_velocity,
                [
                    "friction.rate_and_state.direct_effect",
                    "friction.rate_and_state.reference_velocity",
                ],
            )
        })
    }

    /// The steady-state coefficient mu_ss(V) = mu_0 + (a - b) ln(V / V_0) of the
    /// classical (unregularised) law, V > 0 (m/s).
    pub fn steady_coefficient(&self, speed: f64) -> f64 {
        self.reference_coefficient
            + (self.direct_effect - self.evolution_effect)
                * elementary::ln(speed / self.reference_velocity)
    }
}
