//! The LuGre law (Canudas de Wit, Olsson, Astrom, Lischinsky, IEEE Trans. Autom. Control
//! 40 (1995) 419): the contact as bristles of mean deflection z (m),
//!
//!   dz/dt = v - sigma0 |v| z / g(v),    F = sigma0 z + sigma1 dz/dt + sigma2 v,
//!
//! with g(v) (N) the steady sliding force of a memoryless law, here the scene's
//! exponential law g(v) = mu(|v|) F_n (paper, Eq. 6). At constant v, z relaxes to
//! sign(v) g(v) / sigma0 and F to g(v) sign(v) + sigma2 v; for small displacements from
//! rest (|v| z << g) dz/dt = v and F = sigma0 x: presliding is elastic.

use super::exponential::ExponentialLaw;
use super::kind::FrictionLawKind;
use super::law::FrictionLaw;
use super::parameters::ParameterProblem;
use super::registry::{LawBuild, LawDescription, LawParameter, LawTables, ParameterKind, Range};
use super::state::relaxation::Relaxation;
use super::state::{set_checked, ForceAtState, LawStep, StateError, StateVariable, StatefulLaw};
use crate::elementary::signum_or_zero;
use crate::jacobian::magnitude_slope;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// This law's state variable, listed in `super::state::STATE_VARIABLES` (defined
/// there, so that the list imports no law).
pub use super::state::BRISTLE_DEFLECTION;

const STATE: [StateVariable; 1] = [BRISTLE_DEFLECTION];

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

/// sigma0 (N/m). The bristles start undeflected (z = 0), so the initial force does not
/// depend on it.
pub const BRISTLE_STIFFNESS: LawParameter = LawParameter {
    name: "friction.lugre.bristle_stiffness",
    description: "LuGre bristle stiffness sigma0",
    kind: ParameterKind::Real {
        unit: Some("N/m"),
        range: Range::Positive,
    },
    default: 1e7,
    value_reference: 70,
    initial_force: false,
    initial_state: false,
};

/// sigma1 (N s/m).
pub const BRISTLE_DAMPING: LawParameter = LawParameter {
    name: "friction.lugre.bristle_damping",
    description: "LuGre bristle damping sigma1",
    kind: ParameterKind::Real {
        unit: Some("N.s/m"),
        range: Range::NonNegative,
    },
    default: 1e3,
    value_reference: 71,
    initial_force: true,
    initial_state: false,
};

/// sigma2 (N s/m).
pub const VISCOUS_DAMPING: LawParameter = LawParameter {
    name: "friction.lugre.viscous_damping",
    description: "LuGre viscous damping sigma2",
    kind: ParameterKind::Real {
        unit: Some("N.s/m"),
        range: Range::NonNegative,
    },
    default: 0.0,
    value_reference: 72,
    initial_force: true,
    initial_state: false,
};

/// LuGre in the registry: built from `[friction.lugre]` with g(v) the exponential law of
/// the friction coefficients.
pub static LAW: LawDescription = LawDescription {
    kind: FrictionLawKind::Lugre,
    build: LawBuild::Analytical(|coefficients, values| {
        Arc::new(LuGreLaw::new(
            LuGreParameters::from_values(values),
            ExponentialLaw::from(*coefficients),
        ))
    }),
    parameters: &[BRISTLE_STIFFNESS, BRISTLE_DAMPING, VISCOUS_DAMPING],
    joint_check: None,
    has_state: true,
    presliding: true,
    state_variables: &STATE,
    neural_friction_code: Some(3),
};

impl Default for LuGreParameters {
    fn default() -> Self {
        Self::from_values(&LAW.defaults())
    }
}

impl LuGreParameters {
    /// The parameters from their values in the order of [`LAW`]'s list.
    pub fn from_values(values: &[f64]) -> Self {
        Self {
            bristle_stiffness: values[0],
            bristle_damping: values[1],
            viscous_damping: values[2],
        }
    }

