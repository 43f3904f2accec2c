//! The `stickslip train` and `stickslip search` commands (argument structs and handlers
//! live here so that the binary only dispatches).

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

use crate::error::CliError;
use stickslip::choice::Choice;
use stickslip::files::{write_atomically, OutputFileError, Outputs};
use stickslip::neural::{Activation, NeuralModel, SyntheticPreset, SyntheticSpec, Variant};
use stickslip_train::csv::{read_csv_file, ColumnSelection};
use stickslip_train::data::{Split, Synthetic, NORMAL_FORCE, SLIDING_VELOCITY};
use stickslip_train::search::{format_table, grid_search, SearchConfig, SearchRow};
use stickslip_train::train::{
    train, DataSource, HistoryRecord, TrainConfig, TrainReport, DEFAULT_ITERATIONS, DEFAULT_LAMBDA,
    DEFAULT_SEED,
};

/// Where the training data come from (shared by `train` and `search`).
#[derive(clap::Args, Debug, Clone, PartialEq)]
pub struct DataArgs {
    /// Measured data: CSV with a header of names, optionally `name[unit]`. Without it
    /// the paper's synthetic data set is generated.
    #[arg(long, value_name = "FILE.csv")]
    pub data: Option<PathBuf>,
    /// Feature columns of --data, comma-separated, in the order the network sees them.
    #[arg(long, value_delimiter = ',', value_name = "A,B,...")]
    pub features: Vec<String>,
    /// Target column of --data.
    #[arg(long, value_name = "NAME")]
    pub target: Option<String>,
    /// Feature holding the signed sliding velocity (default: `sliding_velocity` if it is
    /// a feature). Needed by the signed variant and the beam.
    #[arg(long, value_name = "NAME")]
    pub velocity_feature: Option<String>,
    /// Feature holding the normal force (default: `normal_force` if it is a feature).
    #[arg(long, value_name = "NAME")]
    pub normal_force_feature: Option<String>,
    /// Share of the samples held out as the test set.
    #[arg(long, default_value_t = 0.3)]
    pub test_fraction: f64,
    /// The test set as a second CSV with the columns of --data: your own split instead
    /// of a random hold-out of --test-fraction.
    #[arg(
        long,
        value_name = "TEST.csv",
        requires = "data",
        conflicts_with = "test_fraction"
    )]
    pub test_data: Option<PathBuf>,
    /// Synthetic data: number of draws N (paper: 5000; the authors' data set removes
    /// those with |v_s| <= 1e-4 m/s).
    #[arg(long, default_value_t = 5000)]
    pub samples: usize,
    /// Synthetic data: which distribution (`former` regenerates the shipped networks).
    #[arg(
        long,
        value_parser = crate::choice::parser::<SyntheticPreset>(),
        default_value = SyntheticPreset::default().name(),
        conflicts_with = "data"
    )]
    pub generator: SyntheticPreset,
    /// Seed of data generation, split, folds and initial weights.
    #[arg(long, default_value_t = DEFAULT_SEED)]
    pub seed: u64,
}

