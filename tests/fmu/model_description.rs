//! The checked-in modelDescription/*.xml are what the Rust variable tables generate, and
//! the tables are internally consistent.

use std::collections::HashSet;
use stickslip::choice::Choice;
use stickslip::friction::rate_and_state::StateEvolution;
use stickslip::friction::FrictionLawKind;
use stickslip::neural::inference::Inference;
use stickslip::scene::{
    Clamp, DampingPhase, FidelityLevel, FirstSlipStep, HoldingForce, InitialState, ModalBasis,
    Scheme, SlidingVelocity, SlipForce, TipVelocity,
};
use stickslip::simulation::ExternalCoupling;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::friction::StateVelocity;
use stickslip_fmi::model::Model;
use stickslip_fmi::model_description::CHOICES_TOOL;
use stickslip_fmi::variables::{
    Access, ArrayVariable, Causality, InitialDependencies, Variable, UNITS,
};
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

/// The FMI 3.0 copies (`modelDescription/3.0/`) too: generated from the same tables.
#[test]
fn checked_in_fmi3_descriptions_match_the_generated_ones() {
    for kind in FmuKind::ALL {
        let path = stickslip_tests::workspace_root()
            .join("modelDescription")
            .join("3.0")
            .join(format!("{}.xml", kind.model_identifier()));
        let checked_in =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            checked_in == kind.model_description3(),
            "{} drifted from the Rust tables; run `cargo run --release -p fmu-build -- --update-model-descriptions`",
            path.display()
        );
    }
}

