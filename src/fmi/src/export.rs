//! An exported FMU (`stickslip export-fmu`): StickSlipBeam with a user's scene as its
//! start values, under a name of the user's choosing, served by this same library.
//!
//! The export's `resources/` holds, beside the network weights:
//! - [`SCENE_RESOURCE`], the user's scene, its structure files named relative to
//!   `resources/` (copied in by the export);
//! - [`EXPORT_RESOURCE`], what the scene file does not say: the modelIdentifier and the
//!   weights the FMU's `friction.weights` parameter starts at.
//!
//! Its modelDescription.xml is StickSlipBeam's table (every variable, one source of
//! truth) with the scene's values as start values, written by `model_description` from
//! [`Export::described`]. Its GUID (FMI 3.0: instantiationToken) is a hash of that
//! description without the GUID, followed by the bytes of the two files above and of
//! every structure file the scene names ([`Export::guid`]). The library, given a GUID
//! that is neither built-in FMU's, reads `resources/`, recomputes that hash and runs the
//! export only when the two are equal: an edited scene, a swapped structure file or a
//! modelDescription.xml from another export is refused at instantiation, with the
//! reason logged, instead of running something the description does not describe.

use crate::beam::exported::sensor_outputs;
use crate::beam::StickSlipBeam;
use crate::model::Model;
use crate::model_description::described::Described;
use crate::model_description::hash_guid;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use stickslip::scene::Scene;
use stickslip::user_structure::StructureSection;

/// The scene in `resources/`.
pub const SCENE_RESOURCE: &str = "scene.toml";
/// The export's own settings in `resources/` ([`ExportSettings`]).
pub const EXPORT_RESOURCE: &str = "export.toml";

/// What [`EXPORT_RESOURCE`] holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportSettings {
    /// modelName and modelIdentifier (a C identifier: the binaries' file name).
    pub model_identifier: String,
    /// Start value of `friction.weights`: a file in `resources/`.
    pub weights: String,
}

/// An export as its `resources/` holds it.
#[derive(Clone, Debug)]
pub struct Export {
    pub settings: ExportSettings,
    /// The scene with its structure files resolved against `resources/`.
    pub scene: Scene,
    /// The bytes of the scene file, the export file and each structure file, in that
    /// order: what the GUID covers besides the description.
    hashed: Vec<u8>,
}

/// Whether `name` is a C identifier (what FMI asks of a modelIdentifier, which names the
/// binaries and, in some importers, prefixes the functions).
pub fn is_c_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c == '_' || c.is_ascii_alphabetic())
        && chars.all(|c| c == '_' || c.is_ascii_alphanumeric())
}

impl Export {
    /// Reads the export in the unpacked `resources` folder.
    pub fn read(resources: &Path) -> Result<Self, String> {
        let read = |name: &str| {
            let path = resources.join(name);
            std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))
        };
        let scene_bytes = read(SCENE_RESOURCE)?;
        let export_bytes = read(EXPORT_RESOURCE)?;
        let text = |bytes: &[u8], name: &str| {
            String::from_utf8(bytes.to_vec())
                .map_err(|_| format!("resources/{name} is not UTF-8 text"))
        };
        let settings: ExportSettings = toml::from_str(&text(&export_bytes, EXPORT_RESOURCE)?)
            .map_err(|e| format!("resources/{EXPORT_RESOURCE}: {e}"))?;
        let mut scene = Scene::from_toml_str(&text(&scene_bytes, SCENE_RESOURCE)?)
            .map_err(|e| format!("resources/{SCENE_RESOURCE}: {e}"))?;
        let mut hashed = scene_bytes;
        hashed.extend_from_slice(&export_bytes);
        if let Some(section) = &scene.structure {
            check_sensor_names(section).map_err(|e| format!("resources/{SCENE_RESOURCE}: {e}"))?;
        }
        if let Some(section) = &mut scene.structure {
            section.resolve_paths(resources);
            for path in structure_files(section) {
                hashed.extend(
                    std::fs::read(&path)
                        .map_err(|e| format!("structure file {}: {e}", path.display()))?,
                );
            }
        }
        Ok(Self {
            settings,
            scene,
            hashed,
        })
    }

    /// The description of this export: StickSlipBeam's table under the export's name,
    /// starting at the scene's values.
    pub fn described(&self) -> Described<StickSlipBeam> {
        Described {
            model_identifier: self.settings.model_identifier.clone(),
            description: format!(
                "{}: a stick-slip scene exported by stickslip export-fmu (StickSlipBeam's variables, the scene's values as start values)",
                self.settings.model_identifier
            ),
            defaults: StickSlipBeam::with_scene(self.scene.clone(), &self.settings.weights),
        }
    }

    /// The export's GUID: the hash of its description without the GUID, then of the
    /// resources it runs from (see the module's documentation).
    pub fn guid(&self) -> String {
        let described = self.described();
        let mut text = described.body_without_guid().into_bytes();
        text.extend_from_slice(&self.hashed);
        hash_guid(&text)
    }
}

/// The sensors' output names (`beam::exported::sensor_outputs`) against StickSlipBeam's
/// variables and FMI 3.0's `time`, which an exported FMU declares beside them (the
/// scene's check has made them identifiers, unique among the sensors'): the first
/// clash, named.
pub fn check_sensor_names(section: &StructureSection) -> Result<(), String> {
    for output in sensor_outputs(&section.sensors) {
        let taken = StickSlipBeam::variables()
            .iter()
            .map(|v| (v.name, v.causality.as_str()))
            .chain([("time", "independent variable")])
            .find(|(name, _)| *name == output.name);
        if let Some((name, causality)) = taken {
            return Err(format!(
                "structure.sensors: the sensor output {name} has the name of the exported FMU's {causality} {name} (StickSlipBeam's variables are all declared beside the sensors); rename the sensor"
            ));
        }
    }
    Ok(())
}

/// The files a structure section names that exist as files: for CalculiX the job's
/// `.sti`, `.mas` and `.dof`, otherwise the paths given.
pub fn structure_files(section: &StructureSection) -> Vec<PathBuf> {
    let mut files = Vec::new();
    if let Some(job) = &section.job {
        files.extend(stickslip_formats::calculix::job_files(job));
    }
    for path in [
        &section.stiffness,
        &section.mass,
        &section.damping,
        &section.dofs,
        &section.mesh,
    ]
    .into_iter()
    .flatten()
    {
        files.push(path.clone());
    }
    files
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c_identifiers() {
        assert!(is_c_identifier("My_Beam2"));
        assert!(is_c_identifier("_x"));
        assert!(!is_c_identifier("2beam"));
        assert!(!is_c_identifier("my-beam"));
        assert!(!is_c_identifier(""));
        assert!(!is_c_identifier("beamé"));
    }
}
