//! The training loss of a learned state law over force records and its exact gradient
//! (`fit` says what is minimised and why single shooting).
//!
//! The flat parameters x are the law's trainable ones (`LearnedStateLaw::trainable`,
//! `law_len` of them) and, when the records' initial states are trained, one start
//! psi_0 per record after them. Forward sensitivities carried along each record:
//! s_k = d psi_k / d ln D_c (s_0 = 0; s_k = (d psi_k / d psi_{k-1}) s_{k-1} +
//! d psi_k / d ln D_c) and q_k = d psi_k / d psi_0 (q_0 = 1; q_k = (d psi_k / d psi_{k-1})
//! q_{k-1}), so that dF_k/dp = dF/dp|_psi + dF/dpsi s_k [p = ln D_c] and
//! dF_k/dpsi_0 = dF/dpsi q_k.

use super::series::ForceSeries;
use stickslip::friction::learned_state::correction::PER_UNIT;
use stickslip::friction::learned_state::law::{LOG_SLIP, STRUCTURED};
use stickslip::friction::learned_state::LearnedStateLaw;

/// The state each record starts from when it is not trained: steady sliding at its
/// first velocity. When it is trained, the same at its first nonzero velocity is the
/// first guess (psi = 0, steady sliding at V_0, for a record that never slides).
pub fn steady_starts(law: &LearnedStateLaw, records: &[&ForceSeries]) -> Vec<f64> {
    records
        .iter()
        .map(|r| {
            r.velocity
                .iter()
                .find(|v| **v != 0.0)
                .map_or(0.0, |v| law.steady_state(v.abs()))
        })
        .collect()
}

/// Loss (N^2) and its gradient (into `gradient`, the length of `x`) of `law` over
/// `records` with x[..law_len] the law's parameters and x[law_len..], if any, the
/// records' starts; without them each record starts from [`steady_starts`].
pub(super) fn loss_and_gradient(
    law: &mut LearnedStateLaw,
    records: &[&ForceSeries],
    lambda: f64,
    law_len: usize,
    x: &[f64],
    gradient: &mut [f64],
) -> f64 {
    law.set_trainable(&x[..law_len]);
    let starts = if x.len() > law_len {
        x[law_len..].to_vec()
    } else {
        steady_starts(law, records)
    };
    gradient.iter_mut().for_each(|g| *g = 0.0);
    let n: usize = records.iter().map(|r| r.len()).sum();
    let mut sample_gradient = vec![0.0; law_len];
    let mut squared = 0.0;
    for (r, record) in records.iter().enumerate() {
        let mut state = starts[r];
        let (mut sensitivity, mut start_sensitivity) = (0.0, 1.0);
        for k in 0..record.len() {
            if k > 0 {
                let dt = record.time[k] - record.time[k - 1];
                let step = law.step_state(state, record.velocity[k], dt);
                state = step.state;
                sensitivity = step.d_state * sensitivity + step.d_log_slip;
                start_sensitivity *= step.d_state;
            }
            sample_gradient.iter_mut().for_each(|g| *g = 0.0);
            let f = law.force_with_gradient(
                state,
                record.velocity[k],
                record.normal_force[k],
                Some((&mut sample_gradient, 1.0)),
            );
            sample_gradient[LOG_SLIP] += f.d_state * sensitivity;
            let residual = f.force - record.force[k];
            squared += residual * residual;
            let weight = 2.0 * residual / n as f64;
            for (g, s) in gradient.iter_mut().zip(&sample_gradient) {
                *g += weight * s;
            }
            if let Some(g) = gradient.get_mut(law_len + r) {
                *g += weight * f.d_state * start_sensitivity;
            }
        }
    }
    let mut penalty = 0.0;
    for (i, (g, p)) in gradient
        .iter_mut()
        .zip(x)
        .enumerate()
        .take(law_len)
        .skip(STRUCTURED)
    {
        // Weights, not biases: unit slots 0, 1 (hidden) and 3 (output).
        if (i - STRUCTURED) % PER_UNIT != 2 {
            penalty += p * p;
            *g += lambda * p;
        }
    }
    squared / n as f64 + 0.5 * lambda * penalty
}

#[cfg(test)]
mod tests {
    use super::super::fit::scale;
    use super::*;
    use crate::learned_state::protocol::TribometerSpec;
    use stickslip::friction::learned_state::{Correction, StateEvolution};

    /// The forward-sensitivity gradient of the loss against central differences, with a
    /// correction, on short noisy records (relative 1e-5: differences of step 1e-6 in
    /// parameters of O(1) to O(10)), with either evolution law (the slip law's records
    /// and law: its step's D_c sensitivity is another formula), with the records'
    /// starts trained (moved off the steady state, so that they matter) and not.
    #[test]
    fn the_loss_gradient_is_exact_for_the_discrete_simulation() {
        for evolution in [StateEvolution::Aging, StateEvolution::Slip] {
            loss_gradient_matches_differences(evolution);
        }
    }

    fn loss_gradient_matches_differences(evolution: StateEvolution) {
        let mut spec = TribometerSpec {
            hold_slip: 3e-5,
            hold_time: 0.02,
            normal_forces: vec![80.0, 120.0],
            ..TribometerSpec::default()
        };
        spec.law.state_evolution = evolution;
        let records = spec.generate(1).unwrap();
        let refs: Vec<&ForceSeries> = records.iter().collect();
        let mut law = spec.as_learned();
        law.parameters.characteristic_slip = 1.3e-5;
        law.parameters.evolution_effect = 0.018;
        law.correction = Some(Correction {
            inputs: [
                scale("state", "1", [-5.0, 2.0]),
                scale("normal_force", "N", [80.0, 120.0]),
            ],
            hidden_weights: vec![[0.5, -0.3], [0.2, 0.8]],
            hidden_biases: vec![0.1, -0.2],
            output_weights: vec![0.01, -0.02],
        });
        let law_len = law.trainable().len();
        let starts: Vec<f64> = steady_starts(&law, &refs).iter().map(|s| s + 0.8).collect();
        for x in [law.trainable(), [law.trainable(), starts].concat()] {
            let mut g = vec![0.0; x.len()];
            loss_and_gradient(&mut law, &refs, 0.1, law_len, &x, &mut g);
            for i in 0..x.len() {
                let e = 1e-6;
                let mut xp = x.clone();
                xp[i] += e;
                let mut scratch = vec![0.0; x.len()];
                let plus = loss_and_gradient(&mut law, &refs, 0.1, law_len, &xp, &mut scratch);
                xp[i] -= 2.0 * e;
                let minus = loss_and_gradient(&mut law, &refs, 0.1, law_len, &xp, &mut scratch);
                let fd = (plus - minus) / (2.0 * e);
                assert!(
                    (g[i] - fd).abs() < 1e-5 * fd.abs().max(1.0),
                    "{evolution:?} p{i}: {} vs {fd}",
                    g[i]
                );
            }
        }
    }
}