/// `stickslip train`.
#[derive(clap::Args, Debug, Clone, PartialEq)]
pub struct TrainArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// L-BFGS iteration limit.
    #[arg(long, default_value_t = DEFAULT_ITERATIONS)]
    pub iterations: usize,
    /// L2 penalty lambda on the weights: loss = MSE + lambda/2 ||W||^2 (see
    /// stickslip_train::train).
    #[arg(long, default_value_t = DEFAULT_LAMBDA)]
    pub lambda: f64,
    /// plain: the paper's network F(v, F_n); signed: F = sign(v) g(|v|, F_n).
    #[arg(
        long,
        value_parser = crate::choice::parser::<Variant>(),
        default_value = TrainConfig::default().variant.name()
    )]
    pub variant: Variant,
    /// Hidden-layer activation.
    #[arg(
        long,
        value_parser = crate::choice::parser::<Activation>(),
        default_value = TrainConfig::default().activation.name()
    )]
    pub activation: Activation,
    /// Hidden layer widths, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "100,100,100")]
    pub layers: Vec<usize>,
    /// Batch blocks (threads). Part of the reproducibility: a different value changes
    /// rounding and so the weights.
    #[arg(long, default_value_t = TrainConfig::default().blocks)]
    pub threads: usize,
    /// Output weights file (JSON).
    #[arg(long, value_name = "FILE.json")]
    pub out: PathBuf,
    /// Training report (JSON): metrics, iterations, seconds and the history.
    #[arg(long, value_name = "FILE.json")]
    pub report: Option<PathBuf>,
    /// Training history (CSV): loss per iteration.
    #[arg(long, value_name = "FILE.csv")]
    pub history: Option<PathBuf>,
    /// Write the exact train/test split as DIR/train.csv and DIR/test.csv.
    #[arg(long, value_name = "DIR")]
    pub export_data: Option<PathBuf>,
    /// No progress line even on a terminal.
    #[arg(long)]
    pub quiet: bool,
}

/// `stickslip search`.
#[derive(clap::Args, Debug, Clone, PartialEq)]
pub struct SearchArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// Numbers of hidden layers to try.
    #[arg(long, value_delimiter = ',', default_value = "1,2,3")]
    pub depths: Vec<usize>,
    /// Hidden layer widths to try.
    #[arg(long, value_delimiter = ',', default_value = "10,50,100")]
    pub widths: Vec<usize>,
    /// lambda values to try.
    #[arg(long, value_delimiter = ',', default_value = "0.0004,0.004,0.04")]
    pub lambdas: Vec<f64>,
    /// k of k-fold cross-validation.
    #[arg(long, default_value_t = 5)]
    pub folds: usize,
    /// L-BFGS iterations per fit (reduced: this is a study).
    #[arg(long, default_value_t = 60)]
    pub iterations: usize,
    #[arg(
        long,
        value_parser = crate::choice::parser::<Variant>(),
        default_value = TrainConfig::default().variant.name()
    )]
    pub variant: Variant,
    #[arg(
        long,
        value_parser = crate::choice::parser::<Activation>(),
        default_value = TrainConfig::default().activation.name()
    )]
    pub activation: Activation,
    /// Folds trained in parallel.
    #[arg(long, default_value_t = 2)]
    pub threads: usize,
    /// Also write the table as JSON.
    #[arg(long, value_name = "FILE.json")]
    pub out: Option<PathBuf>,
}

/// Loads or generates the data and splits it.
pub fn load_split(args: &DataArgs) -> Result<(Split, DataSource), CliError> {
    match &args.data {
        None => {
            if !args.features.is_empty() || args.target.is_some() {
                return Err(CliError::ColumnsWithoutData);
            }
            let spec = SyntheticSpec {
                samples: args.samples,
                test_fraction: args.test_fraction,
                ..SyntheticSpec::preset(args.generator)
            };
            let split = spec.generate_split(args.seed)?;
            Ok((
                split,
                DataSource {
                    description: "synthetic (Vater et al. 2023, Sec. 3.1)".into(),
                    synthetic: Some(spec),
                    seed: args.seed,
                    test_fraction: args.test_fraction,
                },
            ))
        }
        Some(path) => {
            let target = args.target.clone().ok_or(CliError::DataWithoutTarget)?;
            if args.features.is_empty() {
                return Err(CliError::DataWithoutFeatures);
            }
            let default_role = |given: &Option<String>, name: &str| {
                given.clone().or_else(|| {
                    args.features
                        .iter()
                        .any(|f| f == name)
                        .then(|| name.to_string())
                })
            };
            let selection = ColumnSelection {
                features: args.features.clone(),
                target,
                sliding_velocity: default_role(&args.velocity_feature, SLIDING_VELOCITY),
                normal_force: default_role(&args.normal_force_feature, NORMAL_FORCE),
            };
            let file_name = |path: &Path| {
                path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                )
            };
            let data = read_csv_file(path, &selection)?;
            let (split, description) = match &args.test_data {
                None => (data.split(args.test_fraction, args.seed)?, file_name(path)),
                Some(test_path) => (
                    Split::given(data, read_csv_file(test_path, &selection)?)?,
                    format!("{} (test: {})", file_name(path), file_name(test_path)),
                ),
            };
            // With a given split the report records the share the test file makes up.
            let (n_train, n_test) = (split.train.len(), split.test.len());
            let test_fraction = match args.test_data {
                None => args.test_fraction,
                Some(_) => n_test as f64 / (n_train + n_test) as f64,
            };
            Ok((
                split,
                DataSource {
                    description,
                    synthetic: None,
                    seed: args.seed,
                    test_fraction,
                },
            ))
        }
    }
}

