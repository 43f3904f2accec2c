//! A scene's `[structure]` (`crate::user_structure`) as the model the time loop runs: its
//! files read and checked into a [`LinearStructure`], the full model with the contact
//! DOF as the tip and the sensors' DOFs observed.

use super::read::{read_calculix, read_matrix_market};
use super::LinearStructure;
use crate::scene::FidelityLevel;
use crate::structure::{ModelError, StructuralModel};
use crate::user_structure::{PointDof, PointLabels, StructureFormat, StructureSection};
use std::path::PathBuf;
use stickslip_formats::structure_file::{DofLabel, StructureMatrices};

/// What a `[structure]`'s files give: the matrices, every DOF to clamp (the section's
/// `clamped` labels and, for a Gmsh mesh, the nodes of its `clamped_groups`: the one
/// place the two are joined) and the contact's and sensors' labels (a Gmsh group's node
/// found in the mesh).
#[derive(Clone, Debug)]
pub struct SectionFiles {
    pub matrices: StructureMatrices,
    pub clamped: Vec<DofLabel>,
    pub points: PointLabels,
}

/// The files of `section` read: the reader behind [`load`] and
/// `sparse_modal::reduce_section`.
pub fn read_section(section: &StructureSection) -> Result<SectionFiles, ModelError> {
    let given = |p: &Option<PathBuf>| p.clone().unwrap_or_default();
    let mut clamped: Vec<DofLabel> = section.clamped.iter().map(|d| d.label()).collect();
    let user = |e: &dyn std::fmt::Display| ModelError::UserStructure(e.to_string());
    // Only a Gmsh mesh has groups (`check_fields` refuses one elsewhere).
    let no_groups = || {
        section.point_labels(|field, group| {
            Err(ModelError::UserStructure(format!(
                "{field}: group '{group}': only a Gmsh mesh has physical groups"
            )))
        })
    };
    let (matrices, points) = match section.format {
        StructureFormat::Calculix => (
            read_calculix(&given(&section.job)).map_err(|e| user(&e))?,
            no_groups()?,
        ),
        StructureFormat::MatrixMarket => (
            read_matrix_market(
                &given(&section.stiffness),
                &given(&section.mass),
                section.damping.as_deref(),
                &given(&section.dofs),
            )
            .map_err(|e| user(&e))?,
            no_groups()?,
        ),
        StructureFormat::Gmsh => {
            // The mesh assembled in plane stress; its clamped groups join structure.clamped.
            let (matrices, by_group, points) =
                crate::plane_mesh::read_section(section).map_err(|e| user(&e))?;
            clamped.retain(|d| !by_group.contains(d));
            clamped.extend(by_group);
            (matrices, points)
        }
    };
    Ok(SectionFiles {
        matrices,
        clamped,
        points,
    })
}

/// The files of `section` read and checked into a [`LinearStructure`], with the
/// contact's and sensors' labels.
pub fn load_with_points(
    section: &StructureSection,
) -> Result<(LinearStructure, PointLabels), ModelError> {
    let files = read_section(section)?;
    let structure = LinearStructure::new(&files.matrices, &files.clamped)
        .map_err(|e| ModelError::UserStructure(e.to_string()))?;
    Ok((structure, files.points))
}

/// The files of `section` read and checked into a [`LinearStructure`].
pub fn load(section: &StructureSection) -> Result<LinearStructure, ModelError> {
    Ok(load_with_points(section)?.0)
}

impl StructuralModel {
    /// The full model of a `[structure]`: its M and K on the free DOFs, the tip the
    /// contact DOF with weight 1.
    pub fn from_section(section: &StructureSection) -> Result<Self, ModelError> {
        let (structure, points) = load_with_points(section)?;
        Self::from_structure(&structure, section, &points)
    }

    /// The full model of `structure`, read from `section` (its contact's and sensors'
    /// labels `points`): the contact DOF the tip.
    pub fn from_structure(
        structure: &LinearStructure,
        section: &StructureSection,
        points: &PointLabels,
    ) -> Result<Self, ModelError> {
        let contact = points.contact;
        let tip = structure
            .index_of(contact)
            .map_err(|_| not_free_contact(section, contact, structure.dofs()))?;
        let sensors = sensor_indices(section, points, structure.dofs(), |label| {
            structure.index_of(label).ok()
        })?
        .into_iter()
        .map(|i| vec![(i, 1.0)])
        .collect();
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
            damping: structure.damping().cloned(),
            sensors,
        })
    }
}

/// The refusal of a contact DOF `contact` that is not among the structure's `dofs` free
/// DOFs (named as the scene names it, and by its node where a group gave it).
pub(super) fn not_free_contact(
    section: &StructureSection,
    contact: DofLabel,
    dofs: usize,
) -> ModelError {
    ModelError::UserStructure(format!(
        "structure.contact = {} is not a free DOF of the structure ({dofs} free DOFs: not in the files' DOF map, or removed by them or by structure.clamped; friction acts on a DOF that can move)",
        named(&section.contact, contact)
    ))
}

/// A scene's DOF as the scene names it, with its node where a group gave it.
fn named(dof: &PointDof, label: DofLabel) -> String {
    match dof.group {
        Some(_) => format!("{dof} (node {})", label.node),
        None => label.to_string(),
    }
}

/// The free-DOF index of each of `section`'s sensors (labels in `points`; `index_of`
/// gives the index by label, or None for a DOF the structure does not have free), or the
/// first sensor whose DOF is not free, named, among `dofs` free DOFs.
pub(super) fn sensor_indices(
    section: &StructureSection,
    points: &PointLabels,
    dofs: usize,
    index_of: impl Fn(DofLabel) -> Option<usize>,
) -> Result<Vec<usize>, ModelError> {
    section
        .sensors
        .iter()
        .zip(&points.sensors)
        .map(|(sensor, &label)| {
            index_of(label).ok_or_else(|| {
                ModelError::UserStructure(format!(
                    "structure.sensors '{}' = {} is not a free DOF of the structure ({dofs} free DOFs: not in the files' DOF map, or removed by them or by structure.clamped; a sensor reads a DOF that can move)",
                    sensor.name,
                    named(&sensor.dof(), label)
                ))
            })
        })
        .collect()
}
