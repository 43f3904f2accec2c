//! NeuralFriction's partial derivatives for fmi2GetDirectionalDerivative and
//! fmi3GetDirectionalDerivative: the law's input Jacobian (`stickslip::jacobian`: the
//! network's exact one, or the exponential law's closed form) mapped from the law's
//! inputs to the FMU's value references, and carried to the outputs made from it:
//! - friction_force F and friction_force_slope S = dF/dv: the law's gradients (S's is
//!   the second derivative d2F/dv dx);
//! - friction_force_magnitude |F|: sign(F) dF (0 at F = 0, where |F| has its kink);
//! - friction_coefficient c = |F| / F_n: sign(F) dF / F_n - |F| / F_n^2 dF_n (0 at
//!   F_n = 0, where c is defined as 0);
//! - static_limit mu_s F_n (0 for lugre): mu_s (0) along F_n; evaluated_velocity v: 1 along v;
//! - step_friction_force F_h and step_friction_slope S_h: those of F and S where they
//!   are F and S (a memoryless law, before the first step); for a law with state
//!   dF_h/dv = S_h, and the three others (dF_h/dF_n, dS_h/dv, dS_h/dF_n) centred
//!   differences of the law's own step, increments 1e-6 (|x| + scale) with the scale
//!   1 mm/s for v and 1 N for F_n (the step's exact second derivatives are not coded;
//!   no coupling uses them).

use super::*;
use stickslip::elementary::signum_or_zero;
use stickslip::jacobian::LawJacobian;

/// The FMU's inputs, in the order of the rows below.
const INPUTS: [u32; 2 + EXTRA_FEATURES] = [
    SLIDING_VELOCITY,
    NORMAL_FORCE,
    EXTRA_FEATURE[0],
    EXTRA_FEATURE[1],
    EXTRA_FEATURE[2],
    EXTRA_FEATURE[3],
];

impl NeuralFriction {
    /// The law's Jacobian at the current inputs, and the input that feeds each of the
    /// law's inputs.
    fn law_jacobian(&mut self) -> Result<(LawJacobian, Vec<u32>), EvaluateError> {
        if let Some((jacobian, _)) = self.state_jacobian()? {
            return Ok((jacobian, vec![SLIDING_VELOCITY, NORMAL_FORCE]));
        }
        if let Some(jacobian) = self.memoryless_jacobian()? {
            return Ok((jacobian, vec![SLIDING_VELOCITY, NORMAL_FORCE]));
        }
        let s = &self.settings;
        let network = self.networks.get(&s.weights)?;
        let inputs = feature_inputs(network.model(), &s.weights)?;
        let features: Vec<f64> = inputs.iter().map(|&vr| s.input(vr)).collect();
        let jacobian =
            network
                .input_jacobian(&features)
                .map_err(|source| EvaluateError::Evaluation {
                    weights: s.weights.clone(),
                    source,
                })?;
        Ok((jacobian, inputs))
    }

    /// d(output)/d(input) for every output and input (module notes), reused while the
    /// settings (parameters and inputs) and the law state stay the same.
    pub(super) fn derivatives(&mut self) -> Result<PartialDerivatives, EvaluateError> {
        if let Some((settings, law_state, partials)) = &self.derivatives_at {
            if *settings == self.settings && *law_state == self.law_state {
                return Ok(partials.clone());
            }
        }
        let partials = self.compute_derivatives()?;
        self.derivatives_at = Some((
            self.settings.clone(),
            self.law_state.clone(),
            partials.clone(),
        ));
        Ok(partials)
    }

    /// (dF_h/dv, dF_h/dF_n, dS_h/dv, dS_h/dF_n) of the step-consistent pair of a law
    /// with state after its first step (module notes), or `None` where the pair is the
    /// instantaneous one.
    fn step_pair_gradients(&mut self) -> Result<Option<[f64; 4]>, EvaluateError> {
        let Some((_, slope)) = self.step_pair()? else {
            return Ok(None);
        };
        let (v, normal) = (self.settings.sliding_velocity, self.settings.normal_force);
        let mut at = |v: f64, normal: f64| -> Result<(f64, f64), EvaluateError> {
            self.settings.sliding_velocity = v;
            self.settings.normal_force = normal;
            self.step_pair().map(|p| p.unwrap_or((0.0, 0.0)))
        };
        let dv = 1e-6 * (v.abs() + 1e-3);
        let dn = 1e-6 * (normal.abs() + 1.0);
        let (_, slope_up) = at(v + dv, normal)?;
        let (_, slope_down) = at(v - dv, normal)?;
        let (force_up, slope_n_up) = at(v, normal + dn)?;
        let (force_down, slope_n_down) = at(v, normal - dn)?;
        self.settings.sliding_velocity = v;
        self.settings.normal_force = normal;
        Ok(Some([
            slope,
            (force_up - force_down) / (2.0 * dn),
            (slope_up - slope_down) / (2.0 * dv),
            (slope_n_up - slope_n_down) / (2.0 * dn),
        ]))
    }

