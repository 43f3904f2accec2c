//! `cargo run --release -p fmu-build`: builds the stickslip library and writes
//! `target/fmu/StickSlipBeam.fmu` and `target/fmu/NeuralFriction.fmu`.
//!
//! `--update-model-descriptions` rewrites the checked-in `modelDescription/*.xml` from
//! the Rust tables (after an interface change); without it, a drifted copy is an error.

use std::process::ExitCode;
use stickslip_fmi::FmuKind;

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.as_slice() {
        [] => {}
        [flag] if flag == "--update-model-descriptions" => fmu_build::update_descriptions()?,
        _ => {
            return Err(format!(
                "unknown arguments {args:?}; usage: fmu-build [--update-model-descriptions]"
            ))
        }
    }
    let drifted = fmu_build::drifted_descriptions();
    if !drifted.is_empty() {
        let names: Vec<String> = drifted.iter().map(|p| p.display().to_string()).collect();
        return Err(format!(
            "{} differ from what the Rust tables generate; run `cargo run --release -p fmu-build -- --update-model-descriptions` and review the diff",
            names.join(", ")
        ));
    }
    let library = fmu_build::build_library()?;
    for kind in FmuKind::ALL {
        let path = fmu_build::package(kind, &library, &fmu_build::fmu_dir())?;
        println!("wrote {} (GUID {})", path.display(), kind.guid());
    }
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("fmu-build: {message}");
            ExitCode::FAILURE
        }
    }
}
