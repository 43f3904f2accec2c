//! `stickslip export-fmu`: the scene as a co-simulation FMU of its own
//! (`fmu_build::export`, which the library's `stickslip_fmi::export` runs).

use crate::error::CliError;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// The FMI version of the exported FMU.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FmiVersionArg {
    #[value(name = "2.0")]
    V2,
    #[value(name = "3.0")]
    V3,
}

#[derive(Args, Debug)]
pub struct ExportFmuArgs {
    /// The scene (.toml or .json), with its [structure] files if it has one.
    #[arg(long)]
    pub scene: PathBuf,
    /// The FMU to write; its file name (without .fmu) becomes the modelIdentifier and
    /// must be a C identifier.
    #[arg(long)]
    pub out: PathBuf,
    /// FMI version.
    #[arg(long, value_enum, default_value = "2.0")]
    pub fmi: FmiVersionArg,
    /// The StickSlipBeam.fmu whose binaries the export carries (default: the one
    /// fmu-build writes, target/fmu/<version>/StickSlipBeam.fmu).
    #[arg(long)]
    pub from: Option<PathBuf>,
}

/// Runs `export-fmu` and prints what it wrote.
pub fn export_fmu(args: &ExportFmuArgs) -> Result<(), CliError> {
    let version = match args.fmi {
        FmiVersionArg::V2 => 2,
        FmiVersionArg::V3 => 3,
    };
    let from = args
        .from
        .clone()
        .unwrap_or_else(|| fmu_build::export::default_from(version));
    let exported = fmu_build::export::export_fmu(&args.scene, &args.out, version, &from)?;
    let platforms: Vec<&str> = exported
        .platforms
        .iter()
        .map(|p| {
            if version == 2 {
                p.fmi2_folder()
            } else {
                p.fmi3_folder()
            }
        })
        .collect();
    println!(
        "wrote {} (FMI {}.0, modelIdentifier {}, GUID {}, {} bytes, binaries: {})",
        exported.path.display(),
        version,
        exported.model_identifier,
        exported.guid,
        exported.bytes,
        platforms.join(", ")
    );
    Ok(())
}
