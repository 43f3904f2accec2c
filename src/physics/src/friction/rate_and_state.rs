//! Rate-and-state friction (Dieterich, J. Geophys. Res. 84 (1979) 2161; Ruina,
//! J. Geophys. Res. 88 (1983) 10359) with the state theta (s), in the form regularised
//! at V = 0 of Rice & Ben-Zion (PNAS 93 (1996) 3811) and Lapusta, Rice, Ben-Zion, Zheng
//! (J. Geophys. Res. 105 (2000) 23765, Eq. 3):
//!
//!   mu(v, theta) = a asinh( v / (2 V_0) exp( (mu_0 + b ln(V_0 theta / D_c)) / a ) ),
//!
//! odd and smooth in v, so that sticking (v ~ 0) and reversal are defined. Where
//! v / (2 V_0) exp(..) >> 1 it is the classical mu_0 + a ln(v / V_0) + b ln(V_0 theta /
//! D_c) to O(exp(-2 mu / a)). The friction force is F = mu F_n (N). The state evolves by
//!
//! - the aging law (Dieterich): d theta / dt = 1 - V theta / D_c,
//! - the slip law (Ruina): d theta / dt = -(V theta / D_c) ln(V theta / D_c),
//!
//! with V = |v|. Both have the steady state theta_ss = D_c / V, where
//! mu_ss = mu_0 + (a - b) ln(V / V_0): velocity weakening for b > a.

use super::kind::FrictionLawKind;
use super::law::FrictionLaw;
use super::parameters::ParameterProblem;
use super::registry::{LawBuild, LawDescription, LawParameter, LawTables, ParameterKind, Range};
use super::state::relaxation::Relaxation;
use super::state::{set_checked, ForceAtState, LawStep, StateError, StateVariable, StatefulLaw};
use crate::choice::{Choice, ChoiceType};
use crate::elementary;
use crate::short::Short;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// This law's state variable, listed in `super::state::STATE_VARIABLES` (defined
/// there, so that the list imports no law).
pub use super::state::STATE_THETA;

const STATE: [StateVariable; 1] = [STATE_THETA];

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

const fn real(
    name: &'static str,
    description: &'static str,
    unit: Option<&'static str>,
    range: Range,
    default: f64,
    value_reference: u32,
    [initial_force, initial_state]: [bool; 2],
) -> LawParameter {
    LawParameter {
        name,
        description,
        kind: ParameterKind::Real { unit, range },
        default,
        value_reference,
        initial_force,
        initial_state,
    }
}

// Which parameters reach the initial force and state: theta starts at D_c / V_0, where
// b ln(V_0 theta / D_c) = 0 (to rounding), so b, D_c and the evolution law act only
// through the steps; a, V_0 and mu_0 shape the force at once.

/// a (1).
pub const DIRECT_EFFECT: LawParameter = real(
    "friction.rate_and_state.direct_effect",
    "Rate-and-state direct effect a",
    None,
    Range::Positive,
    0.01,
    80,
    [true, false],
);
/// b (1).
pub const EVOLUTION_EFFECT: LawParameter = real(
    "friction.rate_and_state.evolution_effect",
    "Rate-and-state evolution effect b",
    None,
    Range::NonNegative,
    0.015,
    81,
    [false, false],
);
/// D_c (m).
pub const CHARACTERISTIC_SLIP: LawParameter = real(
    "friction.rate_and_state.characteristic_slip",
    "Rate-and-state characteristic slip D_c",
    Some("m"),
    Range::Positive,
    1e-5,
    82,
    [false, true],
);
/// V_0 (m/s).
pub const REFERENCE_VELOCITY: LawParameter = real(
    "friction.rate_and_state.reference_velocity",
    "Rate-and-state reference velocity V_0",
    Some("m/s"),
    Range::Positive,
    1e-3,
    83,
    [true, true],
);
/// mu_0 (1).
pub const REFERENCE_COEFFICIENT: LawParameter = real(
    "friction.rate_and_state.reference_coefficient",
    "Rate-and-state steady coefficient mu_0 at V_0",
    None,
    Range::NonNegative,
    0.5,
    84,
    [true, false],
);
/// The evolution law of theta.
pub const STATE_EVOLUTION: LawParameter = LawParameter {
    name: "friction.rate_and_state.state_evolution",
    description: "Rate-and-state evolution law of theta",
    kind: ParameterKind::Choice(ChoiceType::of::<StateEvolution>()),
    default: 1.0,
    value_reference: 85,
    initial_force: false,
    initial_state: false,
};

