//! `stickslip train-memory`: trains the learned friction law with memory
//! (`stickslip::friction::learned_state`) on force records under velocity histories (measured,
//! from CSV, or synthetic tribometer records of rate-and-state friction) and writes its
//! weights file.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::CliError;
use crate::train::check_output_directory;
use std::fmt::Write as _;
use stickslip::choice::Choice;
use stickslip::files::Outputs;
use stickslip::friction::learned_state::{LearnedStateFriction, StateLawFile};
use stickslip::friction::rate_and_state::StateEvolution;
use stickslip::friction::state::response::{velocity_step, velocity_step_curve};
use stickslip_train::learned_state::{
    read_series_csv, series_csv, train_state_law, LearnedEvolution, StateTrainConfig,
    StateTrainReport, TribometerSpec,
};

/// `stickslip train-memory`.
#[derive(clap::Args, Debug, Clone, PartialEq)]
pub struct TrainMemoryArgs {
    /// Measured records: CSV with columns t[s], v[m/s], F_n[N], F[N]; a record starts
    /// where t does not increase, from steady sliding at its first velocity. Without it,
    /// synthetic tribometer records of the scene's default rate-and-state law.
    #[arg(long, value_name = "FILE.csv")]
    pub data: Option<PathBuf>,
    /// Synthetic records: standard deviation of the force noise (N).
    #[arg(long, default_value_t = TribometerSpec::default().noise_std, conflicts_with = "data")]
    pub noise: f64,
    /// Synthetic records: the generating law's state evolution.
    #[arg(
        long,
        value_parser = crate::choice::parser::<StateEvolution>(),
        default_value = StateEvolution::default().name(),
        conflicts_with = "data"
    )]
    pub state_evolution: StateEvolution,
    /// The learned law's state evolution ("both" trains each and keeps the one with the
    /// lower held-out RMS force error).
    #[arg(
        long,
        value_parser = crate::choice::parser::<LearnedEvolution>(),
        default_value = LearnedEvolution::default().name()
    )]
    pub learned_evolution: LearnedEvolution,
    /// Seed of the synthetic noise and the correction's initial weights.
    #[arg(long, default_value_t = StateTrainConfig::default().seed)]
    pub seed: u64,
    /// Hidden units of the correction network (0: the structured law alone).
    #[arg(long, default_value_t = StateTrainConfig::default().hidden)]
    pub hidden: usize,
    /// Penalty lambda on the correction's weights (N^2).
    #[arg(long, default_value_t = StateTrainConfig::default().lambda)]
    pub lambda: f64,
    /// L-BFGS iterations of the final fit.
    #[arg(long, default_value_t = StateTrainConfig::default().max_iterations)]
    pub iterations: usize,
    /// Train each record's initial state too, for records that start from rest or
    /// mid-transient (otherwise each starts from steady sliding at its first velocity).
    #[arg(long)]
    pub train_initial_state: bool,
    /// Every N-th record is held out for testing (0: none).
    #[arg(long, default_value_t = StateTrainConfig::default().test_every)]
    pub test_every: usize,
    /// Output weights file (JSON, format stickslip-state-friction).
    #[arg(long, value_name = "FILE.json")]
    pub out: PathBuf,
    /// Also write the records trained on as CSV (the form --data reads).
    #[arg(long, value_name = "FILE.csv")]
    pub export_data: Option<PathBuf>,
    /// Synthetic records: also write the velocity-step responses (1 -> 10 mm/s and
    /// 100 -> 10 mm/s at 100 N) of the learned and the generating law as CSV
    /// (step, slip[m], mu_learned, mu_generating).
    #[arg(long, value_name = "FILE.csv", conflicts_with = "data")]
    pub step_response: Option<PathBuf>,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `stickslip train-memory`; returns the file written.
pub fn run_train_memory(args: &TrainMemoryArgs) -> Result<StateLawFile, CliError> {
    for path in [
        Some(&args.out),
        args.export_data.as_ref(),
        args.step_response.as_ref(),
    ]
    .into_iter()
    .flatten()
    {
        check_output_directory(path)?;
    }
    let synthetic = args.synthetic_spec();
    let (records, description, noise) = match (&args.data, &synthetic) {
        (Some(path), _) => (read_series_csv(path)?, file_name(path), 0.0),
        (None, Some(spec)) => (spec.generate(args.seed)?, spec.describe(), spec.noise_std),
        (None, None) => unreachable!("synthetic is Some exactly when data is None"),
    };
    let quiet = args.quiet;
    let (file, report) = train_state_law(
        &records,
        &args.train_config(),
        &description,
        noise,
        |i, loss| {
            if !quiet && i % 50 == 0 {
                eprintln!("iteration {i}: loss {loss:.6e} N^2");
            }
        },
    )?;
    // Every output after training, all or none.
    let mut outputs = Outputs::new();
    file.validate(&args.out.display().to_string())?;
    outputs.add(&args.out, file.to_json()?)?;
    if let Some(path) = &args.export_data {
        outputs.add(path, series_csv(&records))?;
    }
    print_summary(args, records.len(), &file, &report);
    if let Some(spec) = &synthetic {
        let csv = compare_step_responses(spec, &file);
        if let Some(path) = &args.step_response {
            outputs.add(path, csv)?;
        }
    }
    outputs.commit()?;
    Ok(file)
}