/// Fails early (before minutes of training) if an output file's directory is missing.
pub(crate) fn check_output_directory(path: &Path) -> Result<(), CliError> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.is_dir() => {
            Err(OutputFileError::MissingDirectory {
                path: path.to_path_buf(),
            }
            .into())
        }
        _ => Ok(()),
    }
}

/// Runs `stickslip train`; returns the report.
pub fn run_train(args: &TrainArgs) -> Result<TrainReport, CliError> {
    for path in [Some(&args.out), args.report.as_ref(), args.history.as_ref()]
        .into_iter()
        .flatten()
    {
        check_output_directory(path)?;
    }
    let (split, source) = load_split(&args.data)?;
    let config = TrainConfig {
        hidden_layers: args.layers.clone(),
        activation: args.activation,
        variant: args.variant,
        lambda: args.lambda,
        max_iterations: args.iterations,
        seed: args.data.seed,
        blocks: args.threads.max(1),
        ..TrainConfig::default()
    };
    let progress = !args.quiet && std::io::stderr().is_terminal();
    let max_iterations = args.iterations;
    let (model, report) = train(&split, &config, &source, |h: &HistoryRecord| {
        if progress {
            eprint!(
                "\r  iteration {:>5}/{max_iterations}  objective {:.6e}  MSE train {:>10.4}  MSE test {:>10.4}",
                h.iteration, h.objective, h.mse_train, h.mse_test
            );
            let _ = std::io::stderr().flush();
        }
    })?;
    if progress {
        eprintln!();
    }
    write_training(args, &model, &report, &split)?;
    print_training(args, &model, &report, &source);
    println!("  wrote {}", args.out.display());
    Ok(report)
}

/// Writes the weights and, as asked, the report, the history and the split's data:
/// every output after training, all or none, as a report without its weights (or data
/// exported for a run that failed) would be taken for a finished run.
fn write_training(
    args: &TrainArgs,
    model: &NeuralModel,
    report: &TrainReport,
    split: &Split,
) -> Result<(), CliError> {
    let mut outputs = Outputs::new();
    model.validate(&args.out.display().to_string())?;
    outputs.add(&args.out, model.to_json()?)?;
    if let Some(path) = &args.report {
        let text = serde_json::to_string_pretty(report).map_err(|source| CliError::Json {
            path: path.clone(),
            source,
        })?;
        outputs.add(path, text + "\n")?;
    }
    if let Some(path) = &args.history {
        outputs.add(path, report.history_csv())?;
    }
    if let Some(dir) = &args.export_data {
        std::fs::create_dir_all(dir).map_err(|source| CliError::Folder {
            path: dir.clone(),
            source,
        })?;
        outputs.add(&dir.join("train.csv"), split.train.to_csv())?;
        outputs.add(&dir.join("test.csv"), split.test.to_csv())?;
    }
    outputs.commit()?;
    Ok(())
}

