//! Hyperparameter grid search with k-fold cross-validation on the training set (the
//! paper's Sec. 3.2 "hyperparameter optimization studies", here a plain grid).
//!
//! Every combination of depth, width and lambda is trained k times, each time on k - 1
//! folds, and scored on the held-out fold by the MSE of the law's force (raw target
//! units squared). Folds come from a seeded shuffle; each fold trains single-threaded
//! and folds run in parallel, so results do not depend on the thread count.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::data::{seeded_rng, Dataset, FOLD_STREAM};
use crate::error::TrainError;
use crate::train::{mse_and_r2, train, DataSource, TrainConfig};
use rand::seq::SliceRandom;

/// The grid and how to score it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SearchConfig {
    /// Numbers of hidden layers.
    pub depths: Vec<usize>,
    /// Widths (all hidden layers of a network have the same width).
    pub widths: Vec<usize>,
    pub lambdas: Vec<f64>,
    /// k of k-fold cross-validation.
    pub folds: usize,
    /// Everything else (activation, variant, iterations, seed); `hidden_layers` and
    /// `lambda` are overridden by the grid.
    pub base: TrainConfig,
    /// Folds trained at the same time.
    pub threads: usize,
}

impl Default for SearchConfig {
    fn default() -> Self {
        SearchConfig {
            depths: vec![1, 2, 3],
            widths: vec![10, 50, 100],
            lambdas: vec![0.0004, 0.004, 0.04],
            folds: 5,
            base: TrainConfig {
                max_iterations: 60,
                blocks: 1,
                ..TrainConfig::default()
            },
            threads: 2,
        }
    }
}

/// Cross-validation result of one grid point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SearchRow {
    pub depth: usize,
    pub width: usize,
    pub lambda: f64,
    /// Mean over folds of the held-out MSE (target units squared).
    pub mse_mean: f64,
    /// Standard deviation over folds of the held-out MSE.
    pub mse_std: f64,
    /// Mean over folds of the held-out R^2.
    pub r2_mean: f64,
    /// Wall-clock seconds for all folds of this grid point.
    pub seconds: f64,
}

/// Runs the grid on `data` (normally the training split; the test split stays unseen).
/// `on_row` sees each row as soon as it is done.
pub fn grid_search(
    data: &Dataset,
    config: &SearchConfig,
    mut on_row: impl FnMut(&SearchRow),
) -> Result<Vec<SearchRow>, TrainError> {
    let k = config.folds;
    if k < 2 || k > data.len() {
        return Err(TrainError::InvalidInput(format!(
            "k-fold cross-validation needs 2 <= k <= {} samples, got k = {k}",
            data.len()
        )));
    }
    if config.depths.is_empty() || config.widths.is_empty() || config.lambdas.is_empty() {
        return Err(TrainError::InvalidInput("the search grid is empty".into()));
    }
    let mut order: Vec<usize> = (0..data.len()).collect();
    order.shuffle(&mut seeded_rng(config.base.seed, FOLD_STREAM));
    let folds: Vec<(Dataset, Dataset)> = (0..k)
        .map(|f| {
            let (lo, hi) = (f * data.len() / k, (f + 1) * data.len() / k);
            let held_out = &order[lo..hi];
            let kept: Vec<usize> = order[..lo].iter().chain(&order[hi..]).copied().collect();
            (data.subset(&kept), data.subset(held_out))
        })
        .collect();

    let mut rows = Vec::new();
    for &depth in &config.depths {
        for &width in &config.widths {
            for &lambda in &config.lambdas {
                let train_config = TrainConfig {
                    hidden_layers: vec![width; depth],
                    lambda,
                    blocks: 1,
                    ..config.base.clone()
                };
                let started = Instant::now();
                let scores = score_folds(&folds, &train_config, config.threads.max(1))?;
                let n = scores.len() as f64;
                let mse_mean = scores.iter().map(|s| s.0).sum::<f64>() / n;
                let mse_std =
                    (scores.iter().map(|s| (s.0 - mse_mean).powi(2)).sum::<f64>() / n).sqrt();
                let row = SearchRow {
                    depth,
                    width,
                    lambda,
                    mse_mean,
                    mse_std,
                    r2_mean: scores.iter().map(|s| s.1).sum::<f64>() / n,
                    seconds: started.elapsed().as_secs_f64(),
                };
                on_row(&row);
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

/// (MSE, R^2) on each held-out fold, folds spread over `threads` threads.
fn score_folds(
    folds: &[(Dataset, Dataset)],
    config: &TrainConfig,
    threads: usize,
) -> Result<Vec<(f64, f64)>, TrainError> {
    let score = |fold: &(Dataset, Dataset)| -> Result<(f64, f64), TrainError> {
        let split = crate::data::Split {
            train: fold.0.clone(),
            test: fold.1.clone(),
        };
        let source = DataSource {
            description: "cross-validation fold".into(),
            synthetic: None,
            seed: config.seed,
            test_fraction: 0.0,
        };
        let (model, _) = train(&split, config, &source, |_| {})?;
        Ok(mse_and_r2(
            &model.predict_columns(&fold.1.inputs)?,
            &fold.1.targets,
        ))
    };
    let mut results: Vec<Option<Result<(f64, f64), TrainError>>> =
        (0..folds.len()).map(|_| None).collect();
    std::thread::scope(|scope| {
        let score = &score;
        let handles: Vec<_> = (0..threads.min(folds.len()))
            .map(|t| {
                scope.spawn(move || {
                    (t..folds.len())
                        .step_by(threads)
                        .map(|f| (f, score(&folds[f])))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for handle in handles {
            match handle.join() {
                Ok(done) => {
                    for (f, r) in done {
                        results[f] = Some(r);
                    }
                }
                Err(payload) => std::panic::resume_unwind(payload),
            }
        }
    });
    results
        .into_iter()
        .map(|r| r.unwrap_or_else(|| Err(TrainError::Training("a fold was not trained".into()))))
        .collect()
}

/// The rows as an aligned text table, best (lowest CV MSE) marked with '*'.
pub fn format_table(rows: &[SearchRow], unit: &str) -> String {
    let best = rows
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.mse_mean.total_cmp(&b.1.mse_mean))
        .map(|(i, _)| i);
    let squared = if unit.is_empty() {
        String::new()
    } else {
        format!(" [{unit}^2]")
    };
    let mut text = format!(
        "  {:>5} {:>5} {:>9} {:>14} {:>10} {:>10} {:>8}\n",
        "depth",
        "width",
        "lambda",
        format!("CV MSE{squared}"),
        "+- std",
        "CV R2",
        "seconds"
    );
    for (i, r) in rows.iter().enumerate() {
        text.push_str(&format!(
            "{} {:>5} {:>5} {:>9} {:>14.4} {:>10.4} {:>10.6} {:>8.1}\n",
            if Some(i) == best { "*" } else { " " },
            r.depth,
            r.width,
            r.lambda,
            r.mse_mean,
            r.mse_std,
            r.r2_mean,
            r.seconds
        ));
    }
    text
}
