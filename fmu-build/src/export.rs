//! `stickslip export-fmu`: a user's scene as a co-simulation FMU of its own, made from
//! our shipped StickSlipBeam.fmu without a compiler (`stickslip_fmi::export` describes
//! what the library does with it).
//!
//! The exported FMU holds:
//! - `modelDescription.xml`: StickSlipBeam's variable table under the output file's stem
//!   (modelName and modelIdentifier), the scene's values as start values, the GUID of
//!   `stickslip_fmi::export::Export::guid`;
//! - the binaries of every platform the `--from` FMU carries, renamed to the new
//!   modelIdentifier (the FMI 2.0 and 3.0 functions carry no prefix, so one binary serves
//!   any name);
//! - `resources/`: the scene (`scene.toml`), its structure files under `structure/` with
//!   the scene's paths rewritten to them, `export.toml`, the default network weights
//!   (which every instantiation checks) and the law's weights file if it names another.
//!
//! The resources are first written to a staging folder next to the output and read back
//! by the library's own `Export::read`, so that the GUID written is the one the library
//! will recompute. The FMU is written whole or not at all (`archive::write_zip`).

use crate::archive::{write_zip, Entry};
use crate::platform::Platform;
use std::io::Read as _;
use std::path::{Path, PathBuf};
use stickslip::scene::{CheckedScene, FidelityLevel, Scene};
use stickslip_fmi::export::{
    check_sensor_names, is_c_identifier, structure_files, Export, ExportSettings, EXPORT_RESOURCE,
    SCENE_RESOURCE,
};
use stickslip_fmi::networks::DEFAULT_WEIGHTS;
use stickslip_fmi::FmuKind;

/// The folder under `resources/` that holds the structure's files.
pub const STRUCTURE_FOLDER: &str = "structure";

