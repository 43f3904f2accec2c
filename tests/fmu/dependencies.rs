//! The output dependencies that modelDescription.xml declares (ModelStructure, FMI 2.0
//! section 2.2.8) are the ones the FMUs have. Each known is changed alone, without a
//! step, and every output is read: an output must change for every known it is
//! declared to depend on (in at least one configuration of the parameters, because a
//! declaration covers every law the parameters can choose) and for no other.
//!
//! - `Outputs`, at a communication point: the knowns are the inputs.
//! - `InitialUnknowns`, in Initialization Mode: the inputs and the parameters.
//!
//! The declarations are read from the generated XML, which a master reads, not from the
//! Rust tables.

use std::collections::{BTreeMap, BTreeSet};
use stickslip::choice::Choice;
use stickslip::friction::registry::{self, ParameterKind};
use stickslip::friction::FrictionLawKind;
use stickslip::scene::FidelityLevel;
use stickslip::simulation::ExternalCoupling;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::instance::{Instance, Mode};
use stickslip_fmi::model::Model;
use stickslip_fmi::variables::{Access, Causality};
use stickslip_fmi::FmuKind;
use stickslip_tests::vr;

/// Output name -> names of the knowns it depends on.
type DependencyMap = BTreeMap<String, BTreeSet<String>>;

/// The value of attribute `name` in an XML tag, if present.
fn attribute(tag: &str, name: &str) -> Option<String> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    let end = start + tag[start..].find('"')?;
    Some(tag[start..end].to_string())
}

/// The `Outputs` and `InitialUnknowns` lists of a modelDescription, by variable name.
/// Every unknown must carry a `dependencies` attribute: an absent one would mean "all
/// knowns".
fn declared(xml: &str) -> (DependencyMap, DependencyMap) {
    let names: Vec<String> = xml
        .split("<ScalarVariable ")
        .skip(1)
        .map(|tag| attribute(&format!(" {tag}"), "name").unwrap())
        .collect();
    let list = |element: &str| -> DependencyMap {
        let open = format!("<{element}>");
        let block = &xml[xml.find(&open).unwrap()..xml.find(&format!("</{element}>")).unwrap()];
        block
            .split("<Unknown ")
            .skip(1)
            .map(|tag| {
                let tag = format!(" {}", &tag[..tag.find("/>").unwrap()]);
                let tag = tag.as_str();
                let index: usize = attribute(tag, "index").unwrap().parse().unwrap();
                let dependencies = attribute(tag, "dependencies")
                    .unwrap_or_else(|| panic!("{element}: {tag} declares no dependencies"));
                let known: BTreeSet<String> = dependencies
                    .split_whitespace()
                    .map(|k| names[k.parse::<usize>().unwrap() - 1].clone())
                    .collect();
                (names[index - 1].clone(), known)
            })
            .collect()
    };
    (list("Outputs"), list("InitialUnknowns"))
}

/// Every output of `M`, by name, as bits (Real), value (Integer) or 0/1 (Boolean).
fn outputs<M: Model>(fmu: &mut Instance<M>) -> BTreeMap<String, u64> {
    M::variables()
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .map(|v| {
            let vr = [v.value_reference];
            let value = match &v.access {
                Access::Real { .. } => {
                    let mut out = [0.0];
                    fmu.get_real(&vr, &mut out).unwrap();
                    out[0].to_bits()
                }
                Access::Integer { .. } | Access::Choice { .. } => {
                    let mut out = [0];
                    fmu.get_integer(&vr, &mut out).unwrap();
                    out[0] as u64
                }
                Access::Boolean { .. } => {
                    let mut out = [false];
                    fmu.get_boolean(&vr, &mut out).unwrap();
                    out[0] as u64
                }
                Access::String { .. } => unreachable!("no String outputs"),
            };
            (v.name.to_string(), value)
        })
        .collect()
}

/// A value of a known, in the type its variable has.
#[derive(Clone, Debug)]
enum Value {
    Real(f64),
    Integer(i32),
    String(String),
}

fn set<M: Model>(fmu: &mut Instance<M>, name: &str, value: &Value) {
    let vr = [vr::<M>(name)];
    match value {
        Value::Real(x) => fmu.set_real(&vr, &[*x]),
        Value::Integer(n) => fmu.set_integer(&vr, &[*n]),
        Value::String(s) => fmu.set_string(&vr, &[s.as_str()]),
    }
    .unwrap_or_else(|_| panic!("{name} = {value:?} refused"));
}

