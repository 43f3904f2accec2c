//! `stickslip`: the command line of the stick-slip beam simulator.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "stickslip",
    version,
    about = "Stick-slip cantilever beam with analytical or neural friction"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a stick-slip scene (default: the paper's) and print its summary.
    Simulate(stickslip_cli::simulate::SimulateArgs),
    /// Static tip-load check against Euler-Bernoulli, or the mesh-convergence table.
    Static(stickslip_cli::simulate::StaticArgs),
    /// Train the neural friction law (paper data by default) and write its weights file.
    Train(stickslip_cli::train::TrainArgs),
    /// Train the learned friction law with memory (rate-and-state with a network
    /// correction) on force records under velocity histories; write its weights file.
    TrainMemory(stickslip_cli::train_memory::TrainMemoryArgs),
    /// Speed against accuracy: the paper scene over a grid of fidelity levels, time
    /// steps and integrators, with errors against a converged reference and the Pareto
    /// front.
    Study(stickslip_cli::study::StudyArgs),
    /// Closed-form numbers of the scene's Euler-Bernoulli cantilever as JSON: bending
    /// frequencies, mass, Rayleigh damping, and the belt speed above which steady sliding
    /// is stable.
    Estimates(stickslip_cli::estimates::EstimatesArgs),
    /// Hyperparameter grid search with k-fold cross-validation for the neural law.
    Search(stickslip_cli::train::SearchArgs),
    /// An ONNX network (scikit-learn, PyTorch, Keras exports) as a weights file, its
    /// inputs described by the file's metadata or by flags; optionally checked on data.
    ImportNetwork(stickslip_cli::import::ImportArgs),
    /// The scene (its [structure] included) as a co-simulation FMU of its own, made from
    /// the shipped StickSlipBeam.fmu: the scene's values as start values, its files in
    /// resources/.
    ExportFmu(stickslip_cli::export_fmu::ExportFmuArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Simulate(args) => stickslip_cli::simulate::simulate(args),
        Command::Static(args) => stickslip_cli::simulate::static_check(args),
        Command::Study(args) => stickslip_cli::study::study(args),
        Command::Estimates(args) => stickslip_cli::estimates::estimates(args),
        Command::Train(args) => stickslip_cli::train::run_train(args).map(|_| ()),
        Command::TrainMemory(args) => {
            stickslip_cli::train_memory::run_train_memory(args).map(|_| ())
        }
        Command::Search(args) => stickslip_cli::train::run_search(args).map(|_| ()),
        Command::ImportNetwork(args) => stickslip_cli::import::run_import(args).map(|_| ()),
        Command::ExportFmu(args) => stickslip_cli::export_fmu::export_fmu(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
