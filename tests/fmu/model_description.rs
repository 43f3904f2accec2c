//! The checked-in modelDescription/*.xml are what the Rust variable tables generate, and
//! the tables are internally consistent.

use std::collections::HashSet;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::variables::{Access, Causality, Variable, UNITS};
use stickslip_fmi::{FmuKind, Model};

#[test]
fn checked_in_descriptions_match_the_generated_ones() {
    for kind in FmuKind::ALL {
        let path = stickslip_tests::workspace_root()
            .join("modelDescription")
            .join(format!("{}.xml", kind.model_identifier()));
        let checked_in =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            checked_in == kind.model_description(),
            "{} drifted from the Rust tables; run `cargo run --release -p fmu-build -- --update-model-descriptions`",
            path.display()
        );
    }
}

fn check_table<M: Model>(variables: &[Variable<M>]) {
    let names: HashSet<&str> = variables.iter().map(|v| v.name).collect();
    assert_eq!(names.len(), variables.len(), "duplicate names");
    let refs: HashSet<u32> = variables.iter().map(|v| v.value_reference).collect();
    assert_eq!(refs.len(), variables.len(), "duplicate value references");
    for v in variables {
        if let Access::Real {
            unit: Some(unit), ..
        } = &v.access
        {
            assert!(
                UNITS.iter().any(|u| u.name == *unit),
                "{}: unit {unit}",
                v.name
            );
        }
        assert_eq!(
            v.access.is_settable(),
            v.causality != Causality::Output,
            "{}",
            v.name
        );
        assert!(!v.description.is_empty(), "{}", v.name);
    }
}

#[test]
fn tables_have_unique_names_and_references_and_known_units() {
    check_table(StickSlipBeam::variables());
    check_table(NeuralFriction::variables());
}

#[test]
fn guids_differ_and_are_stable() {
    let a = FmuKind::StickSlipBeam.guid();
    let b = FmuKind::NeuralFriction.guid();
    assert_ne!(a, b);
    assert_eq!(a, FmuKind::StickSlipBeam.guid());
    assert_eq!(FmuKind::from_guid(&b), Some(FmuKind::NeuralFriction));
    assert_eq!(
        FmuKind::from_guid("{00000000-0000-0000-0000-000000000000}"),
        None
    );
}

#[test]
fn structure_lists_every_output_as_output_and_initial_unknown() {
    let xml = FmuKind::StickSlipBeam.model_description();
    let outputs = StickSlipBeam::variables()
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .count();
    let structure = &xml[xml.find("<ModelStructure>").unwrap()..];
    assert_eq!(structure.matches("<Unknown ").count(), 2 * outputs);
    assert!(xml.contains(r#"<DefaultExperiment startTime="0.0" stopTime="1.2""#));
    assert!(xml.contains(r#"canHandleVariableCommunicationStepSize="true""#));
}