/// Sets each known (name, base value, changed value) alone to its changed value, reads
/// every output, and sets it back; adds to `seen` the outputs it changed. Setting it
/// back must give the base outputs again.
fn probe<M: Model>(
    fmu: &mut Instance<M>,
    knowns: &[(&str, Value, Value)],
    seen: &mut DependencyMap,
) {
    for (name, base, _) in knowns {
        set(fmu, name, base);
    }
    let before = outputs(fmu);
    for (name, base, changed) in knowns {
        set(fmu, name, changed);
        let after = outputs(fmu);
        for (output, value) in &after {
            if *value != before[output] {
                seen.entry(output.clone())
                    .or_default()
                    .insert(name.to_string());
            }
        }
        set(fmu, name, base);
        assert_eq!(outputs(fmu), before, "{name} set back");
    }
}

/// Every output with the knowns it was seen to depend on (none for the others).
fn complete(seen: DependencyMap, declared: &DependencyMap) -> DependencyMap {
    declared
        .keys()
        .map(|output| {
            (
                output.clone(),
                seen.get(output).cloned().unwrap_or_default(),
            )
        })
        .collect()
}

/// Every law parameter of the registry with its default and a changed value in range:
/// 1.2 times the default, 5 for a default of 0, the next word of a choice.
fn law_parameters() -> Vec<(&'static str, Value, Value)> {
    registry::parameters()
        .map(|p| match p.kind {
            ParameterKind::Real { .. } => {
                let changed = if p.default == 0.0 {
                    5.0
                } else {
                    1.2 * p.default
                };
                (p.name, Value::Real(p.default), Value::Real(changed))
            }
            ParameterKind::Choice(choice) => {
                let code = p.default as i32;
                let next = code % choice.len as i32 + 1;
                (p.name, Value::Integer(code), Value::Integer(next))
            }
        })
        .collect()
}

fn friction() -> Instance<NeuralFriction> {
    Instance::new(
        "friction",
        Some(&stickslip_tests::weights_dir()),
        false,
        Box::new(|_, _, _| {}),
    )
    .unwrap()
}

