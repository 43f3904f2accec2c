//! What both versions' descriptions write alike: the log categories, the choices'
//! codes, the units, and the dependencies of the outputs.

use crate::model::Model;
use crate::variables::{
    Access, Causality, ChoiceType, DependencyKind, DynamicOutput, InitialDependencies, Unit,
    Variable, UNITS,
};
use crate::version::{FmiVersion, Names};
use crate::xml::{attribute, escape, real};
use std::fmt::Write;

/// A log category every FMU declares: its name, and its description as a version's
/// model description says it (the statuses it names are that version's).
pub struct LogCategory {
    pub name: &'static str,
    pub description: fn(&Names) -> String,
}

/// The log categories every FMU declares, in modelDescription order.
pub const LOG_CATEGORIES: [LogCategory; 4] = [
    LogCategory {
        name: "logStatusError",
        description: |names| {
            format!(
                "Why a call returned {} (on unless logging is switched off)",
                names.error_status
            )
        },
    },
    LogCategory {
        name: "logStatusWarning",
        description: |names| format!("Why a call returned {}", names.warning_status),
    },
    LogCategory {
        name: "logEvents",
        description: |_| {
            "Stick/slip transitions, the communication steps that contain them, and the fidelity = auto choice".into()
        },
    },
    LogCategory {
        name: "logCalls",
        description: |_| "Every FMI function call with its arguments".into(),
    },
];

/// A scalar variable's `initial` attribute, the same in both versions: a parameter
/// exact, an output calculated, an input none (the standard's default).
pub(super) fn initial_attribute(causality: Causality) -> &'static str {
    match causality {
        Causality::Parameter => r#" initial="exact""#,
        Causality::Input => "",
        Causality::Output => r#" initial="calculated""#,
    }
}

