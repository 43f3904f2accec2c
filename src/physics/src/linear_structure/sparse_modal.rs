//! The modal model of a structure too wide for the band, reduced from its sparse
//! matrices (issue 35 item 2): the lowest modes by shift-invert Lanczos on faer's factor
//! of K (`modal::lanczos`, with M's product from [`SymSparseMatrix`]) plus the static
//! correction psi = K^-1 c at the contact DOF, projected as `modal::reduce` projects a
//! band model (`modal::reduced_model`, one code for both). The result is the small
//! diagonal [`StructuralModel`] of the modal level (M = I, K = diag(omega^2), the tip
//! projected), which the time loop runs as any modal model; the full matrices are not
//! kept.
//!
//! [`SymSparseMatrix`]: super::sparse::SymSparseMatrix

use super::scene_model::{not_free_contact, read_section, sensor_indices};
use super::sparse::SparseStructure;
use super::{LinearStructure, StructureError};
use crate::modal;
use crate::structure::{ModelError, StructuralModel};
use crate::user_structure::StructureSection;
use stickslip_formats::structure_file::DofLabel;

/// The modal model of `structure` with its lowest `modes` modes, plus the static shape
/// under a unit force at `contact` when `static_correction` is set; the contact DOF is
/// the tip (weight 1), `label` names the full model in the reduced one's label.
pub fn reduce(
    structure: &SparseStructure,
    contact: DofLabel,
    modes: usize,
    static_correction: bool,
    label: &str,
) -> Result<StructuralModel, ModelError> {
    reduce_observing(structure, contact, &[], modes, static_correction, label)
}

/// [`reduce`], the DOFs of free indices `sensors` observed as the model's sensors.
fn reduce_observing(
    structure: &SparseStructure,
    contact: DofLabel,
    sensors: &[usize],
    modes: usize,
    static_correction: bool,
    label: &str,
) -> Result<StructuralModel, ModelError> {
    if structure.damping().is_some() {
        return Err(modal::damping_not_projected());
    }
    let tip = [(contact_index(structure, contact)?, 1.0)];
    let sensors: Vec<_> = sensors.iter().map(|&i| vec![(i, 1.0)]).collect();
    let eigen = structure
        .lowest_modes(modes)
        .map_err(|e| ModelError::UserStructure(e.to_string()))?;
    let static_shape = static_correction.then(|| {
        let mut c = vec![0.0; structure.dofs()];
        c[tip[0].0] = 1.0;
        structure.refined_solve(&c)
    });
    modal::reduced_model(
        eigen,
        static_shape,
        structure.mass(),
        (&tip, &sensors),
        label,
    )
}

fn contact_index(structure: &SparseStructure, contact: DofLabel) -> Result<usize, ModelError> {
    structure.index_of(contact).map_err(|_| {
        ModelError::UserStructure(format!(
            "structure.contact = {contact} is not a free DOF of the structure ({} free DOFs: not in the files' DOF map, or removed by them or by structure.clamped; friction acts on a DOF that can move)",
            structure.dofs()
        ))
    })
}

/// The modal model of a scene's `[structure]`: reduced from the band model
/// (`modal::reduce` on `StructuralModel::from_section`'s full model, bit for bit what
/// that gives) where the band holds the structure, and from the sparse matrices where
/// the band refuses it (a 3D solid).
pub fn reduce_section(
    section: &StructureSection,
    modes: usize,
    static_correction: bool,
) -> Result<StructuralModel, ModelError> {
    let files = read_section(section)?;
    match LinearStructure::new(&files.matrices, &files.clamped) {
        Err(StructureError::BandTooWide { .. }) => {
            let structure = SparseStructure::new(&files.matrices, &files.clamped)
                .map_err(|e| ModelError::UserStructure(e.to_string()))?;
            let contact = files.points.contact;
            if structure.index_of(contact).is_err() {
                return Err(not_free_contact(section, contact, structure.dofs()));
            }
            let label = format!(
                "structure, {} DOFs ({}), contact {contact}, sparse",
                structure.dofs(),
                section.source()
            );
            let sensors = sensor_indices(section, &files.points, structure.dofs(), |label| {
                structure.index_of(label).ok()
            })?;
            reduce_observing(
                &structure,
                contact,
                &sensors,
                modes,
                static_correction,
                &label,
            )
        }
        Err(e) => Err(ModelError::UserStructure(e.to_string())),
        Ok(structure) => modal::reduce(
            &StructuralModel::from_structure(&structure, section, &files.points)?,
            modes,
            static_correction,
        ),
    }
}
