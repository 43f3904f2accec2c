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

use crate::model::Model;
use crate::variables::{
    Access, ArrayVariable, Causality, ChoiceType, DependencyKind, InitialDependencies, Unit,
    Variability, Variable, UNITS,
};
use crate::version::{FmiVersion, Names};
use crate::xml::{attribute, escape, optional_attribute, real};
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
fn choice_variables<M>(variables: &[Variable<M>]) -> Vec<(&'static str, &ChoiceType)> {
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

fn body<M: Model>(guid: &str) -> String {
    let info = &M::INFO;
    let defaults = M::with_defaults();
    let variables = M::variables();
    let mut x = String::new();
    let w = &mut x;
    // Writing to a String cannot fail.
    let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        w,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="{}" generationTool="stickslip {}" variableNamingConvention="structured" numberOfEventIndicators="0">"#,
        info.model_identifier,
        guid,
        escape(info.description),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        w,
        r#"  <CoSimulation modelIdentifier="{}" needsExecutionTool="false" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" maxOutputDerivativeOrder="0" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true" providesDirectionalDerivative="false"/>"#,
        info.model_identifier
    );

    write_units_categories_experiment(w, variables, FmiVersion::V2);

    write_choices(w, variables);

    let _ = writeln!(w, "  <ModelVariables>");
    for v in variables {
        let initial = match v.causality {
            Causality::Parameter => r#" initial="exact""#,
            Causality::Input => "",
            Causality::Output => r#" initial="calculated""#,
        };
        let _ = writeln!(
            w,
            r#"    <ScalarVariable name="{}" valueReference="{}" description="{}" causality="{}" variability="{}"{initial}>"#,
            escape(v.name),
            v.value_reference,
            escape(&description(v)),
            v.causality.as_str(),
            v.variability.as_str()
        );
        let with_start = v.causality != Causality::Output;
        let element = match &v.access {
            Access::Real { unit, get, .. } => {
                let unit = optional_attribute("unit", *unit);
                let start = if with_start {
                    format!(r#" start="{}""#, real(get(&defaults)))
                } else {
                    String::new()
                };
                format!("<Real{unit}{start}/>")
            }
            Access::Integer { min, max, get, .. } => {
                let start = if with_start {
                    format!(r#" start="{}""#, get(&defaults))
                } else {
                    String::new()
                };
                format!(r#"<Integer min="{min}" max="{max}"{start}/>"#)
            }
            Access::Boolean { get, .. } => {
                let start = if with_start {
                    format!(r#" start="{}""#, get(&defaults))
                } else {
                    String::new()
                };
                format!("<Boolean{start}/>")
            }
            Access::Choice { kind, get, .. } => {
                let start = if with_start {
                    format!(r#" start="{}""#, get(&defaults))
                } else {
                    String::new()
                };
                format!(r#"<Integer min="1" max="{}"{start}/>"#, kind.len)
            }
            Access::String { get, .. } => {
                let start = if with_start {
                    attribute("start", &get(&defaults))
                } else {
                    String::new()
                };
                format!("<String{start}/>")
            }
        };
        let _ = writeln!(w, "      {element}");
        let _ = writeln!(w, "    </ScalarVariable>");
    }
    let _ = writeln!(w, "  </ModelVariables>");

    let _ = writeln!(w, "  <ModelStructure>");
    let _ = writeln!(w, "    <Outputs>");
    let dependencies = output_dependencies(variables);
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
    let _ = writeln!(w, "</fmiModelDescription>");
    debug_assert!(variables.iter().all(|v| match v.causality {
        Causality::Parameter => v.variability == Variability::Fixed,
        _ => v.variability != Variability::Fixed,
    }));
    x
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
fn write_units_categories_experiment<M: Model>(
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

/// The choices' codes and words for programs ([`CHOICES_TOOL`]), in FMI 2.0's
/// `<VendorAnnotations><Tool name=...>` (not in FMI 3.0's description; see [`body3`]).
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

/// The FMI 3.0 modelDescription.xml of the same table (FMI 3.0 standard, section 2.4):
/// the same variables, units, categories and experiment as [`body`], with FMI 3.0's
/// names (Float64, Int32, `instantiationToken`), a `<CoSimulation>` element that says
/// Event Mode for both models and early return where the model has internal events
/// (`ModelInfo::returns_early_at_events`), and ModelStructure by value reference. A choice is an
/// `<Int32 min="1" max="N">`, as in FMI 2.0, so the codes, the scripts that read them
/// from the `stickslip` annotation, and the SSP parameter sets are the same for both
/// versions; their words are in each choice's description. The instantiation token is the FMI 2.0 GUID: both descriptions come from
/// one table, so one hash names the interface, and an FMU state saved through one
/// version restores through the other.
/// The value reference of FMI 3.0's independent variable `time`; no table uses it.
/// fmi3GetFloat64 reads the instance's time there (`values3`).
pub const TIME_VALUE_REFERENCE: u32 = 0;

fn body3<M: Model>(token: &str) -> String {
    let info = &M::INFO;
    let defaults = M::with_defaults();
    let variables = M::variables();
    let mut x = String::new();
    let w = &mut x;
    let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        w,
        r#"<fmiModelDescription fmiVersion="3.0" modelName="{}" instantiationToken="{}" description="{}" generationTool="stickslip {}" variableNamingConvention="structured">"#,
        info.model_identifier,
        token,
        escape(info.description),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        w,
        r#"  <CoSimulation modelIdentifier="{}" needsExecutionTool="false" canBeInstantiatedOnlyOncePerProcess="false" canGetAndSetFMUState="true" canSerializeFMUState="true" providesDirectionalDerivatives="false" providesAdjointDerivatives="false" providesPerElementDependencies="false" canHandleVariableCommunicationStepSize="true" maxOutputDerivativeOrder="0" providesIntermediateUpdate="false" mightReturnEarlyFromDoStep="{}" canReturnEarlyAfterIntermediateUpdate="false" hasEventMode="true" providesEvaluateDiscreteStates="false"/>"#,
        info.model_identifier, info.returns_early_at_events
    );
    write_units_categories_experiment(w, variables, FmiVersion::V3);

    let _ = writeln!(w, "  <ModelVariables>");
    // FMI 3.0 requires exactly one independent variable (section 2.4.7.4); FMI 2.0 left
    // time implicit. It is not in the tables: it is the instance's clock, not a model
    // value; fmi3GetFloat64 reads it and fmi3SetFloat64 refuses it (`values3`).
    let _ = writeln!(
        w,
        r#"    <Float64 name="time" valueReference="{TIME_VALUE_REFERENCE}" description="Simulation time (s)" causality="independent" variability="continuous"/>"#
    );
    for v in variables {
        // An array's elements are rows of the table: the array is written in place of
        // its first element, the other elements not at all.
        if let Some((array, index)) = ArrayVariable::containing(M::arrays(), v.value_reference) {
            if index == 1 {
                write_array(w, array, variables, &defaults);
            }
            continue;
        }
        let initial = match v.causality {
            Causality::Parameter => r#" initial="exact""#,
            Causality::Input => "",
            Causality::Output => r#" initial="calculated""#,
        };
        let with_start = v.causality != Causality::Output;
        let start = |value: String| {
            if with_start {
                format!(r#" start="{value}""#)
            } else {
                String::new()
            }
        };
        let (element, attributes, children) = match &v.access {
            Access::Real { unit, get, .. } => (
                "Float64",
                format!(
                    "{}{}",
                    optional_attribute("declaredType", *unit),
                    start(real(get(&defaults)))
                ),
                None,
            ),
            Access::Integer { min, max, get, .. } => (
                "Int32",
                format!(
                    r#" min="{min}" max="{max}"{}"#,
                    start(get(&defaults).to_string())
                ),
                None,
            ),
            Access::Choice { kind, get, .. } => (
                "Int32",
                format!(
                    r#" min="1" max="{}"{}"#,
                    kind.len,
                    start(get(&defaults).to_string())
                ),
                None,
            ),
            Access::Boolean { get, .. } => ("Boolean", start(get(&defaults).to_string()), None),
            // FMI 3.0 gives a String's start value as a child element.
            Access::String { get, .. } => (
                "String",
                String::new(),
                with_start.then(|| format!(r#"<Start value="{}"/>"#, escape(&get(&defaults)))),
            ),
        };
        let head = format!(
            r#"    <{element} name="{}" valueReference="{}" description="{}" causality="{}" variability="{}"{initial}{attributes}"#,
            escape(v.name),
            v.value_reference,
            escape(&description(v)),
            v.causality.as_str(),
            v.variability.as_str()
        );
        let _ = match children {
            None => writeln!(w, "{head}/>"),
            Some(children) => writeln!(w, "{head}>\n      {children}\n    </{element}>"),
        };
    }
    let _ = writeln!(w, "  </ModelVariables>");

    // The same dependencies as FMI 2.0's, named by value reference instead of index;
    // an array element by its array (no per-element dependencies: the output depends
    // on the whole array if on any element).
    let vr_of = |k: usize| {
        let vr = variables[k - 1].value_reference;
        ArrayVariable::containing(M::arrays(), vr).map_or(vr, |(a, _)| a.value_reference) as usize
    };
    let _ = writeln!(w, "  <ModelStructure>");
    let dependencies = output_dependencies(variables);
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
    // No `stickslip` choices annotation here: FMI 3.0 allows any element inside an
    // <Annotation>, but the `fmi` crate's reader refuses child elements there (it takes
    // text only), and an importer that cannot read the file at all is worse than one
    // that has the codes only in each choice's description. Programs read the codes and
    // words from the FMI 2.0 description, generated from the same table.
    let _ = writeln!(w, "</fmiModelDescription>");
    x
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

/// ` dependencies="..."`, and ` dependenciesKind="..."` when there are kinds. An empty
/// list is written as `dependencies=""`: the unknown depends on none of the knowns (an
/// absent attribute would mean all of them).
fn dependency_attributes(indices: &[usize], kinds: &[DependencyKind]) -> String {
    let indices: Vec<String> = indices.iter().map(usize::to_string).collect();
    let mut attributes = format!(r#" dependencies="{}""#, indices.join(" "));
    if !kinds.is_empty() {
        let kinds: Vec<&str> = kinds.iter().map(|kind| kind.as_str()).collect();
        let _ = write!(attributes, r#" dependenciesKind="{}""#, kinds.join(" "));
    }
    attributes
}

/// 128-bit FNV-1a, written as a GUID.
fn hash_guid(text: &str) -> String {
    let mut h: u128 = 0x6c62272e07bb014262b821756295c58d;
    for byte in text.bytes() {
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
    hash_guid(&body::<M>(""))
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
