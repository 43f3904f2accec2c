//! The FMI 2.0 modelDescription.xml (FMI 2.0 standard, section 2.2).

use super::described::Described;
use super::parts::{
    choice_variables, dependency_attributes, description, dynamic_dependencies, initial_attribute,
    output_dependencies, start_attribute, write_units_categories_experiment, IndexedDependencies,
    CHOICES_TOOL,
};
use crate::model::Model;
use crate::variables::{Access, Causality, DependencyKind, DynamicOutput, Variability, Variable};
use crate::version::FmiVersion;
use crate::xml::{attribute, escape, optional_attribute, real};
use std::fmt::Write;

/// The FMI 2.0 modelDescription.xml of model `M`'s table, with `guid` as its GUID.
pub(super) fn body<M: Model>(guid: &str) -> String {
    body_of(&Described::<M>::built_in(), guid)
}

/// The FMI 2.0 modelDescription.xml of `described`, with `guid` as its GUID.
pub(super) fn body_of<M: Model>(described: &Described<M>, guid: &str) -> String {
    let info = &M::INFO;
    let defaults = &described.defaults;
    let variables = M::variables();
    let mut x = String::new();
    let w = &mut x;
    // Writing to a String cannot fail.
    let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        w,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="{}" generationTool="stickslip {}" variableNamingConvention="structured" numberOfEventIndicators="0">"#,
        described.model_identifier,
        guid,
        escape(&described.description),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        w,
        r#"  <CoSimulation modelIdentifier="{}" needsExecutionTool="false" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" maxOutputDerivativeOrder="0" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true" providesDirectionalDerivative="{}"/>"#,
        described.model_identifier, info.provides_directional_derivatives
    );

    write_units_categories_experiment(w, variables, FmiVersion::V2);

    write_choices(w, variables);

    let dynamic = defaults.dynamic_outputs();
    write_variables(w, variables, defaults);
    write_structure(w, variables, dynamic);
    let _ = writeln!(w, "</fmiModelDescription>");
    debug_assert!(variables.iter().all(|v| match v.causality {
        Causality::Parameter => v.variability == Variability::Fixed,
        _ => v.variability != Variability::Fixed,
    }));
    x
}

