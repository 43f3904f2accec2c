//! The learned state-variable friction law: rate-and-state friction whose direct
//! effect a, evolution effect b, characteristic slip D_c and reference coefficient mu_0
//! are fitted to force records, plus a small network correction of the friction level:
//!
//! ```text
//! F = F_n a asinh( v / (2 V_0) exp(Omega / a) ),   Omega = mu_0 + b psi + N(psi, F_n)
//! d theta / dt = 1 - |v| theta / D_c,               psi = ln(theta V_0 / D_c)
//!   (aging law; or the slip law -(|v| theta / D_c) ln(|v| theta / D_c))
//! ```
//!
//! (`regularised`, `evolution`, `correction`). V_0 is fixed (it only shifts mu_0:
//! mu_0 - a ln V_0 is what the data determine). The evolution law is a choice of the
//! file, not trained. The state is advanced by `evolution::step`,
//! implicit in the step's end velocity, so a contact's slip solve gets the force after
//! the step and its exact total slope dF/dv_{n+1} (`LearnedStateLaw::after_step`).
//!
//! Why this form rather than free networks for dz/dt and F: a free state is defined
//! only up to a change of variables, so nothing in a trained free network is "the decay
//! length" or "the direct effect" (the quantities a tribologist reads off a velocity
//! step and issue 24 asks to reproduce), and a free evolution network must be trained
//! through long, stiff histories (stick ages theta by decades) with no guarantee of a
//! stable steady state. The structured part keeps both by construction; the network
//! may correct what the aging law does not capture (load dependence of the friction
//! level, a state dependence that is not logarithmic).

use serde::{Deserialize, Serialize};

use super::correction::Correction;
use super::evolution::{self, StateEvolution, StateStep};
use super::regularised;

/// The structured parameters (the rate-and-state names of issue 24).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateLawParameters {
    /// mu_0 (1).
    pub reference_coefficient: f64,
    /// V_0 (m/s), > 0; not trained.
    pub reference_velocity: f64,
    /// a (1), > 0.
    pub direct_effect: f64,
    /// b (1).
    pub evolution_effect: f64,
    /// D_c (m), > 0.
    pub characteristic_slip: f64,
    /// How the state evolves; a file without it (format version 1 before the slip law)
    /// is aging.
    #[serde(default)]
    pub state_evolution: StateEvolution,
}

/// The law: structured parameters and an optional correction network.
#[derive(Clone, Debug, PartialEq)]
pub struct LearnedStateLaw {
    pub parameters: StateLawParameters,
    pub correction: Option<Correction>,
}

/// The force at a given state, with its partial derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateForce {
    /// F (N).
    pub force: f64,
    /// dF/dv at fixed state (N s/m).
    pub d_velocity: f64,
    /// dF/d psi (N).
    pub d_state: f64,
}

/// The state and force at the end of a step, with the total slope the slip solve needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepForce {
    /// psi_{n+1}.
    pub state: f64,
    pub force: f64,
    /// dF/dv_{n+1} including the state's dependence on v_{n+1} (N s/m).
    pub slope: f64,
}

/// Trainable parameters before the correction's: mu_0, ln a, b, ln D_c.
pub const STRUCTURED: usize = 4;
/// Index of ln D_c in the flat parameters: the only one the state depends on.
pub const LOG_SLIP: usize = 3;

impl LearnedStateLaw {
    /// The steady state at sliding speed `speed` (m/s, > 0): psi_ss = ln(V_0 / V).
    pub fn steady_state(&self, speed: f64) -> f64 {
        evolution::steady_state(speed, self.parameters.reference_velocity)
    }

    /// The state after a step of `step` s ending at sliding velocity `velocity` (m/s).
    pub fn step_state(&self, state: f64, velocity: f64, step: f64) -> StateStep {
        let p = &self.parameters;
        evolution::step(
            p.state_evolution,
            state,
            velocity,
            step,
            p.characteristic_slip,
            p.reference_velocity,
        )
    }