/// Rate-and-state in the registry: built from `[friction.rate_and_state]`; a, mu_0 and
/// V_0 together must keep the law's outputs finite ([`regularisation_problem`]).
pub static LAW: LawDescription = LawDescription {
    kind: FrictionLawKind::RateAndState,
    build: LawBuild::Analytical(|_, values| {
        Arc::new(RateStateLaw::new(RateStateParameters::from_values(values)))
    }),
    parameters: &[
        DIRECT_EFFECT,
        EVOLUTION_EFFECT,
        CHARACTERISTIC_SLIP,
        REFERENCE_VELOCITY,
        REFERENCE_COEFFICIENT,
        STATE_EVOLUTION,
    ],
    joint_check: Some(|values| {
        regularisation_problem(
            values[0],
            values[4],
            values[3],
            [DIRECT_EFFECT.name, REFERENCE_VELOCITY.name],
        )
    }),
    has_state: true,
    presliding: false,
    state_variables: &STATE,
    neural_friction_code: Some(4),
};

impl Default for RateStateParameters {
    fn default() -> Self {
        Self::from_values(&LAW.defaults())
    }
}

impl RateStateParameters {
    /// The parameters from their values in the order of [`LAW`]'s list (the evolution
    /// law by its code; an unknown code reads as the default, which the check refuses
    /// before any law is built).
    pub fn from_values(values: &[f64]) -> Self {
        Self {
            direct_effect: values[0],
            evolution_effect: values[1],
            characteristic_slip: values[2],
            reference_velocity: values[3],
            reference_coefficient: values[4],
            state_evolution: StateEvolution::from_code(values[5] as i32).unwrap_or_default(),
        }
    }

    /// The values in the order of [`LAW`]'s list.
    pub fn values(&self) -> [f64; 6] {
        [
            self.direct_effect,
            self.evolution_effect,
            self.characteristic_slip,
            self.reference_velocity,
            self.reference_coefficient,
            f64::from(self.state_evolution.code()),
        ]
    }

    /// The parameters a friction section's tables hold (`Friction::laws`).
    pub fn of(tables: &LawTables) -> Self {
        Self::from_values(tables.values(FrictionLawKind::RateAndState))
    }

    /// Writes these parameters into a friction section's tables.
    pub fn write_into(&self, tables: &mut LawTables) {
        for (parameter, value) in LAW.parameters.iter().zip(self.values()) {
            tables.set(parameter, value);
        }
    }

    /// The first field that is out of range: each on its own, then a, mu_0 and V_0
    /// together, whose law must have finite outputs ([`regularisation_problem`]).
    pub fn problem(&self) -> Option<ParameterProblem> {
        LAW.problem(&self.values())
    }

    /// The steady-state coefficient mu_ss(V) = mu_0 + (a - b) ln(V / V_0) of the
    /// classical (unregularised) law, V > 0 (m/s).
    pub fn steady_coefficient(&self, speed: f64) -> f64 {
        self.reference_coefficient
            + (self.direct_effect - self.evolution_effect)
                * elementary::ln(speed / self.reference_velocity)
    }
}

/// The rate-and-state law with its state theta (s), starting at theta = D_c / V_0
/// (steady sliding at the reference velocity).
#[derive(Clone, Debug, PartialEq)]
pub struct RateStateLaw {
    parameters: RateStateParameters,
    state: [f64; 1],
}

/// ln theta at the end of a step and its derivative with respect to V = |v| (s/m).
struct Step {
    log_theta: f64,
    log_theta_slope: f64,
}

/// ln(w) above which asinh(w) = ln(2 w) and w / sqrt(1 + w^2) = 1 in f64 (the
/// neglected terms are below w^-2 = e^-40 ~ 4e-18).
const LARGE_LOG: f64 = 20.0;

