//! The FMI 3.0 modelDescription.xml (FMI 3.0 standard, section 2.4).

use super::described::Described;
use super::parts::{
    dependency_attributes, description, dynamic_dependencies, initial_attribute,
    output_dependencies, start_attribute, write_units_categories_experiment, IndexedDependencies,
};
use crate::model::Model;
use crate::variables::{Access, ArrayVariable, Causality, DependencyKind, DynamicOutput, Variable};
use crate::version::FmiVersion;
use crate::xml::{escape, optional_attribute, real};
use std::fmt::Write;

/// The value reference of FMI 3.0's independent variable `time`; no table uses it.
/// fmi3GetFloat64 reads the instance's time there (`ffi3::values3`).
pub const TIME_VALUE_REFERENCE: u32 = 0;

/// The FMI 3.0 modelDescription.xml of the same table (FMI 3.0 standard, section 2.4):
/// the same variables, units, categories and experiment as `fmi2::body`, with FMI 3.0's
/// names (Float64, Int32, `instantiationToken`), a `<CoSimulation>` element that says
/// Event Mode for both models and early return where the model has internal events
/// (`ModelInfo::returns_early_at_events`), and ModelStructure by value reference. A choice is an
/// `<Int32 min="1" max="N">`, as in FMI 2.0, so the codes, the scripts that read them
/// from the `stickslip` annotation, and the SSP parameter sets are the same for both
/// versions; their words are in each choice's description. The instantiation token is the FMI 2.0 GUID: both descriptions come from
/// one table, so one hash names the interface, and an FMU state saved through one
/// version restores through the other.
pub(super) fn body3<M: Model>(token: &str) -> String {
    body3_of(&Described::<M>::built_in(), token)
}

/// The FMI 3.0 modelDescription.xml of `described`, with `token` as its
/// instantiationToken.
pub(super) fn body3_of<M: Model>(described: &Described<M>, token: &str) -> String {
    let info = &M::INFO;
    let defaults = &described.defaults;
    let variables = M::variables();
    let mut x = String::new();
    let w = &mut x;
    let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        w,
        r#"<fmiModelDescription fmiVersion="3.0" modelName="{}" instantiationToken="{}" description="{}" generationTool="stickslip {}" variableNamingConvention="structured">"#,
        described.model_identifier,
        token,
        escape(&described.description),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        w,
        r#"  <CoSimulation modelIdentifier="{}" needsExecutionTool="false" canBeInstantiatedOnlyOncePerProcess="false" canGetAndSetFMUState="true" canSerializeFMUState="true" providesDirectionalDerivatives="{}" providesAdjointDerivatives="false" providesPerElementDependencies="false" canHandleVariableCommunicationStepSize="true" maxOutputDerivativeOrder="0" providesIntermediateUpdate="false" mightReturnEarlyFromDoStep="{}" canReturnEarlyAfterIntermediateUpdate="false" hasEventMode="true" providesEvaluateDiscreteStates="false"/>"#,
        described.model_identifier,
        info.provides_directional_derivatives,
        info.returns_early_at_events
    );
    write_units_categories_experiment(w, variables, FmiVersion::V3);

    let _ = writeln!(w, "  <ModelVariables>");
    // FMI 3.0 requires exactly one independent variable (section 2.4.7.4); FMI 2.0 left
    // time implicit. It is not in the tables: it is the instance's clock, not a model
    // value; fmi3GetFloat64 reads it and fmi3SetFloat64 refuses it (`ffi3::values3`).
    let _ = writeln!(
        w,
        r#"    <Float64 name="time" valueReference="{TIME_VALUE_REFERENCE}" description="Simulation time (s)" causality="independent" variability="continuous"/>"#
    );
    for v in variables {
        // An array's elements are rows of the table: the array is written in place of
        // its first element, the other elements not at all.
        match ArrayVariable::containing(M::arrays(), v.value_reference) {
            Some((array, 1)) => write_array(w, array, variables, defaults),
            Some(_) => {}
            None => write_scalar(w, v, defaults),
        }
    }
    // The dynamic outputs (an exported FMU's sensors) after the table's variables.
    for o in defaults.dynamic_outputs() {
        let _ = writeln!(
            w,
            r#"    <Float64 name="{}" valueReference="{}" description="{}" causality="output" variability="continuous"{}{}/>"#,
            escape(&o.name),
            o.value_reference,
            escape(&o.description),
            initial_attribute(Causality::Output),
            optional_attribute("declaredType", Some(o.unit))
        );
    }
    let _ = writeln!(w, "  </ModelVariables>");
    write_structure::<M>(w, variables, defaults.dynamic_outputs());
    // No `stickslip` choices annotation here: FMI 3.0 allows any element inside an
    // <Annotation>, but the `fmi` crate's reader refuses child elements there (it takes
    // text only), and an importer that cannot read the file at all is worse than one
    // that has the codes only in each choice's description. Programs read the codes and
    // words from the FMI 2.0 description, generated from the same table.
    let _ = writeln!(w, "</fmiModelDescription>");
    x
}

