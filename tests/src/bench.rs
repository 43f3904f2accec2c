//! The benchmarks' ratio reports.
//!
//! Criterion measures and reports each variant. The project's speed claims are ratios
//! against a baseline measured in the same run (banded against dense, neural against
//! analytical, FMU against the library), so each benchmark also keeps here the time per
//! iteration of every criterion sample and prints its ratio table from them at the end.
//!
//! Criterion calls a routine first to warm up (1, 2, 4, ... iterations) and then once
//! per sample, so the last `sample_size` records of a benchmark are its measured samples;
//! the median over them is what the tables show. Under `cargo test` (criterion's test
//! mode) every routine runs once, and the tables are a smoke test of the reporting code,
//! not measurements.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// Times per iteration, in seconds, of each benchmark of one run, in the order measured.
pub struct Samples {
    sample_size: usize,
    times: RefCell<BTreeMap<String, Vec<f64>>>,
}

impl Samples {
    /// For benchmark groups configured with `sample_size` samples.
    pub fn new(sample_size: usize) -> Self {
        Self {
            sample_size,
            times: RefCell::new(BTreeMap::new()),
        }
    }

    /// A routine for criterion's `Bencher::iter_custom`: runs `f` `iters` times, records
    /// the time per iteration under `id` and returns the total.
    pub fn time<O>(&self, id: &str, iters: u64, mut f: impl FnMut() -> O) -> Duration {
        let start = Instant::now();
        for _ in 0..iters {
            std::hint::black_box(f());
        }
        let elapsed = start.elapsed();
        self.record(id, elapsed.as_secs_f64() / iters.max(1) as f64);
        elapsed
    }

    /// Records one sample's time per iteration (s) under `id`.
    pub fn record(&self, id: &str, seconds: f64) {
        self.times
            .borrow_mut()
            .entry(id.to_owned())
            .or_default()
            .push(seconds);
    }

    /// Median time per iteration (s) over the measured samples of `id`; None when it did
    /// not run (filtered out on the command line).
    pub fn median(&self, id: &str) -> Option<f64> {
        let times = self.times.borrow();
        let all = times.get(id)?;
        let mut measured = all[all.len().saturating_sub(self.sample_size)..].to_vec();
        measured.sort_by(f64::total_cmp);
        Some(measured[measured.len() / 2])
    }

    /// How many samples of `id` the median is over.
    pub fn count(&self, id: &str) -> usize {
        self.times
            .borrow()
            .get(id)
            .map_or(0, |all| all.len().min(self.sample_size))
    }
}

/// `value / baseline` as "12.3", or "-" when either did not run.
pub fn ratio(value: Option<f64>, baseline: Option<f64>, decimals: usize) -> String {
    match (value, baseline) {
        (Some(v), Some(b)) => format!("{:.decimals$}", v / b),
        _ => "-".to_owned(),
    }
}

/// `value` scaled by `scale` as "12.3", or "-" when it did not run.
pub fn shown(value: Option<f64>, scale: f64, decimals: usize) -> String {
    value.map_or("-".to_owned(), |v| format!("{:.decimals$}", v * scale))
}

/// Criterion's test mode, as it decides it: `cargo test` runs a bench binary without
/// `--bench` (`cargo bench` passes it), and `--test` asks for test mode explicitly.
/// Benchmarks use it to skip set-up that only the full measurement needs.
pub fn test_mode() -> bool {
    let mut bench = false;
    for arg in std::env::args().skip(1) {
        match arg.as_str() {
            "--test" => return true,
            "--bench" => bench = true,
            _ => {}
        }
    }
    !bench
}

/// The note under a ratio table: what its numbers are.
pub fn table_note(samples: &Samples) -> String {
    if test_mode() {
        "test mode (cargo test): every routine ran once, unwarmed; these are no measurements"
            .to_owned()
    } else {
        format!(
            "median over criterion's {} measured samples of each benchmark; ratios within this run",
            samples.sample_size
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_median_is_over_the_last_samples_only() {
        let samples = Samples::new(3);
        // Two warm-up calls, then three samples.
        for t in [100.0, 50.0, 2.0, 1.0, 3.0] {
            samples.record("a", t);
        }
        assert_eq!(samples.median("a"), Some(2.0));
        assert_eq!(samples.count("a"), 3);
        assert_eq!(samples.median("b"), None);
        assert_eq!(ratio(Some(6.0), Some(2.0), 1), "3.0");
        assert_eq!(ratio(None, Some(2.0), 1), "-");
        let total = samples.time("c", 4, || 1);
        assert_eq!(samples.count("c"), 1);
        assert!((samples.median("c").unwrap() - total.as_secs_f64() / 4.0).abs() < 1e-12);
    }
}
