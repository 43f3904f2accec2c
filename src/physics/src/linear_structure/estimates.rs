//! A `[structure]`'s own numbers, from its matrices rather than beam theory: what
//! `stickslip static` and `stickslip estimates` report for a scene with the section
//! (docs/structures.md, "static and estimates on a user's structure").
//!
//! Both solve the structure itself, whatever `fidelity.level` says: the band model
//! where the band holds it, faer's sparse factor where it does not (a 3D solid), so a
//! structure too wide for the band's full model still has its statics and modes. The
//! static answer is exact at any DOF (K u = f, one step of iterative refinement); the
//! modes are the shift-invert Lanczos pairs the modal fidelity reduces with.

use super::scene_model::{not_free_contact, read_section, sensor_indices};
use super::sparse::SparseStructure;
use super::{LinearStructure, StructureError};
use crate::modal::Modes;
use crate::structure::ModelError;
use crate::user_structure::{PointLabels, StructureSection};
use stickslip_formats::structure_file::DofLabel;

/// The structure's static response to a force at its contact DOF.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticResponse {
    /// What was solved: "structure, N DOFs (source), contact node X direction D".
    pub label: String,
    /// The force at the contact DOF, in its direction (N; N m on a rotation).
    pub load: f64,
    /// The contact DOF's displacement (m; rad on a rotation).
    pub contact: f64,
    /// Each sensor's name and reading, in the section's order.
    pub sensors: Vec<(String, f64)>,
}

/// The structure's lowest modes seen from the contact DOF, and its static compliance
/// there.
#[derive(Clone, Debug, PartialEq)]
pub struct StructureEstimates {
    /// As [`StaticResponse::label`].
    pub label: String,
    /// The lowest angular frequencies omega_j (rad/s), ascending.
    pub omega: Vec<f64>,
    /// phi_j(contact)^2 of each M-normalised mode (1/kg): mode j seen at the contact is
    /// a mass 1 / phi_j(contact)^2 on a spring omega_j^2 / phi_j(contact)^2 (for the
    /// uniform cantilever's tip, 4 / (rho A L) for every mode).
    pub contact_participation: Vec<f64>,
    /// u_contact under a unit force at the contact (m/N).
    pub contact_compliance: f64,
}

/// The structure of a section, on the solver that holds it.
enum Solver {
    Band(LinearStructure),
    Sparse(SparseStructure),
}

impl Solver {
    fn load(section: &StructureSection) -> Result<(Self, PointLabels, String), ModelError> {
        let files = read_section(section)?;
        let user = |e: StructureError| ModelError::UserStructure(e.to_string());
        let (solver, kind) = match LinearStructure::new(&files.matrices, &files.clamped) {
            Ok(s) => (Solver::Band(s), ""),
            Err(StructureError::BandTooWide { .. }) => (
                Solver::Sparse(
                    SparseStructure::new(&files.matrices, &files.clamped).map_err(user)?,
                ),
                ", sparse",
            ),
            Err(e) => return Err(user(e)),
        };
        let contact = files.points.contact;
        let label = format!(
            "structure, {} DOFs ({}), contact {contact}{kind}",
            solver.dofs(),
            section.source()
        );
        Ok((solver, files.points, label))
    }

    fn dofs(&self) -> usize {
        match self {
            Solver::Band(s) => s.dofs(),
            Solver::Sparse(s) => s.dofs(),
        }
    }

    fn index_of(&self, label: DofLabel) -> Option<usize> {
        match self {
            Solver::Band(s) => s.index_of(label).ok(),
            Solver::Sparse(s) => s.index_of(label).ok(),
        }
    }

    fn static_displacement(&self, load: &[(DofLabel, f64)]) -> Result<Vec<f64>, ModelError> {
        match self {
            Solver::Band(s) => s.static_displacement(load),
            Solver::Sparse(s) => s.static_displacement(load),
        }
        .map_err(|e| ModelError::UserStructure(e.to_string()))
    }

    fn lowest_modes(&self, count: usize) -> Result<Modes, ModelError> {
        match self {
            Solver::Band(s) => s.lowest_modes(count),
            Solver::Sparse(s) => s.lowest_modes(count),
        }
        .map_err(|e| ModelError::UserStructure(e.to_string()))
    }

    /// The contact's free index, or the scene's refusal of a contact that is not free.
    fn contact_index(
        &self,
        section: &StructureSection,
        contact: DofLabel,
    ) -> Result<usize, ModelError> {
        self.index_of(contact)
            .ok_or_else(|| not_free_contact(section, contact, self.dofs()))
    }
}

/// The static displacement of `section`'s structure under the force `load` at its
/// contact DOF: the contact's and each sensor's.
pub fn static_response(
    section: &StructureSection,
    load: f64,
) -> Result<StaticResponse, ModelError> {
    let (solver, points, label) = Solver::load(section)?;
    let contact = solver.contact_index(section, points.contact)?;
    let sensors = sensor_indices(section, &points, solver.dofs(), |l| solver.index_of(l))?;
    let u = solver.static_displacement(&[(points.contact, load)])?;
    Ok(StaticResponse {
        label,
        load,
        contact: u[contact],
        sensors: section
            .sensors
            .iter()
            .zip(sensors)
            .map(|(s, i)| (s.name.clone(), u[i]))
            .collect(),
    })
}

/// The lowest `count` modes of `section`'s structure (fewer if it has fewer DOFs) seen
/// from its contact DOF, and its static compliance there.
pub fn structure_estimates(
    section: &StructureSection,
    count: usize,
) -> Result<StructureEstimates, ModelError> {
    let (solver, points, label) = Solver::load(section)?;
    let contact = solver.contact_index(section, points.contact)?;
    let modes = solver.lowest_modes(count.min(solver.dofs()))?;
    let u = solver.static_displacement(&[(points.contact, 1.0)])?;
    Ok(StructureEstimates {
        label,
        omega: modes.eigenvalues.iter().map(|w2| w2.sqrt()).collect(),
        contact_participation: modes.vectors.iter().map(|v| v[contact].powi(2)).collect(),
        contact_compliance: u[contact],
    })
}