/// Both versions describe the same variables: every FMI 2.0 ScalarVariable's name and
/// value reference appear in the FMI 3.0 description, in the same order, except the
/// elements of an array, which FMI 3.0 replaces by the array (at its first element's
/// place); FMI 3.0 adds `time`. The instantiation token is the GUID.
#[test]
fn fmi3_descriptions_have_the_fmi2_variables() {
    for kind in FmuKind::ALL {
        let arrays = match kind {
            FmuKind::StickSlipBeam => StickSlipBeam::arrays(),
            FmuKind::NeuralFriction => NeuralFriction::arrays(),
        };
        let (v2, v3) = (kind.model_description(), kind.model_description3());
        let pairs = |xml: &str| -> Vec<String> {
            xml.lines()
                .filter(|l| l.contains(" valueReference=") && l.contains(" name="))
                .map(|l| {
                    let attr = |a: &str| {
                        let start = l.find(&format!(" {a}=\"")).unwrap() + a.len() + 3;
                        l[start..start + l[start..].find('"').unwrap()].to_string()
                    };
                    format!("{} {}", attr("name"), attr("valueReference"))
                })
                .collect()
        };
        let mut expected: Vec<String> = pairs(&v2)
            .into_iter()
            .filter_map(|pair| {
                let vr: u32 = pair.rsplit(' ').next().unwrap().parse().unwrap();
                match ArrayVariable::containing(arrays, vr) {
                    None => Some(pair),
                    Some((array, 1)) => Some(format!("{} {}", array.name, array.value_reference)),
                    Some(_) => None,
                }
            })
            .collect();
        expected.insert(0, "time 0".into());
        assert_eq!(pairs(&v3), expected, "{kind:?}");
        assert!(v3.contains(&format!("instantiationToken=\"{}\"", kind.guid())));
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

/// One `<Choice>` of the `stickslip` tool annotation: variable, type name, type
/// description and the items as (word, code, description).
type Declared = (String, String, String, Vec<(String, i32, String)>);

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

/// The choices listed under `<VendorAnnotations><Tool name="stickslip"><Choices>`, in
/// order.
fn annotated_choices(xml: &str) -> Vec<Declared> {
    let tool = format!(r#"<Tool name="{CHOICES_TOOL}">"#);
    let start = xml.find(&tool).expect("no stickslip tool annotation");
    let block = &xml[start..start + xml[start..].find("</Tool>").unwrap()];
    block
        .split("<Choice ")
        .skip(1)
        .map(|choice| {
            let choice = &choice[..choice.find("</Choice>").unwrap()];
            let head = format!(" {}", &choice[..choice.find('>').unwrap()]);
            let items = choice
                .split("<Item ")
                .skip(1)
                .map(|item| {
                    let tag = format!(" {}", &item[..item.find("/>").unwrap()]);
                    (
                        attribute(&tag, "name"),
                        attribute(&tag, "code").parse().unwrap(),
                        attribute(&tag, "description"),
                    )
                })
                .collect();
            (
                attribute(&head, "variable"),
                attribute(&head, "type"),
                attribute(&head, "description"),
                items,
            )
        })
        .collect()
}

/// What the choice `T` of variable `variable` declares: its type and its values with
/// their codes.
fn declared<T: Choice>(variable: &str) -> Declared {
    (
        variable.to_string(),
        T::TYPE_NAME.to_string(),
        T::TYPE_DESCRIPTION.to_string(),
        T::ALL
            .iter()
            .map(|c| (c.name().to_string(), c.code(), c.description().to_string()))
            .collect(),
    )
}

fn checked_in(kind: FmuKind) -> String {
    let path = stickslip_tests::workspace_root()
        .join("modelDescription")
        .join(format!("{}.xml", kind.model_identifier()));
    std::fs::read_to_string(path).unwrap()
}

/// The choices of the checked-in modelDescriptions are the scene's choice enums, item
/// for item: the FMU's words are the scene file's and the command line's.
#[test]
fn the_annotated_choices_are_the_scenes_choices() {
    assert_eq!(
        annotated_choices(&checked_in(FmuKind::StickSlipBeam)),
        vec![
            declared::<FrictionLawKind>("friction.law"),
            declared::<ExternalCoupling>("external.coupling"),
            declared::<Inference>("friction.inference"),
            declared::<HoldingForce>("contact.holding_force"),
            declared::<SlidingVelocity>("contact.sliding_velocity"),
            declared::<InitialState>("contact.initial_state"),
            declared::<TipVelocity>("contact.tip_velocity"),
            declared::<DampingPhase>("contact.damping_phase"),
            declared::<FirstSlipStep>("contact.first_slip_step"),
            declared::<SlipForce>("contact.slip_force"),
            declared::<FidelityLevel>("fidelity.level"),
            declared::<ModalBasis>("fidelity.modal_basis"),
            declared::<Clamp>("fidelity.clamp"),
            declared::<Scheme>("integrator.scheme"),
            declared::<StateEvolution>("friction.rate_and_state.state_evolution"),
        ]
    );
    assert_eq!(
        annotated_choices(&checked_in(FmuKind::NeuralFriction)),
        vec![
            declared::<NeuralFrictionLaw>("law"),
            declared::<StateVelocity>("state_velocity"),
            declared::<StateEvolution>("friction.rate_and_state.state_evolution"),
        ]
    );
}

/// The `<ScalarVariable ...>` opening tag and the type element of variable `name`.
fn scalar_variable<'a>(xml: &'a str, name: &str) -> (&'a str, &'a str) {
    let start = xml
        .find(&format!(r#"<ScalarVariable name="{name}""#))
        .unwrap_or_else(|| panic!("no variable {name}"));
    let rest = &xml[start..];
    let head_end = rest.find('>').unwrap();
    let body = &rest[head_end + 1..];
    let element = body.trim_start();
    (&rest[..head_end], &element[..element.find("/>").unwrap()])
}

/// A choice is an FMI Integer from 1 to its number of values (libcosim and Ecos ignore
/// FMI Enumerations), its start value is the default's code, and its description ends
/// with the codes and their words. No Enumeration is left in either model description.
#[test]
fn choices_are_integers_with_their_codes_in_range_and_description() {
    fn check<M: Model>(kind: FmuKind) {
        let xml = checked_in(kind);
        assert!(
            !xml.contains("<Enumeration"),
            "{kind:?} declares an Enumeration"
        );
        assert!(!xml.contains("<TypeDefinitions>"), "{kind:?}");
        let defaults = M::with_defaults();
        let mut seen = 0;
        for v in M::variables() {
            let Access::Choice {
                kind: values, get, ..
            } = &v.access
            else {
                continue;
            };
            seen += 1;
            let (head, element) = scalar_variable(&xml, v.name);
            assert_eq!(
                element,
                format!(
                    r#"<Integer min="1" max="{}" start="{}""#,
                    values.len,
                    get(&defaults)
                ),
                "{}",
                v.name
            );
            let codes: Vec<String> = values
                .items()
                .map(|(code, word, _)| format!("{code} = {word}"))
                .collect();
            let description = attribute(&format!(" {head}"), "description");
            assert!(
                description.ends_with(&format!(" [{}]", codes.join(", "))),
                "{}: {description}",
                v.name
            );
        }
        assert!(seen > 0, "{kind:?} has no choice");
    }
    check::<StickSlipBeam>(FmuKind::StickSlipBeam);
    check::<NeuralFriction>(FmuKind::NeuralFriction);
}

/// The largest counts the FMU declares are the scene's own limits.
#[test]
fn count_maxima_are_the_scenes_limits() {
    let xml = checked_in(FmuKind::StickSlipBeam);
    for (name, max) in [
        ("fidelity.modes", stickslip::scene::MAX_MODES),
        (
            "fidelity.beam_elements",
            stickslip::scene::MAX_BEAM_ELEMENTS,
        ),
    ] {
        let (_, element) = scalar_variable(&xml, name);
        assert!(
            element.starts_with(&format!(r#"<Integer min="1" max="{max}" "#)),
            "{name}: {element}"
        );
    }
}

/// Every choice variable takes each of its codes and reads it back, and refuses the
/// codes around them with the allowed codes and words in the message.
fn choices_round_trip<M: Model>() {
    let mut model = M::with_defaults();
    for v in M::variables() {
        let Access::Choice { kind, .. } = &v.access else {
            continue;
        };
        for (value, _, _) in kind.items() {
            v.set_integer(&mut model, value).unwrap();
            assert_eq!(v.get_integer(&model), value, "{}", v.name);
        }
        for bad in [0, kind.len as i32 + 1] {
            let error = v.set_integer(&mut model, bad).unwrap_err().to_string();
            assert!(
                error.contains(&format!("allowed: {}", kind.codes())),
                "{}: {error}",
                v.name
            );
        }
    }
}

#[test]
fn choice_variables_take_and_read_back_every_code() {
    choices_round_trip::<StickSlipBeam>();
    choices_round_trip::<NeuralFriction>();
}