    /// The tabulated curves' derivatives with respect to every input but the sliding
    /// velocity (which they do not read): at each node v_i, the law's Jacobian there
    /// (as friction_force's at v) for the instantaneous curve, and for the one-step
    /// curve the same where it is that curve (a memoryless law, before the first step),
    /// else the centred difference of the law's own step along F_n, as for
    /// step_friction_force.
    fn table_derivatives(
        &mut self,
        partials: &mut PartialDerivatives,
    ) -> Result<(), EvaluateError> {
        let v = self.settings.sliding_velocity;
        let filled = self.table_derivatives_at_nodes(partials);
        self.settings.sliding_velocity = v;
        filled
    }

    fn table_derivatives_at_nodes(
        &mut self,
        partials: &mut PartialDerivatives,
    ) -> Result<(), EvaluateError> {
        let n = TABLE_LEN as u32;
        for (i, &at) in TABLE_VELOCITIES.iter().enumerate() {
            self.settings.sliding_velocity = at;
            let (jacobian, law_inputs) = self.law_jacobian()?;
            let mut row = [0.0; INPUTS.len()];
            for (value, input) in jacobian.force_gradient.iter().zip(&law_inputs) {
                if let Some(j) = INPUTS.iter().position(|x| x == input) {
                    row[j] += value;
                }
            }
            let step_n = self
                .step_pair_gradients()?
                .map(|[_, force_n, _, _]| force_n);
            self.settings.sliding_velocity = at;
            let output = FIRST_TABLE_OUTPUT + i as u32;
            for (j, &input) in INPUTS.iter().enumerate().skip(1) {
                partials.set(output, input, row[j]);
                let step = match step_n {
                    Some(force_n) if input == NORMAL_FORCE => force_n,
                    Some(_) => 0.0,
                    None => row[j],
                };
                partials.set(output + n, input, step);
            }
        }
        Ok(())
    }

    fn compute_derivatives(&mut self) -> Result<PartialDerivatives, EvaluateError> {
        let (jacobian, law_inputs) = self.law_jacobian()?;
        let s = &self.settings;
        let gradient_of = |values: &[f64]| -> [f64; INPUTS.len()] {
            let mut row = [0.0; INPUTS.len()];
            for (value, input) in values.iter().zip(&law_inputs) {
                if let Some(j) = INPUTS.iter().position(|i| i == input) {
                    row[j] += value;
                }
            }
            row
        };
        let force = gradient_of(&jacobian.force_gradient);
        let slope = gradient_of(&jacobian.slope_gradient);
        let sign = signum_or_zero(jacobian.force);
        let normal = s.normal_force;
        let mut partials = PartialDerivatives::default();
        for (j, &input) in INPUTS.iter().enumerate() {
            partials.set(FRICTION_FORCE, input, force[j]);
            partials.set(FRICTION_FORCE_SLOPE, input, slope[j]);
            partials.set(FRICTION_FORCE_MAGNITUDE, input, sign * force[j]);
            let mut coefficient = 0.0;
            if normal > 0.0 {
                coefficient = sign * force[j] / normal;
                if input == NORMAL_FORCE {
                    coefficient -= jacobian.force.abs() / (normal * normal);
                }
            }
            partials.set(FRICTION_COEFFICIENT, input, coefficient);
        }
        partials.set(
            STATIC_LIMIT_OUTPUT,
            NORMAL_FORCE,
            s.static_limit_coefficient(),
        );
        partials.set(EVALUATED_VELOCITY_OUTPUT, SLIDING_VELOCITY, 1.0);
        match self.step_pair_gradients()? {
            Some([force_v, force_n, slope_v, slope_n]) => {
                partials.set(STEP_FRICTION_FORCE, SLIDING_VELOCITY, force_v);
                partials.set(STEP_FRICTION_FORCE, NORMAL_FORCE, force_n);
                partials.set(STEP_FRICTION_SLOPE, SLIDING_VELOCITY, slope_v);
                partials.set(STEP_FRICTION_SLOPE, NORMAL_FORCE, slope_n);
            }
            None => {
                for (j, &input) in INPUTS.iter().enumerate() {
                    partials.set(STEP_FRICTION_FORCE, input, force[j]);
                    partials.set(STEP_FRICTION_SLOPE, input, slope[j]);
                }
            }
        }
        self.table_derivatives(&mut partials)?;
        if let Some((output, input, value)) = partials.non_finite() {
            return Err(EvaluateError::NonFiniteDerivative {
                output,
                input,
                value,
            });
        }
        Ok(partials)
    }
}