    /// The friction level Omega and its derivatives (d/dpsi, d/dF_n); with `gradient`,
    /// adds `weight` dOmega/dp to it (flat layout).
    fn level(
        &self,
        state: f64,
        normal_force: f64,
        gradient: Option<(&mut [f64], f64)>,
    ) -> (f64, f64, f64) {
        let p = &self.parameters;
        let mut level = p.reference_coefficient + p.evolution_effect * state;
        let (mut d_state, mut d_normal) = (p.evolution_effect, 0.0);
        let mut gradient = gradient;
        if let Some((g, weight)) = gradient.as_mut() {
            g[0] += *weight;
            g[2] += *weight * state;
        }
        if let Some(net) = &self.correction {
            let n = net.evaluate(
                state,
                normal_force,
                gradient.map(|(g, w)| (&mut g[STRUCTURED..], w)),
            );
            level += n.value;
            d_state += n.d_state;
            d_normal += n.d_normal_force;
        }
        (level, d_state, d_normal)
    }

    /// The regularised force at (psi, v, F_n) with the level Omega and its derivatives
    /// d Omega / d psi and d Omega / d F_n.
    fn regularised(
        &self,
        state: f64,
        velocity: f64,
        normal_force: f64,
    ) -> (regularised::RegularisedForce, f64, f64, f64) {
        let p = &self.parameters;
        let (level, d_state, d_normal) = self.level(state, normal_force, None);
        let f = regularised::force(
            velocity,
            normal_force,
            level,
            p.direct_effect,
            p.reference_velocity,
        );
        (f, level, d_state, d_normal)
    }

    /// F at state `state`, velocity `velocity` (m/s), normal force `normal_force` (N).
    pub fn force(&self, state: f64, velocity: f64, normal_force: f64) -> StateForce {
        self.force_with_gradient(state, velocity, normal_force, None)
    }

    /// As [`LearnedStateLaw::force`]; with `gradient`, adds `weight` dF/dp at fixed state
    /// (flat layout: mu_0, ln a, b, ln D_c, the correction's) to it.
    pub fn force_with_gradient(
        &self,
        state: f64,
        velocity: f64,
        normal_force: f64,
        gradient: Option<(&mut [f64], f64)>,
    ) -> StateForce {
        let p = &self.parameters;
        let (f, _, d_level_state, _) = self.regularised(state, velocity, normal_force);
        if let Some((g, weight)) = gradient {
            // dF/dp = dF/dOmega dOmega/dp, and d ln a through a.
            self.level(state, normal_force, Some((g, weight * f.d_level)));
            g[1] += weight * f.d_direct * p.direct_effect;
        }
        StateForce {
            force: f.force,
            d_velocity: f.d_velocity,
            d_state: f.d_level * d_level_state,
        }
    }

    /// The force and its slope S = dF/dv at fixed state, with their gradients over
    /// (v, F_n) (`crate::jacobian::LawJacobian`): what an FMU's directional derivatives
    /// at a communication point are, where the state is the committed one. With
    /// S = F_n a / sqrt(1/E^2 + v^2) and ln E = Omega / a - ln(2 V_0):
    /// dS/dv = -S v / q, dS/dOmega = S E^-2 / (a q), q = 1/E^2 + v^2.
    pub fn jacobian(
        &self,
        state: f64,
        velocity: f64,
        normal_force: f64,
    ) -> crate::jacobian::LawJacobian {
        let p = &self.parameters;
        let (f, level, _, d_level_normal) = self.regularised(state, velocity, normal_force);
        let inverse = regularised::inverse_scale(level, p.direct_effect, p.reference_velocity);
        let q = inverse * inverse + velocity * velocity;
        let slope = f.d_velocity;
        // v / q and 1/(E^2 q) through the root where q is not a normal f64 (ln E > 354:
        // at v = 0 q was 0 and dS/dv NaN), the plain formulas (same bits) elsewhere.
        let (slope_velocity, slope_level) = if q.is_normal() {
            (
                -slope * velocity / q,
                slope * inverse * inverse / (p.direct_effect * q),
            )
        } else {
            let root = regularised::root_sum_of_squares(inverse, velocity);
            let (v_share, inverse_share) = (velocity / root, inverse / root);
            (
                -slope * v_share / root,
                slope * inverse_share * inverse_share / p.direct_effect,
            )
        };
        let force_normal = if normal_force != 0.0 {
            f.force / normal_force
        } else {
            0.0
        };
        let slope_normal = if normal_force != 0.0 {
            slope / normal_force
        } else {
            0.0
        };
        crate::jacobian::LawJacobian {
            force: f.force,
            slope,
            force_gradient: vec![slope, force_normal + f.d_level * d_level_normal],
            slope_gradient: vec![slope_velocity, slope_normal + slope_level * d_level_normal],
        }
    }

