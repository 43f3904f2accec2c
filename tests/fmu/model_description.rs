//! The checked-in modelDescription/*.xml are what the Rust variable tables generate, and
//! the tables are internally consistent.

use std::collections::HashSet;
use stickslip::choice::Choice;
use stickslip::friction::LawChoice;
use stickslip::scene::{
    Clamp, FidelityLevel, FrictionLawKind, HoldingForce, InitialState, ModalBasis, Scheme,
    SlidingVelocity,
};
use stickslip::simulation::ExternalCoupling;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::model::Model;
use stickslip_fmi::variables::{Access, Causality, InitialDependencies, Variable, UNITS};
use stickslip_fmi::FmuKind;

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
        // Only outputs declare dependencies, and they name inputs and parameters of the
        // table (an input at communication points, both in Initialization Mode).
        assert_eq!(
            v.depends_on.is_some(),
            v.causality == Causality::Output,
            "{}",
            v.name
        );
        let causality_of = |vr: u32| {
            variables
                .iter()
                .find(|w| w.value_reference == vr)
                .map(|w| w.causality)
        };
        if let Some(d) = &v.depends_on {
            for (vr, _) in d.inputs {
                assert_eq!(causality_of(*vr), Some(Causality::Input), "{}", v.name);
            }
            let (listed, expected) = match d.initial {
                InitialDependencies::InputsAnd(parameters) => (parameters, Causality::Parameter),
                InitialDependencies::AllParametersAnd(inputs) => (inputs, Causality::Input),
            };
            for vr in listed {
                assert_eq!(causality_of(*vr), Some(expected), "{}", v.name);
            }
        }
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

/// One `<SimpleType>` of a modelDescription: name, description and its items as
/// (name, value, description).
type SimpleType = (String, String, Vec<(String, i32, String)>);

/// The value of attribute `name` in an XML tag, unescaped.
fn attribute(tag: &str, name: &str) -> String {
    let start = tag
        .find(&format!(" {name}=\""))
        .unwrap_or_else(|| panic!("no {name} in {tag}"))
        + name.len()
        + 3;
    let end = start + tag[start..].find('"').unwrap();
    tag[start..end]
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&")
}

/// The enumeration types declared in a modelDescription, in order.
fn simple_types(xml: &str) -> Vec<SimpleType> {
    xml.split("<SimpleType ")
        .skip(1)
        .map(|block| {
            let block = &block[..block.find("</SimpleType>").unwrap()];
            let head = &block[..block.find('>').unwrap()];
            let items = block
                .split("<Item ")
                .skip(1)
                .map(|item| {
                    let tag = format!(" {}", &item[..item.find("/>").unwrap()]);
                    (
                        attribute(&tag, "name"),
                        attribute(&tag, "value").parse().unwrap(),
                        attribute(&tag, "description"),
                    )
                })
                .collect();
            let head = format!(" {head}");
            (
                attribute(&head, "name"),
                attribute(&head, "description"),
                items,
            )
        })
        .collect()
}

/// What a choice declares: its type and its values with their codes.
fn declared<T: Choice>() -> SimpleType {
    (
        T::TYPE_NAME.to_string(),
        T::TYPE_DESCRIPTION.to_string(),
        T::ALL
            .iter()
            .map(|c| (c.name().to_string(), c.code(), c.description().to_string()))
            .collect(),
    )
}

/// The FMI enumeration types of the checked-in modelDescriptions are the scene's choice
/// enums, item for item: the FMU's words are the scene file's and the command line's.
#[test]
fn the_enumeration_types_are_the_scenes_choices() {
    let read = |kind: FmuKind| {
        let path = stickslip_tests::workspace_root()
            .join("modelDescription")
            .join(format!("{}.xml", kind.model_identifier()));
        simple_types(&std::fs::read_to_string(path).unwrap())
    };
    assert_eq!(
        read(FmuKind::StickSlipBeam),
        vec![
            declared::<FrictionLawKind>(),
            declared::<ExternalCoupling>(),
            declared::<HoldingForce>(),
            declared::<SlidingVelocity>(),
            declared::<InitialState>(),
            declared::<FidelityLevel>(),
            declared::<ModalBasis>(),
            declared::<Clamp>(),
            declared::<Scheme>(),
        ]
    );
    assert_eq!(read(FmuKind::NeuralFriction), vec![declared::<LawChoice>()]);
}

/// Every enumeration variable takes each of its items and reads it back, and refuses
/// the values around them with the allowed items in the message.
fn enumerations_round_trip<M: Model>() {
    let mut model = M::with_defaults();
    for v in M::variables() {
        let Access::Enumeration { kind, .. } = &v.access else {
            continue;
        };
        for (value, _, _) in kind.items() {
            v.set_integer(&mut model, value).unwrap();
            assert_eq!(v.get_integer(&model), value, "{}", v.name);
        }
        for bad in [0, kind.len as i32 + 1] {
            let error = v.set_integer(&mut model, bad).unwrap_err().to_string();
            assert!(error.contains("allowed: 1 = "), "{}: {error}", v.name);
        }
    }
}

#[test]
fn enumeration_variables_take_and_read_back_every_item() {
    enumerations_round_trip::<StickSlipBeam>();
    enumerations_round_trip::<NeuralFriction>();
}
