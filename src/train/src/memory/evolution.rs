//! Which state evolution the learned law is trained with: the aging law, the slip law,
//! or both, keeping the one whose law fits the held-out records better.
//!
//! The evolution is not a trained parameter: the two laws are different equations
//! (they differ most at rest, where the aging law heals and the slip law is frozen),
//! and a blend would no longer have a closed-form step. "Both" trains each from scratch
//! (twice the time) and compares the RMS force error (N) on the held-out records, or on
//! the training records when none are held out; the report lists both.

use super::fit::{fit_state_law, StateTrainConfig, StateTrainReport};
use super::series::ForceSeries;
use crate::error::TrainError;
use stickslip::neural::memory::{StateEvolution, StateLawFile};

stickslip::choice! {
    /// The state evolution the learned law is trained with.
    #[choice(name = "LearnedEvolution", description = "State evolution of the learned law with memory")]
    #[derive(Default)]
    pub enum LearnedEvolution {
        /// The aging law (Dieterich): the default, today's behaviour and speed.
        #[default]
        Aging = "aging": "the aging law d theta/dt = 1 - |v| theta / D_c: heals at rest",
        /// The slip law (Ruina).
        Slip = "slip": "the slip law d theta/dt = -(|v| theta / D_c) ln(|v| theta / D_c): frozen at rest",
        /// Each, keeping the better.
        Both = "both": "train with each law and keep the one with the lower held-out RMS force error (twice the time)",
    }
}

impl LearnedEvolution {
    /// The evolutions to train, in order.
    pub fn candidates(self) -> &'static [StateEvolution] {
        match self {
            LearnedEvolution::Aging => &[StateEvolution::Aging],
            LearnedEvolution::Slip => &[StateEvolution::Slip],
            LearnedEvolution::Both => &[StateEvolution::Aging, StateEvolution::Slip],
        }
    }
}

/// Trains a learned state law on `records` (checked first) with the evolution(s) of
/// `config.evolution`, returning the file of the better one (lower held-out RMS error;
/// the first on a tie) and a report listing every candidate. `data` and `noise_std`
/// describe the data for the file; `on_iteration` sees (iteration, loss) of each final
/// fit.
pub fn train_state_law(
    records: &[ForceSeries],
    config: &StateTrainConfig,
    data: &str,
    noise_std: f64,
    mut on_iteration: impl FnMut(usize, f64),
) -> Result<(StateLawFile, StateTrainReport), TrainError> {
    let mut best: Option<(StateLawFile, StateTrainReport)> = None;
    let mut candidates = Vec::new();
    for &evolution in config.evolution.candidates() {
        let (file, report) = fit_state_law(
            records,
            config,
            evolution,
            data,
            noise_std,
            &mut on_iteration,
        )?;
        candidates.push((evolution, file.metrics));
        let error = |file: &StateLawFile| {
            if file.training.test_series > 0 {
                file.metrics.rms_error_test
            } else {
                file.metrics.rms_error_train
            }
        };
        // NaN never wins: a comparison with it is false.
        if best
            .as_ref()
            .is_none_or(|(kept, _)| error(&file) < error(kept))
        {
            best = Some((file, report));
        }
    }
    let (file, mut report) = best.expect("every LearnedEvolution has a candidate");
    report.candidates = candidates;
    Ok((file, report))
}
