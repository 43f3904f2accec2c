//! modelDescription.xml, generated from a model's variable table (FMI 2.0 standard,
//! section 2.2). The copies in `modelDescription/` are checked in and a test keeps them
//! equal to what this writes.
//!
//! - Start values are read from `Model::with_defaults()`, so they are the defaults the
//!   Rust code uses.
//! - Outputs are `initial="calculated"`; ModelStructure lists every output under
//!   `Outputs` and under `InitialUnknowns` (no calculated parameters, no states), each
//!   with the dependencies its table entry declares (`variables::Dependencies`):
//!   `Outputs` with the inputs that reach it directly and their `dependenciesKind`,
//!   `InitialUnknowns` with the inputs and parameters it is computed from (there only
//!   "dependent" is meaningful, so no `dependenciesKind`).
//! - A choice (`Access::Choice`) is an `<Integer min="1" max="N">` whose description ends
//!   with its codes, "[1 = exponential, 2 = coulomb, ...]", and whose codes, words and
//!   descriptions are listed for programs in `<VendorAnnotations><Tool name="stickslip">`
//!   ([`CHOICES_TOOL`]). FMI Enumerations are not used: libcosim and Ecos ignore them.
//! - No generation date, so that the file is reproducible byte for byte.
//!
//! `parts` writes what both versions share, `fmi2` and `fmi3` each version's document.

pub mod described;
mod fmi2;
mod fmi3;
mod parts;

use crate::model::Model;
use described::Described;
use fmi2::{body, body_of};
use fmi3::{body3, body3_of};

pub use fmi3::TIME_VALUE_REFERENCE;
pub use parts::{
    description, output_dependencies, unit_element, IndexedDependencies, LogCategory, CHOICES_TOOL,
    LOG_CATEGORIES,
};

/// FNV-1a (128 bit) of `bytes` as a GUID.
pub(crate) fn hash_guid(bytes: impl AsRef<[u8]>) -> String {
    let mut h: u128 = 0x6c62272e07bb014262b821756295c58d;
    for &byte in bytes.as_ref() {
        h ^= byte as u128;
        h = h.wrapping_mul(0x0000000001000000000000000000013B);
    }
    let hex = format!("{h:032x}");
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

/// The GUID of model `M`: a hash of its description without the GUID.
pub fn guid<M: Model>() -> String {
    Described::<M>::built_in().guid()
}

impl<M: Model> Described<M> {
    /// Its GUID (and FMI 3.0 instantiationToken): a hash of its FMI 2.0 description
    /// without the GUID.
    pub fn guid(&self) -> String {
        hash_guid(body_of(self, ""))
    }

    /// Its FMI 2.0 description without the GUID (what the GUID hashes).
    pub fn body_without_guid(&self) -> String {
        body_of(self, "")
    }

    /// Its FMI 2.0 modelDescription.xml with `guid`.
    pub fn generate_with(&self, guid: &str) -> String {
        body_of(self, guid)
    }

    /// Its FMI 3.0 modelDescription.xml with instantiationToken `token`.
    pub fn generate3_with(&self, token: &str) -> String {
        body3_of(self, token)
    }
}

/// modelDescription.xml of model `M`.
pub fn generate<M: Model>() -> String {
    body::<M>(&guid::<M>())
}

/// The FMI 3.0 modelDescription.xml of model `M` (instantiation token: [`guid`]).
pub fn generate3<M: Model>() -> String {
    body3::<M>(&guid::<M>())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_has_a_value_reference_of_its_own() {
        use crate::{beam::StickSlipBeam, friction::NeuralFriction};
        assert!(StickSlipBeam::variables()
            .iter()
            .all(|v| v.value_reference != TIME_VALUE_REFERENCE));
        assert!(NeuralFriction::variables()
            .iter()
            .all(|v| v.value_reference != TIME_VALUE_REFERENCE));
    }

    #[test]
    fn guid_changes_with_content() {
        assert_ne!(hash_guid("a"), hash_guid("b"));
        assert_eq!(hash_guid("a").len(), 38);
    }
}