    /// The values in the order of [`LAW`]'s list.
    pub fn values(&self) -> [f64; 3] {
        [
            self.bristle_stiffness,
            self.bristle_damping,
            self.viscous_damping,
        ]
    }

    /// The parameters a friction section's tables hold (`Friction::laws`).
    pub fn of(tables: &LawTables) -> Self {
        Self::from_values(tables.values(FrictionLawKind::Lugre))
    }

    /// Writes these parameters into a friction section's tables.
    pub fn write_into(&self, tables: &mut LawTables) {
        for (parameter, value) in LAW.parameters.iter().zip(self.values()) {
            tables.set(parameter, value);
        }
    }

    /// The first field that is out of range.
    pub fn problem(&self) -> Option<ParameterProblem> {
        LAW.problem(&self.values())
    }
}

/// The LuGre law with its bristle deflection z (m), starting at z = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct LuGreLaw {
    parameters: LuGreParameters,
    /// g(v) = mu(|v|) F_n.
    steady: ExponentialLaw,
    state: [f64; 1],
}

/// The end of one step: z_n+1, dz/dt at t_n+1 and their derivatives with respect to v.
struct Step {
    deflection: f64,
    deflection_slope: f64,
    rate: f64,
    rate_slope: f64,
}

impl LuGreLaw {
    /// Panics if `parameters` are out of range (a checked scene never holds such).
    pub fn new(parameters: LuGreParameters, steady: ExponentialLaw) -> Self {
        assert!(parameters.problem().is_none(), "{:?}", parameters.problem());
        Self {
            parameters,
            steady,
            state: [0.0],
        }
    }

    pub fn parameters(&self) -> &LuGreParameters {
        &self.parameters
    }

    /// The exact step for v held: with c = sigma0 |v| / g(v) and s = c dt,
    /// z_n+1 = z_n exp(-s) + v dt P(s), P(s) = (1 - exp(-s)) / s, and the rate at the
    /// step's end dz/dt = v - c z_n+1. Where g <= 0 (no normal force) the bristles carry
    /// nothing: z = 0.
    fn advance(&self, step: LawStep) -> Step {
        let LawStep {
            dt,
            sliding_velocity: v,
            normal_force,
        } = step;
        let sigma0 = self.parameters.bristle_stiffness;
        let (mu, mu_slope) = self.steady.coefficient_and_slope(v);
        let (g, g_slope) = (mu * normal_force, mu_slope * normal_force);
        if g.is_nan() || g <= 0.0 {
            return Step {
                deflection: 0.0,
                deflection_slope: 0.0,
                rate: 0.0,
                rate_slope: 0.0,
            };
        }
        let speed = v.abs();
        let c = sigma0 * speed / g;
        // dc/dv = sigma0 sign(v) (g - |v| g') / g^2 (0 at v = 0, between its one-sided
        // values: only the slip solve's Newton step uses it).
        let c_slope = sigma0 * signum_or_zero(v) * (g - speed * g_slope) / (g * g);
        let r = Relaxation::at(c * dt);
        let z0 = self.state[0];
        let deflection = z0 * r.decay + v * dt * r.average;
        let deflection_slope =
            -z0 * r.decay * dt * c_slope + dt * r.average + v * dt * r.average_slope * dt * c_slope;
        Step {
            deflection,
            deflection_slope,
            rate: v - c * deflection,
            rate_slope: 1.0 - c_slope * deflection - c * deflection_slope,
        }
    }
}

impl FrictionLaw for LuGreLaw {
    fn name(&self) -> &str {
        "lugre"
    }

    /// The steady sliding force g(v) sign(v) + sigma2 v.
    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        self.sliding_force_and_slope(sliding_velocity, normal_force)
            .0
    }

    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        let (force, slope) = self
            .steady
            .sliding_force_and_slope(sliding_velocity, normal_force);
        let sigma2 = self.parameters.viscous_damping;
        (force + sigma2 * sliding_velocity, slope + sigma2)
    }

    fn as_stateful(&self) -> Option<&dyn StatefulLaw> {
        Some(self)
    }

    fn as_stateful_mut(&mut self) -> Option<&mut dyn StatefulLaw> {
        Some(self)
    }
}