/// `<ModelVariables>`: one `<ScalarVariable>` per row of the table, in table order
/// (its index is the row's place, counted from 1), with the defaults as start values,
/// then the model's dynamic outputs (an exported FMU's sensors).
fn write_variables<M: Model>(w: &mut String, variables: &[Variable<M>], defaults: &M) {
    let _ = writeln!(w, "  <ModelVariables>");
    for v in variables {
        let _ = writeln!(
            w,
            r#"    <ScalarVariable name="{}" valueReference="{}" description="{}" causality="{}" variability="{}"{}>"#,
            escape(v.name),
            v.value_reference,
            escape(&description(v)),
            v.causality.as_str(),
            v.variability.as_str(),
            initial_attribute(v.causality)
        );
        let _ = writeln!(w, "      {}", type_element(v, defaults));
        let _ = writeln!(w, "    </ScalarVariable>");
    }
    for o in defaults.dynamic_outputs() {
        let _ = writeln!(
            w,
            r#"    <ScalarVariable name="{}" valueReference="{}" description="{}" causality="output" variability="continuous"{}>"#,
            escape(&o.name),
            o.value_reference,
            escape(&o.description),
            initial_attribute(Causality::Output)
        );
        let _ = writeln!(w, r#"      <Real unit="{}"/>"#, escape(o.unit));
        let _ = writeln!(w, "    </ScalarVariable>");
    }
    let _ = writeln!(w, "  </ModelVariables>");
}

/// The type element inside a `<ScalarVariable>`, with the default as its start value
/// except for an output (whose initial is calculated). A choice is an `<Integer>` of
/// its codes.
fn type_element<M>(v: &Variable<M>, defaults: &M) -> String {
    let with_start = v.causality != Causality::Output;
    let start = |value: String| start_attribute(v, value);
    match &v.access {
        Access::Real { unit, get, .. } => {
            let unit = optional_attribute("unit", *unit);
            format!("<Real{unit}{}/>", start(real(get(defaults))))
        }
        Access::Integer { min, max, get, .. } => {
            format!(
                r#"<Integer min="{min}" max="{max}"{}/>"#,
                start(get(defaults).to_string())
            )
        }
        Access::Boolean { get, .. } => format!("<Boolean{}/>", start(get(defaults).to_string())),
        Access::Choice { kind, get, .. } => format!(
            r#"<Integer min="1" max="{}"{}/>"#,
            kind.len,
            start(get(defaults).to_string())
        ),
        Access::String { get, .. } => {
            let start = if with_start {
                attribute("start", &get(defaults))
            } else {
                String::new()
            };
            format!("<String{start}/>")
        }
    }
}

/// `<ModelStructure>`: each output's step dependencies under `<Outputs>` and its
/// initial ones under `<InitialUnknowns>`, by variable index; the dynamic outputs
/// (indices after the table's) with their `like` row's.
fn write_structure<M>(w: &mut String, variables: &[Variable<M>], dynamic: &[DynamicOutput]) {
    let _ = writeln!(w, "  <ModelStructure>");
    let _ = writeln!(w, "    <Outputs>");
    let mut dependencies: Vec<(usize, &IndexedDependencies)> = Vec::new();
    let table = output_dependencies(variables);
    dependencies.extend(table.iter().map(|(k, d)| (*k, d)));
    let like = dynamic_dependencies(variables, &table, dynamic);
    dependencies.extend(
        like.into_iter()
            .enumerate()
            .map(|(i, d)| (variables.len() + 1 + i, d)),
    );
    for (k, d) in &dependencies {
        let (indices, kinds): (Vec<usize>, Vec<DependencyKind>) = d.step.iter().copied().unzip();
        let _ = writeln!(
            w,
            r#"      <Unknown index="{k}"{}/>"#,
            dependency_attributes(&indices, &kinds)
        );
    }
    let _ = writeln!(w, "    </Outputs>");
    let _ = writeln!(w, "    <InitialUnknowns>");
    for (k, d) in &dependencies {
        let _ = writeln!(
            w,
            r#"      <Unknown index="{k}"{}/>"#,
            dependency_attributes(&d.initial, &[])
        );
    }
    let _ = writeln!(w, "    </InitialUnknowns>");
    let _ = writeln!(w, "  </ModelStructure>");
}

/// The choices' codes and words for programs ([`CHOICES_TOOL`]), in FMI 2.0's
/// `<VendorAnnotations><Tool name=...>` (not in FMI 3.0's description; see `fmi3::body3`).
fn write_choices<M>(w: &mut String, variables: &[Variable<M>]) {
    let (outer, element, attribute) = ("VendorAnnotations", "Tool", "name");
    let choices = choice_variables(variables);
    if !choices.is_empty() {
        let _ = writeln!(w, "  <{outer}>");
        let _ = writeln!(w, r#"    <{element} {attribute}="{CHOICES_TOOL}">"#);
        let _ = writeln!(w, "      <Choices>");
        for (name, kind) in choices {
            let _ = writeln!(
                w,
                r#"        <Choice variable="{}" type="{}" description="{}">"#,
                escape(name),
                escape(kind.name),
                escape(kind.description)
            );
            for (code, word, description) in kind.items() {
                let _ = writeln!(
                    w,
                    r#"          <Item code="{code}" name="{}" description="{}"/>"#,
                    escape(word),
                    escape(description)
                );
            }
            let _ = writeln!(w, "        </Choice>");
        }
        let _ = writeln!(w, "      </Choices>");
        let _ = writeln!(w, "    </{element}>");
        let _ = writeln!(w, "  </{outer}>");
    }
}
