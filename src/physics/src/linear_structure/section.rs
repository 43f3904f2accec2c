//! The scene's `[structure]` section: a user's structure from files, in place of the
//! built-in beam (issue 35 item 2, the full model).
//!
//! ```toml
//! [structure]
//! format = "calculix"          # or "matrix-market"
//! job = "beam"                 # calculix: dir/JOB for JOB.sti, JOB.mas, JOB.dof
//! # stiffness = "k.mtx"        # matrix-market: K, M and the DOF map file
//! # mass = "m.mtx"
//! # dofs = "k.dofs"
//! contact = { node = 202, direction = 2 }      # where friction acts and the belt moves
//! clamped = [{ node = 7, direction = 3 }]      # DOFs the files did not remove (optional)
//! ```
//!
//! Paths are relative to the scene file ([`crate::scene::Scene::load`] makes them
//! absolute) or absolute; a scene given as text takes them relative to the working
//! directory. The section is checked twice: its fields by [`StructureSection::check`]
//! inside `Scene::check` (no file is opened there), the files and the DOFs by
//! [`StructuralModel::from_section`] when the model is built.
//!
//! The structure is the full model: M and K as given, clamped DOFs removed, the scene's
//! Rayleigh damping C = a M + b K on them as on the beam (the integrator forms it from
//! the model's M and K). The tip is the contact DOF: u_tip = u_contact, and the friction
//! force enters as a force on that DOF (N, or N m on a rotation).

use super::{read_calculix, read_matrix_market, LinearStructure};
use crate::scene::{FidelityLevel, HoldingForce, SceneError};
use crate::structure::{ModelError, StructuralModel};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use stickslip_formats::structure_file::{DofLabel, MAX_DIRECTION};

/// How the structure's files are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StructureFormat {
    /// CalculiX's `*MATRIX STORAGE` output: `job`.sti, .mas, .dof.
    Calculix,
    /// Matrix Market `.mtx` files for K and M with a DOF map file.
    MatrixMarket,
}

impl StructureFormat {
    fn word(self) -> &'static str {
        match self {
            StructureFormat::Calculix => "calculix",
            StructureFormat::MatrixMarket => "matrix-market",
        }
    }
}

/// A DOF named in the scene: node number (the file's) and direction (1 to 6: x, y, z,
/// then rotations about them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDof {
    pub node: u64,
    pub direction: u8,
}

impl SceneDof {
    pub fn label(self) -> DofLabel {
        DofLabel {
            node: self.node,
            direction: self.direction,
        }
    }
}

/// The `[structure]` section.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructureSection {
    pub format: StructureFormat,
    /// calculix: the job path without extension.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub job: Option<PathBuf>,
    /// matrix-market: K's file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<PathBuf>,
    /// matrix-market: M's file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<PathBuf>,
    /// matrix-market: a damping matrix's file; refused by the check (the integrator's
    /// damping is Rayleigh, C = a M + b K, from the scene's `[damping]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<PathBuf>,
    /// matrix-market: the DOF map file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dofs: Option<PathBuf>,
    /// The DOF where friction acts and the belt moves.
    pub contact: SceneDof,
    /// DOFs to fix that the files did not remove.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub clamped: Vec<SceneDof>,
}