/// Why an export failed; nothing was written in its place.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error("--out {}: the file name must end in .fmu", .0.display())]
    NotFmuName(PathBuf),
    #[error("--out {}: the name \"{name}\" becomes the modelIdentifier, which must be a C identifier (a letter or _, then letters, digits or _)", .path.display())]
    NotIdentifier { path: PathBuf, name: String },
    #[error(transparent)]
    Scene(#[from] stickslip::scene::SceneError),
    #[error("the scene's structure: {0}")]
    Structure(String),
    #[error("--from {}: {reason}", .path.display())]
    NotOurFmu { path: PathBuf, reason: String },
    #[error("{}: {source}", .path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("weights {name}: {reason}")]
    Weights { name: String, reason: String },
    #[error("the exported resources do not read back: {0}")]
    ReadBack(String),
    #[error(transparent)]
    Write(#[from] crate::BuildError),
}

/// What was written.
#[derive(Debug)]
pub struct Exported {
    pub path: PathBuf,
    pub model_identifier: String,
    pub guid: String,
    /// The platforms whose binaries it carries.
    pub platforms: Vec<Platform>,
    /// Its size (bytes).
    pub bytes: u64,
}

/// The default `--from`: the StickSlipBeam.fmu of FMI `version` (2 or 3) that fmu-build
/// writes under `target/fmu/`.
pub fn default_from(version: u8) -> PathBuf {
    let dir = if version == 2 {
        crate::fmu_dir()
    } else {
        crate::fmu3_dir()
    };
    dir.join(format!("{}.fmu", FmuKind::StickSlipBeam.model_identifier()))
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> ExportError + '_ {
    move |source| ExportError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The --from FMU's entries, checked to be StickSlipBeam of this interface and FMI
/// `version`: (name, bytes).
fn read_from(path: &Path, version: u8) -> Result<Vec<(String, Vec<u8>)>, ExportError> {
    let not_ours = |reason: String| ExportError::NotOurFmu {
        path: path.to_path_buf(),
        reason,
    };
    let file = std::fs::File::open(path).map_err(io(path))?;
    let mut archive = zip::ZipArchive::new(file)
        .map_err(|e| not_ours(format!("not an FMU (zip archive): {e}")))?;
    let mut entries = Vec::new();
    for k in 0..archive.len() {
        let mut entry = archive
            .by_index(k)
            .map_err(|e| not_ours(format!("entry {k}: {e}")))?;
        let name = entry
            .name()
            .map_err(|e| not_ours(format!("entry {k}: {e}")))?
            .into_owned();
        let mut bytes = Vec::new();
        entry
            .read_to_end(&mut bytes)
            .map_err(|e| not_ours(format!("{name}: {e}")))?;
        entries.push((name, bytes));
    }
    let description = entries
        .iter()
        .find(|(name, _)| name == "modelDescription.xml")
        .map(|(_, bytes)| String::from_utf8_lossy(bytes).into_owned())
        .ok_or_else(|| not_ours("no modelDescription.xml".into()))?;
    let kind = FmuKind::StickSlipBeam;
    let expected = if version == 2 {
        kind.model_description()
    } else {
        kind.model_description3()
    };
    if description != expected {
        let version_name = if version == 2 { "2.0" } else { "3.0" };
        return Err(not_ours(format!(
            "its modelDescription.xml is not this program's StickSlipBeam (FMI {version_name}, GUID {}): pass the StickSlipBeam.fmu of FMI {version_name} built from this version (`cargo run --release -p fmu-build`)",
            kind.guid()
        )));
    }
    Ok(entries)
}

/// The file name of `path` as a string.
fn file_name(path: &Path) -> Result<String, ExportError> {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .ok_or_else(|| ExportError::Structure(format!("{} names no file", path.display())))
}

/// Writes the FMU of the scene file `scene_path` to `out` for FMI `version` (2 or 3),
/// from the StickSlipBeam FMU `from`.
pub fn export_fmu(
    scene_path: &Path,
    out: &Path,
    version: u8,
    from: &Path,
) -> Result<Exported, ExportError> {
    if out.extension().and_then(|e| e.to_str()) != Some("fmu") {
        return Err(ExportError::NotFmuName(out.to_path_buf()));
    }
    let identifier = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    if !is_c_identifier(&identifier) {
        return Err(ExportError::NotIdentifier {
            path: out.to_path_buf(),
            name: identifier,
        });
    }
    // The scene as the command line reads it: unknown fields and bad values refused,
    // structure files named relative to the scene file; then its structure built once,
    // so that a missing or malformed structure file is refused here, not in the FMU.
    let checked = Scene::load(scene_path)?;
    // `auto` is chosen by the FMU at initialisation (its experiment's horizon); here the
    // files and DOFs are checked on the full model, which every choice reduces.
    let built = if checked.fidelity.level == FidelityLevel::Auto {
        let mut full = checked.scene().clone();
        full.fidelity.level = FidelityLevel::PlaneStress;
        full.check()?
    } else {
        checked.clone()
    };
    stickslip::structure::StructuralModel::build(&built)
        .map_err(|e| ExportError::Structure(e.to_string()))?;
    if let Some(section) = &checked.scene().structure {
        check_sensor_names(section).map_err(ExportError::Structure)?;
    }
    let from_entries = read_from(from, version)?;

    let mut scene = CheckedScene::into_scene(checked);
    // resources/ entries (path under resources/, bytes).
    let mut resources: Vec<(String, Vec<u8>)> = Vec::new();
    if let Some(section) = &mut scene.structure {
        let mut names = Vec::new();
        for source in structure_files(section) {
            let name = file_name(&source)?;
            if names.contains(&name) {
                return Err(ExportError::Structure(format!(
                    "two structure files are named {name}: resources/{STRUCTURE_FOLDER}/ holds one folder"
                )));
            }
            let bytes = std::fs::read(&source).map_err(io(&source))?;
            resources.push((format!("{STRUCTURE_FOLDER}/{name}"), bytes));
            names.push(name);
        }
        let folder = Path::new(STRUCTURE_FOLDER);
        for path in [
            &mut section.job,
            &mut section.stiffness,
            &mut section.mass,
            &mut section.damping,
            &mut section.dofs,
            &mut section.mesh,
        ]
        .into_iter()
        .flatten()
        {
            *path = folder.join(file_name(path)?);
        }
    }
    // The law's weights: the FMU's friction.weights parameter names a file in
    // resources/; the scene's own field is not read by the FMU.
    let weights = match scene.friction.weights.take() {
        None => DEFAULT_WEIGHTS.to_owned(),
        Some(given) => {
            let path = Path::new(&given);
            let name = file_name(path)?;
            let shipped = format!("resources/{name}");
            let bytes = match from_entries.iter().find(|(n, _)| *n == shipped) {
                Some((_, bytes)) if !path.is_file() => bytes.clone(),
                _ => std::fs::read(path).map_err(|e| ExportError::Weights {
                    name: given.clone(),
                    reason: e.to_string(),
                })?,
            };
            if name != DEFAULT_WEIGHTS {
                resources.push((name.clone(), bytes));
            }
            name
        }
    };
    let default_weights = format!("resources/{DEFAULT_WEIGHTS}");
    let (_, bytes) = from_entries
        .iter()
        .find(|(n, _)| *n == default_weights)
        .ok_or_else(|| ExportError::NotOurFmu {
            path: from.to_path_buf(),
            reason: format!("no {default_weights}"),
        })?;
    resources.push((DEFAULT_WEIGHTS.to_owned(), bytes.clone()));
    let settings = ExportSettings {
        model_identifier: identifier.clone(),
        weights,
    };
    let scene_text = toml::to_string(&scene)
        .map_err(|e| ExportError::Structure(format!("the scene cannot be written as TOML: {e}")))?;
    let export_text = toml::to_string(&settings)
        .map_err(|e| ExportError::Structure(format!("export.toml: {e}")))?;
    resources.push((SCENE_RESOURCE.to_owned(), scene_text.into_bytes()));
    resources.push((EXPORT_RESOURCE.to_owned(), export_text.into_bytes()));
    resources.sort_by(|a, b| a.0.cmp(&b.0));

    // The GUID as the library computes it: from the resources written out and read back.
    let (guid, description) = {
        let stage = Staging::new(out)?;
        for (name, bytes) in &resources {
            let path = stage.dir.join(name);
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).map_err(io(parent))?;
            }
            std::fs::write(&path, bytes).map_err(io(&path))?;
        }
        let export = Export::read(&stage.dir).map_err(ExportError::ReadBack)?;
        let guid = export.guid();
        let described = export.described();
        let description = if version == 2 {
            described.generate_with(&guid)
        } else {
            described.generate3_with(&guid)
        };
        (guid, description)
    };

    let mut entries = vec![Entry::deflated(
        "modelDescription.xml",
        description.into_bytes(),
    )];
    let mut platforms = Vec::new();
    for platform in Platform::ALL {
        let shipped = platform.binary_entry(version, FmuKind::StickSlipBeam.model_identifier());
        if let Some((_, bytes)) = from_entries.iter().find(|(n, _)| *n == shipped) {
            entries.push(Entry {
                mode: 0o755,
                ..Entry::deflated(platform.binary_entry(version, &identifier), bytes.clone())
            });
            platforms.push(platform);
        }
    }
    if platforms.is_empty() {
        return Err(ExportError::NotOurFmu {
            path: from.to_path_buf(),
            reason: "it carries no binary of a platform this program knows".into(),
        });
    }
    for (name, bytes) in resources {
        entries.push(Entry::deflated(format!("resources/{name}"), bytes));
    }
    write_zip(out, entries)?;
    let bytes = std::fs::metadata(out).map_err(io(out))?.len();
    Ok(Exported {
        path: out.to_path_buf(),
        model_identifier: identifier,
        guid,
        platforms,
        bytes,
    })
}

/// A folder next to the output, removed when dropped.
struct Staging {
    dir: PathBuf,
}

impl Staging {
    fn new(out: &Path) -> Result<Self, ExportError> {
        let parent = out
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let stem = out.file_stem().unwrap_or_default().to_string_lossy();
        let dir = parent.join(format!(".{stem}.export-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        Ok(Self { dir })
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