impl StatefulLaw for LuGreLaw {
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
        self.state = [0.0];
    }

    /// z = F / sigma0, the bristle deflection that carries F at rest (dz/dt = 0 at
    /// v = 0), for |F| below the breakaway force g(0) = mu_s F_n; beyond it the bristles
    /// cannot hold F, and they start at g(0) / sigma0 in its direction.
    fn hold(&mut self, force: f64, normal_force: f64) {
        let limit = self.steady.coefficient(0.0) * normal_force;
        self.state[0] = force.clamp(-limit, limit) / self.parameters.bristle_stiffness;
    }

    /// F = sigma0 z_n+1 + sigma1 dz/dt(t_n+1) + sigma2 v.
    fn step_force_and_slope(&mut self, step: LawStep) -> (f64, f64) {
        let end = self.advance(step);
        let p = &self.parameters;
        (
            p.bristle_stiffness * end.deflection
                + p.bristle_damping * end.rate
                + p.viscous_damping * step.sliding_velocity,
            p.bristle_stiffness * end.deflection_slope
                + p.bristle_damping * end.rate_slope
                + p.viscous_damping,
        )
    }

    fn commit(&mut self, step: LawStep) {
        self.state[0] = self.advance(step).deflection;
    }

    /// F = sigma0 z + sigma1 (v - sigma0 z h(v)) + sigma2 v with h = |v| / g(v),
    /// g = mu(|v|) F_n and z the committed deflection. With u = |v| and ' = d/du:
    /// dh/dv = sign(v) (1/g - u g'/g^2), d2h/dv2 = -2 g'/g^2 - u g''/g^2 + 2 u g'^2/g^3
    /// (mu'' = -alpha mu' for the exponential law), dh/dF_n = -h / F_n. At v = 0, the
    /// kink of |v|, the v-derivatives are those of v > 0, as for every law
    /// (`crate::jacobian`): S(0) = sigma1 (1 - sigma0 z / g(0)) + sigma2, the limit
    /// v -> 0+ (d2h/dv2 is even, its formula at u = 0 that limit). Where g <= 0 the
    /// bristles carry nothing (as in the step): F = sigma2 v.
    fn force_at_state(&self, sliding_velocity: f64, normal_force: f64) -> ForceAtState {
        let p = &self.parameters;
        let (sigma0, sigma1, sigma2) = (p.bristle_stiffness, p.bristle_damping, p.viscous_damping);
        let v = sliding_velocity;
        let (mu, mu_slope) = self.steady.coefficient_and_slope(v);
        let g = mu * normal_force;
        if g.is_nan() || g <= 0.0 {
            return ForceAtState {
                force: sigma2 * v,
                slope: sigma2,
                force_gradient: [sigma2, 0.0],
                slope_gradient: [0.0, 0.0],
            };
        }
        let (g1, g2) = (
            mu_slope * normal_force,
            -self.steady.decay * mu_slope * normal_force,
        );
        let u = v.abs();
        let h = u / g;
        let h_v = magnitude_slope(v) * (1.0 / g - u * g1 / (g * g));
        let h_vv = -2.0 * g1 / (g * g) - u * g2 / (g * g) + 2.0 * u * g1 * g1 / (g * g * g);
        // The bristle force's coefficient in the rate term: sigma1 sigma0 z.
        let damped = sigma1 * sigma0 * self.state[0];
        let slope = sigma1 * (1.0 - sigma0 * self.state[0] * h_v) + sigma2;
        ForceAtState {
            force: sigma0 * self.state[0] + sigma1 * (v - sigma0 * self.state[0] * h) + sigma2 * v,
            slope,
            force_gradient: [slope, damped * h / normal_force],
            slope_gradient: [-damped * h_vv, damped * h_v / normal_force],
        }
    }
}
