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

use super::parameters::{RateStateParameters, StateEvolution};
use super::relaxation::Relaxation;
use super::{set_checked, ForceAtState, LawStep, MemoryLaw, MemoryStateError, StateVariable};
use crate::elementary;
use crate::friction::FrictionLaw;

/// This law's state variable, listed in `crate::memory::STATE_VARIABLES` (defined
/// there, so that the list imports no law).
pub use super::STATE_THETA;

const STATE: [StateVariable; 1] = [STATE_THETA];

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

    fn as_memory(&self) -> Option<&dyn MemoryLaw> {
        Some(self)
    }

    fn as_memory_mut(&mut self) -> Option<&mut dyn MemoryLaw> {
        Some(self)
    }
}

impl MemoryLaw for RateStateLaw {
    fn state_variables(&self) -> &[StateVariable] {
        &STATE
    }

    fn state(&self) -> &[f64] {
        &self.state
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), MemoryStateError> {
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
