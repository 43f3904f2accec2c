//! Variables by name through the `fmi` crate's importer, as a tool reads them from the
//! packaged modelDescription.xml. Shared by these tests and the fmi_overhead bench
//! (which includes this file by path).

use fmi::fmi2::import::Fmi2Import;
use fmi::traits::FmiImport;

/// The value reference of variable `name` in the FMU `import` read.
pub fn vr(import: &Fmi2Import, name: &str) -> u32 {
    import
        .model_description()
        .model_variable_by_name(name)
        .unwrap_or_else(|e| panic!("variable {name}: {e}"))
        .value_reference
}