impl RateStateLaw {
    /// Panics if `parameters` are out of range (a checked scene never holds such).
    pub fn new(parameters: RateStateParameters) -> Self {
        assert!(parameters.problem().is_none(), "{:?}", parameters.problem());
        let theta = parameters.characteristic_slip / parameters.reference_velocity;
        Self {
            parameters,
            state: [theta],
        }
    }

    pub fn parameters(&self) -> &RateStateParameters {
        &self.parameters
    }

    /// The exact step of the evolution law for V = |v| held over dt (finite for every
    /// finite v: at V = 5e-324 m/s the slip law's V theta / D_c underflows, so its
    /// logarithm is taken as a sum of logarithms there, `log_of_ratio`):
    /// - aging: theta_n+1 = theta_n exp(-s) + dt P(s), s = V dt / D_c;
    /// - slip: y = ln(V theta / D_c) obeys dy/dt = -(V / D_c) y, so
    ///   ln theta_n+1 = ln theta_n + y_n (exp(-s) - 1), and at V = 0 theta stays.
    fn advance(&self, dt: f64, speed: f64) -> Step {
        let d_c = self.parameters.characteristic_slip;
        let theta = self.state[0];
        let r = Relaxation::at(speed * dt / d_c);
        match self.parameters.state_evolution {
            StateEvolution::Aging => {
                let next = theta * r.decay + dt * r.average;
                // d/dV of theta_n exp(-s) + dt P(s) with ds/dV = dt / D_c.
                let slope = dt / d_c * (-theta * r.decay + dt * r.average_slope);
                Step {
                    log_theta: elementary::ln(next),
                    log_theta_slope: slope / next,
                }
            }
            StateEvolution::Slip if speed > 0.0 => {
                let y = log_of_ratio(speed * theta, d_c, || {
                    elementary::ln(speed) + elementary::ln(theta) - elementary::ln(d_c)
                });
                // (exp(-s) - 1) = -s P(s); d/dV [y (exp(-s) - 1)] with dy/dV = 1 / V:
                // -s P / V - y exp(-s) dt / D_c = -(dt / D_c) (P + y exp(-s)).
                Step {
                    log_theta: elementary::ln(theta) - y * speed * dt / d_c * r.average,
                    log_theta_slope: -(dt / d_c) * (r.average + y * r.decay),
                }
            }
            // V = 0: no slip, no change; the slope's log singularity meets a force
            // derivative proportional to v, and their product tends to 0.
            StateEvolution::Slip => Step {
                log_theta: elementary::ln(theta),
                log_theta_slope: 0.0,
            },
        }
    }

    /// mu(v, theta) (1), d mu / dv (s/m), d mu / d ln theta (1) and d2 mu / dv2 (s^2/m^2),
    /// from ln theta.
    fn coefficient(&self, v: f64, log_theta: f64) -> (f64, f64, f64, f64) {
        let p = &self.parameters;
        let a = p.direct_effect;
        // Psi / a with Psi = mu_0 + b ln(V_0 theta / D_c).
        let exponent = (p.reference_coefficient
            + p.evolution_effect
                * (log_theta + elementary::ln(p.reference_velocity / p.characteristic_slip)))
            / a;
        let sign = v.signum();
        let speed = v.abs();
        // w = v K with K = exp(Psi / a) / (2 V_0); ln |w|:
        let log_w = elementary::ln(speed) - elementary::ln(2.0 * p.reference_velocity) + exponent;
        if log_w > LARGE_LOG {
            // asinh|w| = ln 2|w|, d asinh / dv = 1 / |v|, w / sqrt(1 + w^2) = sign.
            let mu = a * (log_w + std::f64::consts::LN_2);
            (
                sign * mu,
                a / speed,
                sign * p.evolution_effect,
                -sign * a / (speed * speed),
            )
        } else {
            let w = sign * elementary::exp(log_w);
            let root = (1.0 + w * w).sqrt();
            let k = elementary::exp(exponent - elementary::ln(2.0 * p.reference_velocity));
            let mu_v = a * k / root;
            (
                a * elementary::asinh(w),
                mu_v,
                p.evolution_effect * w / root,
                // d/dv of a K (1 + w^2)^(-1/2) with dw/dv = K.
                -mu_v * w * k / (root * root),
            )
        }
    }
}