    /// One step from state `state` over `step` s to velocity `velocity`: the new state,
    /// the force there and dF/dv_{n+1} = dF/dv + dF/dpsi dpsi_{n+1}/dv_{n+1}.
    pub fn after_step(&self, state: f64, velocity: f64, normal_force: f64, step: f64) -> StepForce {
        let next = self.step_state(state, velocity, step);
        let f = self.force(next.state, velocity, normal_force);
        StepForce {
            state: next.state,
            force: f.force,
            slope: f.d_velocity + f.d_state * next.d_velocity,
        }
    }

    /// The trainable parameters, flat: mu_0, ln a, b, ln D_c, then the correction's.
    pub fn trainable(&self) -> Vec<f64> {
        let p = &self.parameters;
        let mut x = vec![
            p.reference_coefficient,
            crate::elementary::ln(p.direct_effect),
            p.evolution_effect,
            crate::elementary::ln(p.characteristic_slip),
        ];
        if let Some(net) = &self.correction {
            x.extend(net.parameters());
        }
        x
    }

    /// Sets the trainable parameters (layout of [`LearnedStateLaw::trainable`]).
    pub fn set_trainable(&mut self, x: &[f64]) {
        let p = &mut self.parameters;
        p.reference_coefficient = x[0];
        p.direct_effect = crate::elementary::exp(x[1]);
        p.evolution_effect = x[2];
        p.characteristic_slip = crate::elementary::exp(x[LOG_SLIP]);
        if let Some(net) = &mut self.correction {
            net.set_parameters(&x[STRUCTURED..]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::friction::learned_state::correction::InputScale;

    fn law(hidden: usize) -> LearnedStateLaw {
        let scale = |name: &str, mean: f64, std: f64| InputScale {
            name: name.into(),
            unit: String::new(),
            mean,
            std,
            min: mean - 3.0 * std,
            max: mean + 3.0 * std,
        };
        LearnedStateLaw {
            parameters: StateLawParameters {
                reference_coefficient: 0.6,
                reference_velocity: 1e-6,
                direct_effect: 0.01,
                evolution_effect: 0.015,
                characteristic_slip: 2e-5,
                state_evolution: StateEvolution::Aging,
            },
            correction: (hidden > 0).then(|| Correction {
                inputs: [
                    scale("state", -9.0, 1.5),
                    scale("normal_force", 100.0, 20.0),
                ],
                hidden_weights: (0..hidden).map(|k| [0.3 - 0.1 * k as f64, 0.2]).collect(),
                hidden_biases: (0..hidden).map(|k| 0.05 * k as f64).collect(),
                output_weights: (0..hidden).map(|k| 0.01 * (k as f64 - 1.0)).collect(),
            }),
        }
    }

    /// The parameter gradient and the state and velocity slopes against central
    /// differences of the force (relative 1e-6: step 1e-6 in each parameter, the force's
    /// curvature is O(1) in these units), with and without the correction, and the
    /// step's total slope with either evolution law.
    #[test]
    fn gradients_and_slopes_match_differences() {
        for (hidden, evolution) in [
            (0, StateEvolution::Aging),
            (3, StateEvolution::Aging),
            (3, StateEvolution::Slip),
        ] {
            let mut law = law(hidden);
            law.parameters.state_evolution = evolution;
            let x = law.trainable();
            let (psi, v, f_n) = (-8.5, 3e-3, 95.0);
            let mut g = vec![0.0; x.len()];
            let f = law.force_with_gradient(psi, v, f_n, Some((&mut g, 1.0)));
            for i in 0..x.len() {
                let e = 1e-6;
                let mut up = x.clone();
                up[i] += e;
                law.set_trainable(&up);
                let plus = law.force(psi, v, f_n).force;
                up[i] -= 2.0 * e;
                law.set_trainable(&up);
                let minus = law.force(psi, v, f_n).force;
                law.set_trainable(&x);
                let fd = (plus - minus) / (2.0 * e);
                let expected = if i == LOG_SLIP { 0.0 } else { fd };
                assert!(
                    (g[i] - expected).abs() < 1e-6 * fd.abs().max(1.0),
                    "{hidden} p{i}: {} {fd}",
                    g[i]
                );
            }
            let e = 1e-6;
            let fd =
                (law.force(psi + e, v, f_n).force - law.force(psi - e, v, f_n).force) / (2.0 * e);
            assert!((f.d_state - fd).abs() < 1e-6 * fd.abs());
            // The total slope of a step: the state moves with v_{n+1} too.
            let h = 1e-3;
            // The Jacobian at fixed state against differences of the force and slope.
            let j = law.jacobian(psi, v, f_n);
            let (dv, df) = (1e-9, 1e-4);
            let fd = |g: &dyn Fn(f64, f64) -> f64| {
                [
                    (g(v + dv, f_n) - g(v - dv, f_n)) / (2.0 * dv),
                    (g(v, f_n + df) - g(v, f_n - df)) / (2.0 * df),
                ]
            };
            let force = fd(&|v, n| law.force(psi, v, n).force);
            let slope = fd(&|v, n| law.force(psi, v, n).d_velocity);
            for k in 0..2 {
                assert!(
                    (j.force_gradient[k] - force[k]).abs() < 1e-5 * force[k].abs().max(1e-3),
                    "{hidden} F{k}"
                );
                assert!(
                    (j.slope_gradient[k] - slope[k]).abs() < 1e-4 * slope[k].abs().max(1e-3),
                    "{hidden} S{k}: {} {}",
                    j.slope_gradient[k],
                    slope[k]
                );
            }
            let s = law.after_step(psi, v, f_n, h);
            let dv = 1e-9;
            let fd = (law.after_step(psi, v + dv, f_n, h).force
                - law.after_step(psi, v - dv, f_n, h).force)
                / (2.0 * dv);
            assert!((s.slope - fd).abs() < 1e-5 * fd.abs(), "{} {fd}", s.slope);
        }
    }

    /// The slip law at rest: the state is frozen and the step's total slope is the
    /// slope at fixed state, finite, and continuous there (the state's ln V slope meets
    /// a dF/dpsi that vanishes like V: here 1/E = 2 V_0 e^{-Omega/a} ~ 1e-33 m/s, and at
    /// |v| = 1e-40 m/s their product is ~1e-3 N s/m against a slope of F_n a E ~ 1e33
    /// N s/m, so 1e-9 relative is generous).
    #[test]
    fn the_slip_law_is_frozen_at_rest_with_a_finite_continuous_slope() {
        let mut law = law(3);
        law.parameters.state_evolution = StateEvolution::Slip;
        let (psi, f_n, h) = (2.0, 100.0, 1e-3);
        let rest = law.after_step(psi, 0.0, f_n, h);
        assert_eq!(rest.state, psi);
        assert_eq!(rest.slope, law.force(psi, 0.0, f_n).d_velocity);
        for v in [1e-40, -1e-40, 5e-324] {
            let s = law.after_step(psi, v, f_n, h);
            assert!(s.slope.is_finite() && s.force.is_finite(), "v {v}: {s:?}");
            assert!(
                (s.slope - rest.slope).abs() < 1e-9 * rest.slope,
                "v {v}: {s:?}"
            );
        }
        // The aging law heals at rest instead: theta grows by h.
        law.parameters.state_evolution = StateEvolution::Aging;
        assert!(law.after_step(psi, 0.0, f_n, h).state > psi);
    }
}