/// The network trained, how the training stopped and its errors on both sets.
fn print_training(
    args: &TrainArgs,
    model: &NeuralModel,
    report: &TrainReport,
    source: &DataSource,
) {
    let unit = if model.target.unit.is_empty() {
        String::new()
    } else {
        format!(" {}^2", model.target.unit)
    };
    let sizes: Vec<String> = report.layer_sizes.iter().map(usize::to_string).collect();
    println!(
        "trained {:?} {} {} (lambda {}, seed {}) on {}: {} iterations ({:?}), {} evaluations, {:.1} s",
        report.variant,
        sizes.join("-"),
        args.activation.name(),
        report.lambda,
        report.seed,
        source.description,
        report.iterations,
        report.stop_reason,
        report.evaluations,
        report.seconds
    );
    println!(
        "  train ({:>5} samples): MSE {:.4}{unit}  R2 {:.5}",
        report.train_samples, report.mse_train, report.r2_train
    );
    println!(
        "  test  ({:>5} samples): MSE {:.4}{unit}  R2 {:.5}",
        report.test_samples, report.mse_test, report.r2_test
    );
}

/// Runs `stickslip search`; prints the table and returns its rows.
pub fn run_search(args: &SearchArgs) -> Result<Vec<SearchRow>, CliError> {
    let (split, source) = load_split(&args.data)?;
    let config = SearchConfig {
        depths: args.depths.clone(),
        widths: args.widths.clone(),
        lambdas: args.lambdas.clone(),
        folds: args.folds,
        base: TrainConfig {
            activation: args.activation,
            variant: args.variant,
            max_iterations: args.iterations,
            seed: args.data.seed,
            blocks: 1,
            ..TrainConfig::default()
        },
        threads: args.threads,
    };
    println!(
        "grid search, {}-fold CV on the {} training samples of {} ({} iterations per fit)",
        args.folds,
        split.train.len(),
        source.description,
        args.iterations
    );
    let progress = std::io::stderr().is_terminal();
    let total = config.depths.len() * config.widths.len() * config.lambdas.len();
    let mut done = 0;
    let rows = grid_search(&split.train, &config, |row| {
        done += 1;
        if progress {
            eprint!(
                "\r  {done}/{total}: depth {} width {} lambda {} -> CV MSE {:.4}   ",
                row.depth, row.width, row.lambda, row.mse_mean
            );
            let _ = std::io::stderr().flush();
        }
    })?;
    if progress {
        eprintln!();
    }
    print!("{}", format_table(&rows, &split.train.target.unit));
    if let Some(path) = &args.out {
        let text = serde_json::to_string_pretty(&rows).map_err(|source| CliError::Json {
            path: path.clone(),
            source,
        })?;
        write_atomically(path, text + "\n")?;
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(subcommand)]
        command: Command,
    }

    #[derive(clap::Subcommand)]
    enum Command {
        Train(TrainArgs),
        Search(SearchArgs),
    }

    /// Without flags, `train` trains as `TrainConfig::default()` does, and `search` with
    /// its variant and activation.
    #[test]
    fn the_defaults_are_the_trainers() {
        let config = TrainConfig::default();
        let Command::Train(train) =
            Cli::parse_from(["stickslip", "train", "--out", "w.json"]).command
        else {
            unreachable!()
        };
        assert_eq!(train.variant, config.variant);
        assert_eq!(train.activation, config.activation);
        assert_eq!(train.layers, config.hidden_layers);
        assert_eq!(train.lambda, config.lambda);
        assert_eq!(train.iterations, config.max_iterations);
        assert_eq!(train.data.seed, config.seed);
        assert_eq!(train.threads, config.blocks);
        let Command::Search(search) = Cli::parse_from(["stickslip", "search"]).command else {
            unreachable!()
        };
        assert_eq!(search.variant, config.variant);
        assert_eq!(search.activation, config.activation);
    }
}