/// ln(numerator / denominator), from the quotient where it and the numerator are normal
/// f64 (the same bits as before for every ordinary velocity), else from `logs`, the same
/// logarithm as a sum of logarithms: a product or quotient that underflows to a
/// subnormal or 0 (V = 5e-324 m/s gave ln 0 = -inf and an infinite state) or overflows
/// has a finite logarithm. Shared with the learned law's slip step.
pub(crate) fn log_of_ratio(numerator: f64, denominator: f64, logs: impl Fn() -> f64) -> f64 {
    let ratio = numerator / denominator;
    if numerator.is_normal() && ratio.is_normal() {
        elementary::ln(ratio)
    } else {
        logs()
    }
}

impl FrictionLaw for RateStateLaw {
    fn name(&self) -> &str {
        "rate-and-state"
    }

    /// The steady sliding force mu(v, D_c / |v|) F_n (0 at v = 0, where theta_ss is
    /// unbounded).
    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        self.sliding_force_and_slope(sliding_velocity, normal_force)
            .0
    }

    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        if sliding_velocity == 0.0 {
            return (0.0, 0.0);
        }
        let speed = sliding_velocity.abs();
        let log_theta = elementary::ln(self.parameters.characteristic_slip / speed);
        let (mu, mu_v, mu_log_theta, _) = self.coefficient(sliding_velocity, log_theta);
        // d ln theta_ss / dv = -1 / v.
        (
            mu * normal_force,
            (mu_v - mu_log_theta / sliding_velocity) * normal_force,
        )
    }

    fn as_stateful(&self) -> Option<&dyn StatefulLaw> {
        Some(self)
    }

    fn as_stateful_mut(&mut self) -> Option<&mut dyn StatefulLaw> {
        Some(self)
    }
}

impl StatefulLaw for RateStateLaw {
    fn state_variables(&self) -> &[StateVariable] {
        &STATE
    }

    fn state(&self) -> &[f64] {
        &self.state
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), StateError> {
        set_checked(&STATE, &mut self.state, state)
    }

    fn reset(&mut self) {
        self.state = [self.parameters.characteristic_slip / self.parameters.reference_velocity];
    }

    /// F = mu(v, theta_n+1(v)) F_n; dF/dv = (d mu/dv + d mu/d ln theta
    /// d ln theta_n+1/dV sign(v)) F_n.
    fn step_force_and_slope(&mut self, step: LawStep) -> (f64, f64) {
        let v = step.sliding_velocity;
        let end = self.advance(step.dt, v.abs());
        let (mu, mu_v, mu_log_theta, _) = self.coefficient(v, end.log_theta);
        let sign = if v > 0.0 {
            1.0
        } else if v < 0.0 {
            -1.0
        } else {
            0.0
        };
        (
            mu * step.normal_force,
            (mu_v + mu_log_theta * end.log_theta_slope * sign) * step.normal_force,
        )
    }

    fn commit(&mut self, step: LawStep) {
        self.state[0] =
            elementary::exp(self.advance(step.dt, step.sliding_velocity.abs()).log_theta);
    }

    /// F = mu(v, theta) F_n at the committed theta: dF/dv = mu_v F_n, dF/dF_n = mu,
    /// dS/dv = mu_vv F_n, dS/dF_n = mu_v (`coefficient`).
    fn force_at_state(&self, sliding_velocity: f64, normal_force: f64) -> ForceAtState {
        let v = sliding_velocity;
        let (mu, mu_v, _, mu_vv) = self.coefficient(v, elementary::ln(self.state[0]));
        ForceAtState {
            force: mu * normal_force,
            slope: mu_v * normal_force,
            force_gradient: [mu_v * normal_force, mu],
            slope_gradient: [mu_vv * normal_force, mu_v],
        }
    }
}
