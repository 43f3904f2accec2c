//! A scene's `[structure]` (`crate::user_structure`) as the model the time loop runs: its
//! files read and checked into a [`LinearStructure`], the full model with the contact
//! DOF as the tip and the sensors' DOFs observed.

use super::read::{read_calculix, read_matrix_market};
use super::LinearStructure;
use crate::scene::FidelityLevel;
use crate::structure::{ModelError, StructuralModel};
use crate::user_structure::{StructureFormat, StructureSection};
use std::path::PathBuf;
use stickslip_formats::structure_file::{DofLabel, StructureMatrices};

/// The matrices of `section` read from its files, and every DOF to clamp: the section's
/// `clamped` labels and, for a Gmsh mesh, the nodes of its `clamped_groups` (the one
/// place the two are joined). The reader behind [`load`] and
/// `sparse_modal::reduce_section`.
pub fn read_section(
    section: &StructureSection,
) -> Result<(StructureMatrices, Vec<DofLabel>), ModelError> {
    let given = |p: &Option<PathBuf>| p.clone().unwrap_or_default();
    let mut clamped: Vec<DofLabel> = section.clamped.iter().map(|d| d.label()).collect();
    let matrices = match section.format {
        StructureFormat::Calculix => read_calculix(&given(&section.job)),
        StructureFormat::MatrixMarket => read_matrix_market(
            &given(&section.stiffness),
            &given(&section.mass),
            section.damping.as_deref(),
            &given(&section.dofs),
        ),
        StructureFormat::Gmsh => {
            // The mesh assembled in plane stress; its clamped groups join structure.clamped.
            let (matrices, by_group) = crate::plane_mesh::read_section(section)
                .map_err(|e| ModelError::UserStructure(e.to_string()))?;
            clamped.retain(|d| !by_group.contains(d));
            clamped.extend(by_group);
            Ok(matrices)
        }
    }
    .map_err(|e| ModelError::UserStructure(e.to_string()))?;
    Ok((matrices, clamped))
}

/// The files of `section` read and checked into a [`LinearStructure`].
pub fn load(section: &StructureSection) -> Result<LinearStructure, ModelError> {
    let (matrices, clamped) = read_section(section)?;
    LinearStructure::new(&matrices, &clamped).map_err(|e| ModelError::UserStructure(e.to_string()))
}

impl StructuralModel {
    /// The full model of a `[structure]`: its M and K on the free DOFs, the tip the
    /// contact DOF with weight 1.
    pub fn from_section(section: &StructureSection) -> Result<Self, ModelError> {
        Self::from_structure(&load(section)?, section)
    }

    /// The full model of `structure`, read from `section`: the contact DOF the tip.
    pub fn from_structure(
        structure: &LinearStructure,
        section: &StructureSection,
    ) -> Result<Self, ModelError> {
        let contact = section.contact.label();
        let tip = structure.index_of(contact).map_err(|_| {
            ModelError::UserStructure(format!(
                "structure.contact = {contact} is not a free DOF of the structure ({} free DOFs: not in the files' DOF map, or removed by them or by structure.clamped; friction acts on a DOF that can move)",
                structure.dofs()
            ))
        })?;
        let sensors = sensor_indices(section, structure.dofs(), |label| {
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

/// The free-DOF index of each of `section`'s sensors (`index_of` gives it by label, or
/// None for a DOF the structure does not have free), or the first sensor whose DOF is not
/// free, named, among `dofs` free DOFs.
pub(super) fn sensor_indices(
    section: &StructureSection,
    dofs: usize,
    index_of: impl Fn(DofLabel) -> Option<usize>,
) -> Result<Vec<usize>, ModelError> {
    section
        .sensors
        .iter()
        .map(|sensor| {
            let label = sensor.dof().label();
            index_of(label).ok_or_else(|| {
                ModelError::UserStructure(format!(
                    "structure.sensors '{}' = {label} is not a free DOF of the structure ({dofs} free DOFs: not in the files' DOF map, or removed by them or by structure.clamped; a sensor reads a DOF that can move)",
                    sensor.name
                ))
            })
        })
        .collect()
}