impl TrainMemoryArgs {
    /// The synthetic records' settings, without `--data`.
    fn synthetic_spec(&self) -> Option<TribometerSpec> {
        self.data.is_none().then(|| TribometerSpec {
            noise_std: self.noise,
            law: stickslip::friction::rate_and_state::RateStateParameters {
                state_evolution: self.state_evolution,
                ..TribometerSpec::default().law
            },
            ..TribometerSpec::default()
        })
    }

    fn train_config(&self) -> StateTrainConfig {
        StateTrainConfig {
            hidden: self.hidden,
            lambda: self.lambda,
            max_iterations: self.iterations,
            seed: self.seed,
            test_every: self.test_every,
            evolution: self.learned_evolution,
            train_initial_state: self.train_initial_state,
            ..StateTrainConfig::default()
        }
    }
}

/// Prints what was trained: each evolution's errors when both were, then the learned
/// parameters, the errors and how the fit ended.
fn print_summary(
    args: &TrainMemoryArgs,
    record_count: usize,
    file: &StateLawFile,
    report: &StateTrainReport,
) {
    if report.candidates.len() > 1 {
        for (evolution, m) in &report.candidates {
            println!(
                "{} law: RMS force error train {:.4} N, test {:.4} N",
                evolution.name(),
                m.rms_error_train,
                m.rms_error_test
            );
        }
    }
    let p = &file.law;
    println!(
        "{} records ({} samples) -> {}\nlearned ({} law): mu_0 {:.5} at V_0 {} m/s, a {:.5}, b {:.5}, D_c {:.4e} m; correction {} units\nRMS force error: train {:.4} N, test {:.4} N; {} iterations ({:?}); D_c grid start {:.1e} m",
        record_count,
        file.training.samples,
        args.out.display(),
        p.state_evolution.name(),
        p.reference_coefficient,
        p.reference_velocity,
        p.direct_effect,
        p.evolution_effect,
        p.characteristic_slip,
        args.hidden,
        file.metrics.rms_error_train,
        file.metrics.rms_error_test,
        report.iterations,
        file.training.stop_reason,
        report.grid_best.1,
    );
}

/// The learned law against the generating one over two velocity steps (1 -> 10 mm/s,
/// 100 -> 10 mm/s at 100 N): prints the direct effect and decay length of each and
/// returns the curves as CSV (step, slip[m], mu_learned, mu_generating).
fn compare_step_responses(spec: &TribometerSpec, file: &StateLawFile) -> String {
    let d_c = spec.law.characteristic_slip;
    let mut truth = spec.generating_law();
    let mut learned = LearnedStateFriction::new(Arc::new(file.law()));
    let mut csv = String::from("step,slip[m],mu_learned,mu_generating\n");
    for steps in [(1e-3, 1e-2), (1e-1, 1e-2)] {
        // From 2 D_c before the step to 8 D_c after it, every D_c / 20.
        let window = (2.0 * d_c, 8.0 * d_c, 0.05 * d_c);
        let got = velocity_step_curve(&mut learned, steps, 100.0, 1e3 * d_c, window);
        let want = velocity_step_curve(&mut truth, steps, 100.0, 1e3 * d_c, window);
        for ((slip, mu), (_, mu_truth)) in got.iter().zip(&want) {
            let _ = writeln!(csv, "{} -> {} m/s,{slip},{mu},{mu_truth}", steps.0, steps.1);
        }
        let want = velocity_step(&mut truth, steps, 100.0, 1e3 * d_c, 1e-3 * d_c);
        let got = velocity_step(&mut learned, steps, 100.0, 1e3 * d_c, 1e-3 * d_c);
        println!(
            "step {} -> {} m/s at 100 N: direct effect {:.5} (generating {:.5}), decay length {:.4e} m (generating {:.4e} m)",
            steps.0, steps.1, got.direct_effect, want.direct_effect, got.decay_length, want.decay_length
        );
    }
    csv
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
