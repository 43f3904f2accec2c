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

use super::scene_model::{not_free_contact, read_section, sensor_indices, SectionFiles};
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
    Ok(reduce_at_counts(
        structure,
        contact,
        sensors,
        &[(modes, static_correction)],
        label,
    )?
    .pop()
    .expect("one model per count"))
}

/// [`reduce_observing`] for each (mode count, static correction) of `wanted`, from one
/// Lanczos recurrence (`modal::lanczos_counts`, that of the largest count) and one
/// static shape: each model is the one [`reduce_observing`] gives for it alone, bit for
/// bit.
fn reduce_at_counts(
    structure: &SparseStructure,
    contact: DofLabel,
    sensors: &[usize],
    wanted: &[(usize, bool)],
    label: &str,
) -> Result<Vec<StructuralModel>, ModelError> {
    if structure.damping().is_some() {
        return Err(modal::damping_not_projected());
    }
    let tip = [(contact_index(structure, contact)?, 1.0)];
    let sensors: Vec<_> = sensors.iter().map(|&i| vec![(i, 1.0)]).collect();
    let mut counts: Vec<usize> = wanted.iter().map(|&(k, _)| k).collect();
    counts.sort_unstable();
    counts.dedup();
    let eigen = structure
        .lowest_modes_at(&counts)
        .map_err(|e| ModelError::UserStructure(e.to_string()))?;
    let static_shape = wanted.iter().any(|&(_, c)| c).then(|| {
        let mut c = vec![0.0; structure.dofs()];
        c[tip[0].0] = 1.0;
        structure.refined_solve(&c)
    });
    wanted
        .iter()
        .map(|&(modes, correction)| {
            let at = counts
                .binary_search(&modes)
                .expect("every count was reduced");
            modal::reduced_model(
                eigen[at].clone(),
                static_shape.clone().filter(|_| correction),
                structure.mass(),
                (&tip, &sensors),
                label,
            )
        })
        .collect()
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
            SparseSection::new(section, &files)?.model(modes, static_correction)
        }
        Err(e) => Err(ModelError::UserStructure(e.to_string())),
        Ok(structure) => modal::reduce(
            &StructuralModel::from_structure(&structure, section, &files.points)?,
            modes,
            static_correction,
        ),
    }
}

/// A scene's `[structure]` checked and factorised sparse ([`SparseStructure`]), with its
/// contact and sensors: what [`reduce_section`] reduces a structure too wide for the
/// band from, and what `auto::structure` reduces such a structure from at every mode
/// count of its ladder at once ([`Self::models`], the same bits as [`Self::model`] per
/// count).
pub struct SparseSection {
    structure: SparseStructure,
    contact: DofLabel,
    sensors: Vec<usize>,
    label: String,
}

impl SparseSection {
    /// The structure of `section` from its files as `scene_model::read_section` read
    /// them, stored and factorised sparse whatever its band.
    pub fn new(section: &StructureSection, files: &SectionFiles) -> Result<Self, ModelError> {
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
        Ok(Self {
            structure,
            contact,
            sensors,
            label,
        })
    }

    /// [`SparseSection::new`] of a section's files as `read_section` reads them.
    pub fn read(section: &StructureSection) -> Result<Self, ModelError> {
        Self::new(section, &read_section(section)?)
    }

    /// The structure's free DOFs.
    pub fn dofs(&self) -> usize {
        self.structure.dofs()
    }

    /// The checked, factorised structure.
    pub fn structure(&self) -> &SparseStructure {
        &self.structure
    }

    /// The modal model with the lowest `modes` modes, plus the static correction at the
    /// contact with `static_correction`: what `fidelity.level = modal` runs.
    pub fn model(
        &self,
        modes: usize,
        static_correction: bool,
    ) -> Result<StructuralModel, ModelError> {
        reduce_observing(
            &self.structure,
            self.contact,
            &self.sensors,
            modes,
            static_correction,
            &self.label,
        )
    }

    /// [`Self::model`] for each (mode count, static correction) of `wanted`, from one
    /// Lanczos recurrence (that of the largest count) and one static shape; each bit for
    /// bit [`Self::model`]'s.
    pub fn models(&self, wanted: &[(usize, bool)]) -> Result<Vec<StructuralModel>, ModelError> {
        reduce_at_counts(
            &self.structure,
            self.contact,
            &self.sensors,
            wanted,
            &self.label,
        )
    }
}