#[test]
fn neural_friction_outputs_change_with_exactly_the_inputs_and_parameters_declared() {
    let (declared_outputs, declared_initial) =
        declared(&FmuKind::NeuralFriction.model_description());
    let weights = stickslip_tests::six_feature_weights("dependencies");
    let weights = weights.to_str().unwrap().to_string();
    let neural = NeuralFrictionLaw::NEURAL.code();
    let exponential = NeuralFrictionLaw::EXPONENTIAL.code();
    // Base values inside the networks' training ranges (inputs are clamped to them).
    // Rate-and-state is probed inside its regularisation core (|v K| ~ 1 at
    // v ~ 4e-25 m/s for the defaults), where its slope depends on mu_0 and V_0 as well:
    // at 0.05 m/s it is a F_n / |v| (to 1e-40 relative) and would hide them.
    let inputs = |law: i32| {
        let v = if law == NeuralFrictionLaw::RATE_AND_STATE.code() {
            3e-25
        } else {
            0.05
        };
        vec![
            ("sliding_velocity", Value::Real(v), Value::Real(2.0 * v)),
            ("normal_force", Value::Real(100.0), Value::Real(105.0)),
            ("extra_feature[1]", Value::Real(0.1), Value::Real(0.5)),
            ("extra_feature[2]", Value::Real(0.2), Value::Real(-0.5)),
            ("extra_feature[3]", Value::Real(0.3), Value::Real(0.7)),
            ("extra_feature[4]", Value::Real(-0.4), Value::Real(0.2)),
        ]
    };
    let parameters = |law: i32| {
        let other_law = if law == neural { exponential } else { neural };
        [
            ("law", Value::Integer(law), Value::Integer(other_law)),
            ("static_coefficient", Value::Real(0.5), Value::Real(0.6)),
            ("kinetic_coefficient", Value::Real(0.3), Value::Real(0.25)),
            ("decay", Value::Real(20.0), Value::Real(10.0)),
            (
                "weights",
                Value::String(weights.clone()),
                Value::String("paper-plain.json".into()),
            ),
        ]
        .into_iter()
        .chain(law_parameters())
        .collect::<Vec<_>>()
    };
    let mut seen_outputs = DependencyMap::new();
    let mut seen_initial = DependencyMap::new();
    for law in NeuralFrictionLaw::ALL.iter().map(|l| l.code()) {
        let mut fmu = friction();
        for (name, base, _) in parameters(law) {
            set(&mut fmu, name, &base);
        }
        fmu.setup_experiment(0.0, None).unwrap();
        fmu.enter_initialization_mode().unwrap();
        let mut knowns = inputs(law);
        knowns.extend(parameters(law));
        probe(&mut fmu, &knowns, &mut seen_initial);
        fmu.exit_initialization_mode().unwrap();
        fmu.do_step(0.0, 1e-3).unwrap();
        assert_eq!(fmu.mode(), Mode::StepComplete);
        probe(&mut fmu, &inputs(law), &mut seen_outputs);
    }
    let _ = std::fs::remove_file(&weights);
    let mut seen_outputs = complete(seen_outputs, &declared_outputs);
    let mut seen_initial = complete(seen_initial, &declared_initial);
    println!("Outputs: {seen_outputs:#?}\nInitialUnknowns: {seen_initial:#?}");
    // The table coupling's curves at fixed velocities: a node can hide a dependency by
    // coincidence (at v = 0 every memoryless law's force is 0; at |v| = V_0 = 1e-3 m/s
    // rate-and-state's initial force is mu_0 F_n whatever a), so there the seen ones
    // must be declared, and the node at -1e-2 m/s, which hides none, must see them all.
    let (mut declared_outputs, mut declared_initial) = (declared_outputs, declared_initial);
    for (seen, declared, what) in [
        (&mut seen_outputs, &mut declared_outputs, "Outputs"),
        (&mut seen_initial, &mut declared_initial, "InitialUnknowns"),
    ] {
        let table: Vec<String> = declared
            .keys()
            .filter(|o| o.starts_with("table_"))
            .cloned()
            .collect();
        assert_eq!(table.len(), 22, "{what}");
        for output in table {
            let s = seen.remove(&output).unwrap_or_default();
            let d = declared.remove(&output).unwrap_or_default();
            if output.ends_with("_force_0") {
                assert_eq!(s, d, "{what}: {output}");
            } else {
                assert!(
                    s.is_subset(&d),
                    "{what}: {output}: seen {s:?}, declared {d:?}"
                );
            }
        }
    }
    assert_eq!(seen_outputs, declared_outputs, "Outputs");
    assert_eq!(seen_initial, declared_initial, "InitialUnknowns");
    // The probe sees the force depend on every input and static_limit on F_n alone.
    assert_eq!(seen_outputs["friction_force"].len(), 6);
    assert_eq!(
        seen_outputs["static_limit"],
        BTreeSet::from(["normal_force".to_string()])
    );
}

fn beam(model: FrictionLawKind) -> Instance<StickSlipBeam> {
    let mut fmu: Instance<StickSlipBeam> = Instance::new(
        "beam",
        Some(&stickslip_tests::weights_dir()),
        false,
        Box::new(|_, _, _| {}),
    )
    .unwrap();
    let set_code = |fmu: &mut Instance<StickSlipBeam>, name: &str, code: i32| {
        fmu.set_integer(&[vr::<StickSlipBeam>(name)], &[code])
            .unwrap()
    };
    set_code(&mut fmu, "fidelity.level", FidelityLevel::Modal.code());
    set_code(&mut fmu, "friction.law", model.code());
    fmu.setup_experiment(0.0, Some(1.2)).unwrap();
    fmu
}

/// The beam's inputs, each with a base value (the paper's, with the external model fed
/// the exponential law's kinetic force at rest and its static limit) and a changed one.
fn beam_inputs() -> Vec<(&'static str, Value, Value)> {
    vec![
        ("belt_speed", Value::Real(0.02), Value::Real(0.05)),
        ("normal_force", Value::Real(100.0), Value::Real(120.0)),
        (
            "external.kinetic_force",
            Value::Real(30.0),
            Value::Real(20.0),
        ),
        (
            "external.static_limit",
            Value::Real(50.0),
            Value::Real(40.0),
        ),
        (
            "external.friction_force",
            Value::Real(30.0),
            Value::Real(-20.0),
        ),
        (
            "external.friction_slope",
            Value::Real(-150.0),
            Value::Real(1e4),
        ),
        (
            "external.sliding_velocity",
            Value::Real(0.01),
            Value::Real(-0.01),
        ),
    ]
}