/// A path field's dotted name and whether the scene gives it.
type GivenField = (&'static str, bool);

fn refused(field: &'static str, value: impl ToString, requirement: impl ToString) -> SceneError {
    SceneError::Invalid {
        field,
        value: value.to_string(),
        requirement: requirement.to_string(),
    }
}

fn check_dof(field: &'static str, dof: SceneDof) -> Result<(), SceneError> {
    if dof.node == 0 {
        return Err(refused(
            field,
            dof.label(),
            "a node number >= 1 (the file's numbering)",
        ));
    }
    if !(1..=MAX_DIRECTION).contains(&dof.direction) {
        return Err(refused(
            field,
            dof.label(),
            format!("a direction in 1..={MAX_DIRECTION} (x, y, z, then rotations about them)"),
        ));
    }
    Ok(())
}

impl StructureSection {
    /// The fields (no file opened): the format's paths present and the other format's
    /// absent, no damping file, the DOFs well formed, the contact not clamped; and what
    /// the rest of the scene must be with a user's structure: `fidelity.level =
    /// plane-stress` (meaning the full model: the modal reduction of a user's structure
    /// and `auto` are not here yet, and `beam` names the built-in beam) and
    /// `contact.holding_force = reaction` (the paper's rule uses the beam's EI).
    pub fn check(&self, level: FidelityLevel, holding: HoldingForce) -> Result<(), SceneError> {
        let format = self.format.word();
        let (needed, foreign): (&[GivenField], &[GivenField]) = match self.format {
            StructureFormat::Calculix => (
                &[("structure.job", self.job.is_some())],
                &[
                    ("structure.stiffness", self.stiffness.is_some()),
                    ("structure.mass", self.mass.is_some()),
                    ("structure.dofs", self.dofs.is_some()),
                ],
            ),
            StructureFormat::MatrixMarket => (
                &[
                    ("structure.stiffness", self.stiffness.is_some()),
                    ("structure.mass", self.mass.is_some()),
                    ("structure.dofs", self.dofs.is_some()),
                ],
                &[("structure.job", self.job.is_some())],
            ),
        };
        if let Some((field, _)) = needed.iter().find(|(_, given)| !given) {
            return Err(refused(
                field,
                "(absent)",
                format!("given with structure.format = {format}"),
            ));
        }
        if let Some((field, _)) = foreign.iter().find(|(_, given)| *given) {
            return Err(refused(
                field,
                "(given)",
                format!("absent with structure.format = {format}: it belongs to the other format"),
            ));
        }
        if let Some(path) = &self.damping {
            return Err(refused(
                "structure.damping",
                path.display(),
                "absent: a damping matrix from a file is not used yet; the scene's Rayleigh damping ([damping]: C = a M + b K) acts on the structure",
            ));
        }
        check_dof("structure.contact", self.contact)?;
        for &dof in &self.clamped {
            check_dof("structure.clamped", dof)?;
        }
        if self.clamped.contains(&self.contact) {
            return Err(refused(
                "structure.contact",
                self.contact.label(),
                "a free DOF: structure.clamped fixes it, so friction could not move it",
            ));
        }
        if level != FidelityLevel::PlaneStress {
            return Err(refused(
                "fidelity.level",
                crate::choice::Choice::name(level),
                "plane-stress with a [structure]: it means the structure's full model (modal reduction of a user's structure and auto are not here yet)",
            ));
        }
        if holding != HoldingForce::Reaction {
            return Err(refused(
                "contact.holding_force",
                crate::choice::Choice::name(holding),
                "reaction with a [structure]: the paper's rule 3 EI delta / L^3 is the built-in beam's",
            ));
        }
        Ok(())
    }

    /// Makes relative paths relative to `dir` (the scene file's directory).
    pub fn resolve_paths(&mut self, dir: &Path) {
        for path in [
            &mut self.job,
            &mut self.stiffness,
            &mut self.mass,
            &mut self.damping,
            &mut self.dofs,
        ]
        .into_iter()
        .flatten()
        {
            if path.is_relative() {
                *path = dir.join(&*path);
            }
        }
    }

    /// The files read and checked into a [`LinearStructure`].
    pub fn load(&self) -> Result<LinearStructure, ModelError> {
        let given = |p: &Option<PathBuf>| p.clone().unwrap_or_default();
        let matrices = match self.format {
            StructureFormat::Calculix => read_calculix(&given(&self.job)),
            StructureFormat::MatrixMarket => read_matrix_market(
                &given(&self.stiffness),
                &given(&self.mass),
                None,
                &given(&self.dofs),
            ),
        }
        .map_err(|e| ModelError::UserStructure(e.to_string()))?;
        let clamped: Vec<DofLabel> = self.clamped.iter().map(|d| d.label()).collect();
        LinearStructure::new(&matrices, &clamped)
            .map_err(|e| ModelError::UserStructure(e.to_string()))
    }

    /// The files' name for labels: "calculix beam" for job `dir/beam`.
    fn source(&self) -> String {
        let stem = |p: &Option<PathBuf>| {
            p.as_deref()
                .and_then(Path::file_stem)
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        };
        match self.format {
            StructureFormat::Calculix => format!("calculix {}", stem(&self.job)),
            StructureFormat::MatrixMarket => format!("matrix-market {}", stem(&self.stiffness)),
        }
    }
}

impl StructuralModel {
    /// The full model of a `[structure]`: its M and K on the free DOFs, the tip the
    /// contact DOF with weight 1.
    pub fn from_section(section: &StructureSection) -> Result<Self, ModelError> {
        let structure = section.load()?;
        let contact = section.contact.label();
        let tip = structure.index_of(contact).map_err(|_| {
            ModelError::UserStructure(format!(
                "structure.contact = {contact} is not a free DOF of the structure ({} free DOFs: not in the files' DOF map, or removed by them or by structure.clamped; friction acts on a DOF that can move)",
                structure.dofs()
            ))
        })?;
        Ok(Self {
            level: FidelityLevel::PlaneStress,
            label: format!(
                "structure, {} DOFs ({}), contact {contact}",
                structure.dofs(),
                section.source()
            ),
            mass: structure.mass().clone(),
            stiffness: structure.stiffness().clone(),
            tip: vec![(tip, 1.0)],
        })
    }
}