/// A scalar variable: its type's element (Float64, Int32, Boolean, String) with the
/// default as its start value except for an output (whose initial is calculated). A
/// choice is an `<Int32>` of its codes.
fn write_scalar<M>(w: &mut String, v: &Variable<M>, defaults: &M) {
    let with_start = v.causality != Causality::Output;
    let start = |value: String| start_attribute(v, value);
    let (element, attributes, children) = match &v.access {
        Access::Real { unit, get, .. } => (
            "Float64",
            format!(
                "{}{}",
                optional_attribute("declaredType", *unit),
                start(real(get(defaults)))
            ),
            None,
        ),
        Access::Integer { min, max, get, .. } => (
            "Int32",
            format!(
                r#" min="{min}" max="{max}"{}"#,
                start(get(defaults).to_string())
            ),
            None,
        ),
        Access::Choice { kind, get, .. } => (
            "Int32",
            format!(
                r#" min="1" max="{}"{}"#,
                kind.len,
                start(get(defaults).to_string())
            ),
            None,
        ),
        Access::Boolean { get, .. } => ("Boolean", start(get(defaults).to_string()), None),
        // FMI 3.0 gives a String's start value as a child element.
        Access::String { get, .. } => (
            "String",
            String::new(),
            with_start.then(|| format!(r#"<Start value="{}"/>"#, escape(&get(defaults)))),
        ),
    };
    let head = format!(
        r#"    <{element} name="{}" valueReference="{}" description="{}" causality="{}" variability="{}"{}{attributes}"#,
        escape(v.name),
        v.value_reference,
        escape(&description(v)),
        v.causality.as_str(),
        v.variability.as_str(),
        initial_attribute(v.causality)
    );
    let _ = match children {
        None => writeln!(w, "{head}/>"),
        Some(children) => writeln!(w, "{head}>\n      {children}\n    </{element}>"),
    };
}

/// `<ModelStructure>`: the same dependencies as FMI 2.0's, named by value reference
/// instead of index; an array element by its array (no per-element dependencies: the
/// output depends on the whole array if on any element). The dynamic outputs come
/// after the table's, with their `like` row's dependencies.
fn write_structure<M: Model>(w: &mut String, variables: &[Variable<M>], dynamic: &[DynamicOutput]) {
    let vr_of = |k: usize| match variables.get(k - 1) {
        Some(v) => ArrayVariable::containing(M::arrays(), v.value_reference)
            .map_or(v.value_reference, |(a, _)| a.value_reference) as usize,
        None => dynamic[k - 1 - variables.len()].value_reference as usize,
    };
    let _ = writeln!(w, "  <ModelStructure>");
    let table = output_dependencies(variables);
    let mut dependencies: Vec<(usize, &IndexedDependencies)> =
        table.iter().map(|(k, d)| (*k, d)).collect();
    let like = dynamic_dependencies(variables, &table, dynamic);
    dependencies.extend(
        like.into_iter()
            .enumerate()
            .map(|(i, d)| (variables.len() + 1 + i, d)),
    );
    for (k, d) in &dependencies {
        let (vrs, kinds) = merge_elements(d.step.iter().map(|&(k, kind)| (vr_of(k), kind)));
        let _ = writeln!(
            w,
            r#"    <Output valueReference="{}"{}/>"#,
            vr_of(*k),
            dependency_attributes(&vrs, &kinds)
        );
    }
    for (k, d) in &dependencies {
        let (vrs, _) = merge_elements(
            d.initial
                .iter()
                .map(|&k| (vr_of(k), DependencyKind::Dependent)),
        );
        let _ = writeln!(
            w,
            r#"    <InitialUnknown valueReference="{}"{}/>"#,
            vr_of(*k),
            dependency_attributes(&vrs, &[])
        );
    }
    let _ = writeln!(w, "  </ModelStructure>");
}

/// An FMI 3.0 array variable: a `<Float64>` with the first element's causality,
/// variability and unit, the start values of all elements (in element order, which is
/// row-major order for a vector) and one `<Dimension start="N"/>`.
fn write_array<M>(
    w: &mut String,
    array: &ArrayVariable,
    variables: &'static [Variable<M>],
    defaults: &M,
) {
    let first = match array.check(variables) {
        Ok(first) => first,
        Err(reason) => panic!("{reason}"),
    };
    let unit = match first.access {
        Access::Real { unit, .. } => unit,
        _ => None,
    };
    let initial = match first.causality {
        Causality::Parameter => r#" initial="exact""#,
        Causality::Input | Causality::Output => "",
    };
    let start = if first.causality == Causality::Output {
        String::new()
    } else {
        let values: Vec<String> = array
            .elements
            .iter()
            .filter_map(|&vr| variables.iter().find(|v| v.value_reference == vr))
            .map(|v| real(v.get_real(defaults)))
            .collect();
        format!(r#" start="{}""#, values.join(" "))
    };
    let _ = writeln!(
        w,
        r#"    <Float64 name="{}" valueReference="{}" description="{}" causality="{}" variability="{}"{initial}{}{start}>"#,
        escape(array.name),
        array.value_reference,
        escape(array.description),
        first.causality.as_str(),
        first.variability.as_str(),
        optional_attribute("declaredType", unit),
    );
    let _ = writeln!(w, r#"      <Dimension start="{}"/>"#, array.elements.len());
    let _ = writeln!(w, "    </Float64>");
}

/// Dependencies by value reference with the elements of an array merged into one
/// entry (the first occurrence's place). Elements that enter in different ways make
/// the array's kind "dependent", the kind that claims no structure.
fn merge_elements(
    dependencies: impl Iterator<Item = (usize, DependencyKind)>,
) -> (Vec<usize>, Vec<DependencyKind>) {
    let mut merged: Vec<(usize, DependencyKind)> = Vec::new();
    for (vr, kind) in dependencies {
        match merged.iter_mut().find(|(v, _)| *v == vr) {
            Some((_, known)) if *known != kind => *known = DependencyKind::Dependent,
            Some(_) => {}
            None => merged.push((vr, kind)),
        }
    }
    merged.into_iter().unzip()
}