#[test]
fn no_stick_slip_beam_output_follows_an_input_before_the_next_step() {
    let (declared_outputs, declared_initial) =
        declared(&FmuKind::StickSlipBeam.model_description());
    assert!(declared_outputs.values().all(BTreeSet::is_empty));
    let mut seen_outputs = DependencyMap::new();
    let mut seen_initial = DependencyMap::new();
    let h = 1e-3;
    for (model, coupling) in [
        (FrictionLawKind::Exponential, ExternalCoupling::Magnitude),
        (FrictionLawKind::External, ExternalCoupling::Magnitude),
        (FrictionLawKind::External, ExternalCoupling::Signed),
    ] {
        let mut fmu = beam(model);
        fmu.set_integer(
            &[vr::<StickSlipBeam>("external.coupling")],
            &[coupling.code()],
        )
        .unwrap();
        fmu.enter_initialization_mode().unwrap();
        probe(&mut fmu, &beam_inputs(), &mut seen_initial);
        fmu.exit_initialization_mode().unwrap();
        // In stick (0.1 s), just after breakaway (0.41 s) and in the stick-slip cycles.
        let mut t = 0.0;
        for until in [0.1, 0.41, 0.8] {
            while t < until - 0.5 * h {
                fmu.do_step(t, h).unwrap();
                t += h;
            }
            probe(&mut fmu, &beam_inputs(), &mut seen_outputs);
            // The inputs do act, on the next step: in slip, the same step from a saved
            // state with the belt speed or the kinetic force input changed gives other
            // outputs.
            if until != 0.41 {
                continue;
            }
            let saved = fmu.get_state().unwrap();
            fmu.do_step(t, h).unwrap();
            let unchanged = outputs(&mut fmu);
            let acting: &[&str] = match (model, coupling) {
                (FrictionLawKind::External, ExternalCoupling::Magnitude) => {
                    &["belt_speed", "external.kinetic_force"]
                }
                (FrictionLawKind::External, ExternalCoupling::Signed) => &[
                    "belt_speed",
                    "external.friction_force",
                    "external.friction_slope",
                    "external.sliding_velocity",
                ],
                _ => &["belt_speed", "normal_force"],
            };
            for (name, base, changed) in beam_inputs() {
                if !acting.contains(&name) {
                    continue;
                }
                fmu.set_state(&saved).unwrap();
                set(&mut fmu, name, &changed);
                fmu.do_step(t, h).unwrap();
                assert_ne!(
                    outputs(&mut fmu),
                    unchanged,
                    "{model:?} ({coupling:?}): {name} set at t = {t} s changes nothing in the next step"
                );
                set(&mut fmu, name, &base);
            }
            fmu.set_state(&saved).unwrap();
        }
    }
    let seen_outputs = complete(seen_outputs, &declared_outputs);
    println!("Outputs: {seen_outputs:#?}\nInitialUnknowns (inputs only): {seen_initial:#?}");
    assert_eq!(seen_outputs, declared_outputs, "Outputs");
    // In Initialization Mode every parameter and the scene's inputs are declared (a
    // superset: the start state is built from the whole scene); the probe changes the
    // inputs only. No output follows the external inputs; belt_speed reaches the start
    // (the quasi-static start moves at the belt speed).
    for (output, knowns) in &seen_initial {
        for known in knowns {
            assert!(
                declared_initial[output].contains(known),
                "{output} changed with {known} in Initialization Mode, which is not declared"
            );
        }
    }
    let external_inputs: Vec<&str> = beam_inputs()
        .into_iter()
        .map(|(name, _, _)| name)
        .filter(|name| name.starts_with("external."))
        .collect();
    assert_eq!(external_inputs.len(), 5);
    assert!(declared_initial
        .values()
        .all(|knowns| external_inputs.iter().all(|k| !knowns.contains(*k))));
    assert!(seen_initial["tip_velocity"].contains("belt_speed"));
}
