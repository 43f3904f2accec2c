//! `cargo run --release -p fmu-build`: builds the stickslip library and writes
//! `target/fmu/StickSlipBeam.fmu` and `target/fmu/NeuralFriction.fmu`, then the SSP
//! systems around them (`target/fmu/StickSlipCoupled.ssp`,
//! `target/fmu/StickSlipMonolithic.ssp`) and fmucontainer's link list of each
//! (`target/fmu/<system>.csv`).
//!
//! `--update-model-descriptions` rewrites the checked-in `modelDescription/*.xml` from
//! the Rust tables (after an interface change); without it, a drifted copy is an error.

use fmu_build::BuildError;
use std::process::ExitCode;
use stickslip_fmi::FmuKind;

fn run() -> Result<(), BuildError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.as_slice() {
        [] => {}
        [flag] if flag == "--update-model-descriptions" => fmu_build::update_descriptions()?,
        _ => return Err(BuildError::Usage(args)),
    }
    let drifted = fmu_build::drifted_descriptions();
    if !drifted.is_empty() {
        return Err(BuildError::Drift(drifted));
    }
    let library = fmu_build::build_library()?;
    for kind in FmuKind::ALL {
        let path = fmu_build::package(kind, &library, &fmu_build::fmu_dir())?;
        println!("wrote {} (GUID {})", path.display(), kind.guid());
    }
    let dir = fmu_build::fmu_dir();
    for system in fmu_build::ssp::systems() {
        let system = system.check()?;
        println!(
            "wrote {}",
            fmu_build::ssp::write_ssp(&system, &dir, &dir)?.display()
        );
        println!(
            "wrote {}",
            fmu_build::ssp::write_container_csv(&system, &dir)?.display()
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("fmu-build: {error}");
            ExitCode::FAILURE
        }
    }
}