/// A variable's `start` attribute with `value`, or nothing for an output, whose
/// initial is calculated: the same in both versions.
pub(super) fn start_attribute<M>(v: &Variable<M>, value: String) -> String {
    if v.causality == Causality::Output {
        String::new()
    } else {
        format!(r#" start="{value}""#)
    }
}

/// The `name` of the `<Tool>` under `<VendorAnnotations>` that lists the choices:
///
/// ```xml
/// <Tool name="stickslip">
///   <Choices>
///     <Choice variable="friction.law" type="FrictionLaw" description="...">
///       <Item code="1" name="exponential" description="..."/>
/// ```
///
/// One `<Choice>` per choice variable, in table order, and one `<Item>` per code.
/// (FMI 2.0 allows a single element inside a `<Tool>`, hence `<Choices>`; per-variable
/// `<Annotations>` would be closer, but some importers, the `fmi` crate among them,
/// refuse unknown elements inside a ScalarVariable.)
pub const CHOICES_TOOL: &str = "stickslip";

/// The choice variables of the table: (name, values).
pub(super) fn choice_variables<M>(variables: &[Variable<M>]) -> Vec<(&'static str, &ChoiceType)> {
    variables
        .iter()
        .filter_map(|v| match &v.access {
            Access::Choice { kind, .. } => Some((v.name, kind)),
            _ => None,
        })
        .collect()
}

/// The description written for variable `v`: a choice's ends with its codes.
pub fn description<M>(v: &Variable<M>) -> String {
    match &v.access {
        Access::Choice { kind, .. } => format!("{} [{}]", v.description, kind.codes()),
        _ => v.description.to_string(),
    }
}

/// The units of the table's Real variables, in `UNITS` order.
fn units_used<M>(variables: &[Variable<M>]) -> impl Iterator<Item = &'static str> + '_ {
    UNITS
        .iter()
        .filter(|u| {
            variables.iter().any(
                |v| matches!(v.access, Access::Real { unit: Some(name), .. } if name == u.name),
            )
        })
        .map(|u| u.name)
}

/// FMI 3.0 TypeDefinitions: one `<Float64Type>` per unit, named after the unit, which
/// the variables with that unit declare as their type. A unit could also sit on each
/// `<Float64>` itself (the standard allows both), but the `fmi` crate's FMI 3.0 reader
/// refuses a `unit` attribute there and accepts it on a type, as Reference-FMUs write it.
fn write_float64_types<M>(w: &mut String, variables: &[Variable<M>]) {
    let _ = writeln!(w, "  <TypeDefinitions>");
    for unit in units_used(variables) {
        let _ = writeln!(
            w,
            r#"    <Float64Type name="{}" unit="{}"/>"#,
            escape(unit),
            escape(unit)
        );
    }
    let _ = writeln!(w, "  </TypeDefinitions>");
}

/// A unit as FMI's `<Unit>` (`prefix` "") or SSP's `<ssc:Unit>` (`prefix` "ssc:") gives
/// it: its name and its nonzero SI exponents of kg, m and s on the `BaseUnit`.
pub fn unit_element(unit: &Unit, prefix: &str) -> String {
    let mut exponents = String::new();
    for (base, exponent) in [("kg", unit.kg), ("m", unit.m), ("s", unit.s)] {
        if exponent != 0 {
            let _ = write!(exponents, r#" {base}="{exponent}""#);
        }
    }
    format!(
        "<{prefix}Unit{}><{prefix}BaseUnit{exponents}/></{prefix}Unit>",
        attribute("name", unit.name)
    )
}

/// UnitDefinitions, (FMI 3.0: TypeDefinitions,) LogCategories and DefaultExperiment.
pub(super) fn write_units_categories_experiment<M: Model>(
    w: &mut String,
    variables: &[Variable<M>],
    version: FmiVersion,
) {
    let info = &M::INFO;
    let _ = writeln!(w, "  <UnitDefinitions>");
    for unit in UNITS.iter().filter(|u| {
        variables
            .iter()
            .any(|v| matches!(v.access, Access::Real { unit: Some(name), .. } if name == u.name))
    }) {
        let _ = writeln!(w, "    {}", unit_element(unit, ""));
    }
    let _ = writeln!(w, "  </UnitDefinitions>");
    if version == FmiVersion::V3 {
        write_float64_types(w, variables);
    }

    let _ = writeln!(w, "  <LogCategories>");
    for category in LOG_CATEGORIES {
        let _ = writeln!(
            w,
            r#"    <Category name="{}" description="{}"/>"#,
            category.name,
            escape(&(category.description)(version.names()))
        );
    }
    let _ = writeln!(w, "  </LogCategories>");
    let _ = writeln!(
        w,
        r#"  <DefaultExperiment startTime="{}" stopTime="{}" stepSize="{}"/>"#,
        real(info.start_time),
        real(info.stop_time),
        real(info.step_size)
    );
}

/// An output's dependencies as ModelStructure lists them: (1-based ScalarVariable
/// index, kind), ordered by index.
pub struct IndexedDependencies {
    /// At communication points (`Outputs`): the inputs.
    pub step: Vec<(usize, DependencyKind)>,
    /// In Initialization Mode (`InitialUnknowns`): inputs and parameters. Every
    /// parameter is a known that can still change there, so a factor that is fixed at
    /// communication points is not fixed there: no kinds but "dependent", which is
    /// what an absent `dependenciesKind` says.
    pub initial: Vec<usize>,
}

/// Every output of the table, in table order, with its 1-based index and its
/// dependencies as indices. `Outputs` must list every output and `InitialUnknowns` every
/// output with `initial = "calculated"`, which ours all are; both in index order.
pub fn output_dependencies<M>(variables: &[Variable<M>]) -> Vec<(usize, IndexedDependencies)> {
    let index_of = |vr: u32| {
        variables
            .iter()
            .position(|v| v.value_reference == vr)
            .map(|k| k + 1)
            .unwrap_or_else(|| {
                panic!("a dependency names value reference {vr}, which no variable has")
            })
    };
    variables
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Output)
        .map(|(k, v)| {
            let depends_on = v
                .depends_on
                .unwrap_or_else(|| panic!("output {} declares no dependencies", v.name));
            let mut step: Vec<(usize, DependencyKind)> = depends_on
                .inputs
                .iter()
                .map(|(vr, kind)| (index_of(*vr), *kind))
                .collect();
            step.sort_by_key(|(k, _)| *k);
            step.dedup_by_key(|(k, _)| *k);
            let knowns: Vec<u32> = match depends_on.initial {
                InitialDependencies::InputsAnd(parameters) => depends_on
                    .inputs
                    .iter()
                    .map(|(vr, _)| *vr)
                    .chain(parameters.iter().copied())
                    .collect(),
                InitialDependencies::AllParametersAnd(inputs) => variables
                    .iter()
                    .filter(|p| p.causality == Causality::Parameter)
                    .map(|p| p.value_reference)
                    .chain(inputs.iter().copied())
                    .collect(),
            };
            let mut initial: Vec<usize> = knowns.into_iter().map(index_of).collect();
            initial.sort_unstable();
            initial.dedup();
            (k + 1, IndexedDependencies { step, initial })
        })
        .collect()
}

/// The dependencies of each of `dynamic` (by position), those of its `like` row among
/// `dependencies` (what [`output_dependencies`] gave for `variables`).
pub(super) fn dynamic_dependencies<'a, M>(
    variables: &[Variable<M>],
    dependencies: &'a [(usize, IndexedDependencies)],
    dynamic: &[DynamicOutput],
) -> Vec<&'a IndexedDependencies> {
    dynamic
        .iter()
        .map(|o| {
            let like = variables
                .iter()
                .position(|v| v.value_reference == o.like)
                .map(|k| k + 1);
            dependencies
                .iter()
                .find(|(k, _)| Some(*k) == like)
                .map(|(_, d)| d)
                .unwrap_or_else(|| {
                    panic!(
                        "dynamic output {} is like value reference {}, which is no output",
                        o.name, o.like
                    )
                })
        })
        .collect()
}

/// ` dependencies="..."`, and ` dependenciesKind="..."` when there are kinds. An empty
/// list is written as `dependencies=""`: the unknown depends on none of the knowns (an
/// absent attribute would mean all of them).
pub(super) fn dependency_attributes(indices: &[usize], kinds: &[DependencyKind]) -> String {
    let indices: Vec<String> = indices.iter().map(usize::to_string).collect();
    let mut attributes = format!(r#" dependencies="{}""#, indices.join(" "));
    if !kinds.is_empty() {
        let kinds: Vec<&str> = kinds.iter().map(|kind| kind.as_str()).collect();
        let _ = write!(attributes, r#" dependenciesKind="{}""#, kinds.join(" "));
    }
    attributes
}
