//! SSP 1.0 system files (System Structure and Parameterization, Modelica Association,
//! 2019), written from the same Rust tables as the FMUs, and the link list that
//! `fmucontainer` (fmu-manipulation-toolbox) builds a container FMU from.
//!
//! A [`System`] names its components (an FMU each, under an instance name), the values
//! it gives some of their parameters ([`Component::set`]) and its connections, all by
//! variable name. [`System::check`] resolves every name against the FMU's variable
//! table: a connection must run from an output to an input of the same type, and each
//! parameter value goes through the table's own setter on a default model, which
//! refuses it as the FMU would (a choice's word becomes its code here). The parameter
//! values written are then read back from that model: every parameter of the FMU, at
//! its default unless the system sets it. So a user who edits the `.ssd` finds every
//! parameter there, with its unit.
//!
//! The `.ssp` archive holds `SystemStructure.ssd` at its root and the FMUs under
//! `resources/`; it is reproducible like the FMUs (fixed entry order and timestamps).
//! The SSD uses only what libcosim, Ecos, fmpy and fmucontainer read:
//! - the prefixes `ssd:`, `ssc:`, `ssv:` (libcosim's reader looks elements up by
//!   prefixed name);
//! - one inline `ssv:ParameterSet` per component, named [`PARAMETER_SET`], with
//!   `ssv:Real`, `ssv:Integer`, `ssv:Boolean` and `ssv:String` values only (libcosim
//!   aborts on `ssv:Enumeration`, Ecos refuses it). Ecos applies a parameter set only
//!   when it is named at initialisation (`init(parameter_set="initialValues")`);
//!   libcosim takes the first set of each component;
//! - connectors for the connected inputs and for every output (fmpy's SSP runner sets
//!   each input connector before every step, to 0 when nothing feeds it, so an
//!   unconnected input must not be a connector). Parameters need no connector: SSP 1.0
//!   applies a parameter set to the FMU variables of the same names;
//! - the communication step h in the Open Simulation Platform's annotation of the
//!   default experiment (`osp:FixedStepAlgorithm baseStepSize`), which libcosim reads
//!   when no step is passed; SSP 1.0 itself has no step size.

use crate::archive::{write_zip, Entry};
use crate::{io, BuildError};
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use stickslip::friction::tabulated::TABLE_VELOCITIES;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::model::Model;
use stickslip_fmi::model_description::unit_element;
use stickslip_fmi::variables::{Access, AccessError, Causality, UNITS};
use stickslip_fmi::xml::{escape, optional_attribute, real};
use stickslip_fmi::FmuKind;
use zip::CompressionMethod;

/// Name of the parameter set of every component: the name Ecos's own SSP examples use,
/// and the one to pass to ecospy's `init(parameter_set=...)`.
pub const PARAMETER_SET: &str = "initialValues";

/// The `source` folder of the FMUs inside an `.ssp`.
const RESOURCES: &str = "resources";

/// A value the system gives a parameter, as in the FMU's table: a choice by its word.
#[derive(Clone, Debug, PartialEq)]
pub enum Setting {
    Real(f64),
    Integer(i32),
    Boolean(bool),
    String(&'static str),
    /// A choice variable's word (the scene file's), written as its code.
    Choice(&'static str),
}

/// A parameter value as written: the four SSP value types libcosim and Ecos read.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// Value and unit (None: dimensionless).
    Real(f64, Option<&'static str>),
    Integer(i32),
    Boolean(bool),
    String(String),
}

impl Value {
    /// The `ssv:` element, e.g. `<ssv:Real value="2.0" unit="m"/>`.
    fn ssv(&self) -> String {
        match self {
            Value::Real(value, unit) => format!(
                r#"<ssv:Real value="{}"{}/>"#,
                real(*value),
                optional_attribute("unit", *unit)
            ),
            Value::Integer(value) => format!(r#"<ssv:Integer value="{value}"/>"#),
            Value::Boolean(value) => format!(r#"<ssv:Boolean value="{value}"/>"#),
            Value::String(value) => format!(r#"<ssv:String value="{}"/>"#, escape(value)),
        }
    }

    /// The value as fmucontainer's START rule reads it.
    fn text(&self) -> String {
        match self {
            Value::Real(value, _) => real(*value),
            Value::Integer(value) => value.to_string(),
            Value::Boolean(value) => value.to_string(),
            Value::String(value) => value.clone(),
        }
    }
}

/// The type of a connector, as `ssc:` names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConnectorType {
    /// With its unit (None: dimensionless).
    Real(Option<&'static str>),
    Integer,
    Boolean,
    String,
}

impl ConnectorType {
    fn ssc(self) -> String {
        match self {
            ConnectorType::Real(unit) => format!("<ssc:Real{}/>", optional_attribute("unit", unit)),
            ConnectorType::Integer => "<ssc:Integer/>".into(),
            ConnectorType::Boolean => "<ssc:Boolean/>".into(),
            ConnectorType::String => "<ssc:String/>".into(),
        }
    }
}

/// One variable of an FMU's table, as a system file needs it.
#[derive(Clone, Debug, PartialEq)]
pub struct Port {
    pub name: &'static str,
    pub causality: Causality,
    pub kind: ConnectorType,
}

/// Why a system does not fit the FMUs' tables.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SspError {
    #[error("system {system}: component {component} appears twice")]
    DuplicateComponent {
        system: &'static str,
        component: &'static str,
    },
    #[error("system {system}: no component named {component}")]
    UnknownComponent {
        system: &'static str,
        component: &'static str,
    },
    #[error("system {system}: {fmu} has no variable {variable}")]
    UnknownVariable {
        system: &'static str,
        fmu: &'static str,
        variable: &'static str,
    },
    #[error("system {system}: {component}.{variable} has causality {causality}, not {expected}")]
    WrongCausality {
        system: &'static str,
        component: &'static str,
        variable: &'static str,
        causality: &'static str,
        expected: &'static str,
    },
    #[error("system {system}: {from} and {to} have different types ({from_type:?}, {to_type:?})")]
    TypeMismatch {
        system: &'static str,
        from: String,
        to: String,
        from_type: ConnectorType,
        to_type: ConnectorType,
    },
    #[error("system {system}: {component}.{variable} is fed twice")]
    InputFedTwice {
        system: &'static str,
        component: &'static str,
        variable: &'static str,
    },
    #[error("system {system}: {component}.{variable} = {setting:?}: {reason}")]
    Refused {
        system: &'static str,
        component: &'static str,
        variable: &'static str,
        setting: Setting,
        reason: String,
    },
}

/// One FMU in a system.
#[derive(Clone, Debug)]
pub struct Component {
    /// Instance name (the SSD's element name; the master's instance name).
    pub name: &'static str,
    pub fmu: FmuKind,
    /// Parameter values the system sets; the other parameters keep their defaults.
    pub set: Vec<(&'static str, Setting)>,
}

/// Output `from` = (component, variable) feeds input `to`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Connection {
    pub from: (&'static str, &'static str),
    pub to: (&'static str, &'static str),
}

/// A system of FMUs: what an `.ssp` holds.
#[derive(Clone, Debug)]
pub struct System {
    /// The file name (without `.ssp`) and the SSD's system name.
    pub name: &'static str,
    pub description: &'static str,
    /// In stepping order for a sequential (Gauss-Seidel) master: each component's
    /// outputs feed the next.
    pub components: Vec<Component>,
    pub connections: Vec<Connection>,
}

/// A component resolved against its FMU's table.
#[derive(Clone, Debug)]
pub struct CheckedComponent {
    pub name: &'static str,
    pub fmu: FmuKind,
    /// Every parameter of the FMU with the value the system gives it, in table order.
    pub parameters: Parameters,
    /// The connected inputs and every output, in table order.
    pub connectors: Vec<Port>,
}

/// A system whose names, types and values fit the FMUs.
#[derive(Clone, Debug)]
pub struct CheckedSystem {
    pub name: &'static str,
    pub description: &'static str,
    pub components: Vec<CheckedComponent>,
    pub connections: Vec<Connection>,
    /// DefaultExperiment (s): the first component's FMU's.
    pub start_time: f64,
    pub stop_time: f64,
    /// The communication step h (s): the first component's FMU's step size.
    pub step_size: f64,
}

/// StickSlipBeam with the external friction law, coupled to NeuralFriction with its
/// default plain network: the beam's sliding velocity drives the friction law, whose
/// force magnitude and static limit come back as the beam's external inputs. (The beam
/// has no normal-force output: both FMUs keep their normal-force input at its start
/// value, as in `python-checks/stickslip_checks/master.py`.) Beam first, so a
/// sequential master steps it as our Gauss-Seidel master does.
pub fn coupled() -> System {
    System {
        name: "StickSlipCoupled",
        description: "StickSlipBeam (friction.law = external, external.coupling = signed) coupled to NeuralFriction (the shipped plain network)",
        components: vec![
            Component {
                name: "beam",
                fmu: FmuKind::StickSlipBeam,
                // The plain network is a smooth signed law, steep at v = 0: the beam
                // reads its tangent (`signed`), not a magnitude along its own v_rel.
                set: vec![
                    ("friction.law", Setting::Choice("external")),
                    ("external.coupling", Setting::Choice("signed")),
                ],
            },
            Component {
                name: "friction",
                fmu: FmuKind::NeuralFriction,
                set: vec![],
            },
        ],
        connections: vec![
            Connection {
                from: ("beam", "relative_velocity"),
                to: ("friction", "sliding_velocity"),
            },
            Connection {
                from: ("friction", "friction_force_magnitude"),
                to: ("beam", "external.kinetic_force"),
            },
            Connection {
                from: ("friction", "static_limit"),
                to: ("beam", "external.static_limit"),
            },
            Connection {
                from: ("friction", "friction_force"),
                to: ("beam", "external.friction_force"),
            },
            Connection {
                from: ("friction", "friction_force_slope"),
                to: ("beam", "external.friction_slope"),
            },
            Connection {
                from: ("friction", "evaluated_velocity"),
                to: ("beam", "external.sliding_velocity"),
            },
            // The step-consistent tangent, which `external.coupling = step` reads (the
            // systems with a law with state); `signed` leaves it unread.
            Connection {
                from: ("friction", "step_friction_force"),
                to: ("beam", "external.step_force"),
            },
            Connection {
                from: ("friction", "step_friction_slope"),
                to: ("beam", "external.step_slope"),
            },
            // The step's mean sliding velocity, with which NeuralFriction commits a law
            // with state where its `state_velocity` says so (`auto`: every law with
            // state); a memoryless law has no state to commit and leaves it unread.
            Connection {
                from: ("beam", "mean_relative_velocity"),
                to: ("friction", "mean_sliding_velocity"),
            },
        ],
    }
}

/// [`coupled`] with NeuralFriction running the shipped learned law with memory
/// (`weights = rate-and-state-learned.json`, a rate-and-state law with a state that
/// NeuralFriction integrates over each communication step): the coupled system with a
/// law that has state, for the masters (issue 24).
pub fn coupled_with_memory() -> System {
    with_friction(
        "StickSlipCoupledMemory",
        "StickSlipBeam (friction.law = external, external.coupling = table) coupled to NeuralFriction running the shipped learned law with memory (rate-and-state-learned.json)",
        ("weights", Setting::String("rate-and-state-learned.json")),
    )
}

/// [`coupled`] with NeuralFriction running `law = rate-and-state` at its default
/// parameters (the scene's: aging law, b > a, stick-slip on the paper's beam): the
/// coupled system with a state-variable law whose state output `state_theta` the
/// masters can record.
pub fn coupled_rate_and_state() -> System {
    with_law(
        "StickSlipCoupledRateState",
        "StickSlipBeam (friction.law = external, external.coupling = table) coupled to NeuralFriction running law = rate-and-state (default parameters)",
        "rate-and-state",
    )
}

/// [`coupled`] with NeuralFriction running `law = lugre` at its default parameters
/// (bristle state `bristle_deflection`, g(v) NeuralFriction's exponential law).
pub fn coupled_lugre() -> System {
    with_law(
        "StickSlipCoupledLuGre",
        "StickSlipBeam (friction.law = external, external.coupling = table) coupled to NeuralFriction running law = lugre (default parameters)",
        "lugre",
    )
}

/// [`coupled`] under `name`, with NeuralFriction's `law` choice set to `law` (the other
/// parameters at their defaults).
fn with_law(name: &'static str, description: &'static str, law: &'static str) -> System {
    with_friction(name, description, ("law", Setting::Choice(law)))
}

/// [`coupled`] under `name`, with one parameter of NeuralFriction set (the others at
/// their defaults).
fn with_friction(
    name: &'static str,
    description: &'static str,
    setting: (&'static str, Setting),
) -> System {
    let mut system = coupled();
    system.name = name;
    system.description = description;
    let friction = system
        .components
        .iter_mut()
        .find(|c| c.fmu == FmuKind::NeuralFriction)
        .expect("the coupled system has a NeuralFriction");
    friction.set = vec![setting];
    // A law with state: the beam reads both its force curves tabulated (issue 36).
    let beam = system
        .components
        .iter_mut()
        .find(|c| c.fmu == FmuKind::StickSlipBeam)
        .expect("the coupled system has a StickSlipBeam");
    for (name, value) in &mut beam.set {
        if *name == "external.coupling" {
            *value = Setting::Choice("table");
        }
    }
    system.connections.extend(table_connections());
    system
}

/// The `table` coupling's links: NeuralFriction's `table_friction_force_i` and
/// `table_step_friction_force_i` into StickSlipBeam's `external.table_force_i` and
/// `external.table_step_force_i`, node by node
/// (`stickslip::friction::tabulated::TABLE_VELOCITIES`).
fn table_connections() -> Vec<Connection> {
    // Names made once per system, as the FMUs' own tables make them.
    let name = |text: String| -> &'static str { Box::leak(text.into_boxed_str()) };
    (0..TABLE_VELOCITIES.len())
        .flat_map(|i| {
            [
                Connection {
                    from: ("friction", name(format!("table_friction_force_{i}"))),
                    to: ("beam", name(format!("external.table_force_{i}"))),
                },
                Connection {
                    from: ("friction", name(format!("table_step_friction_force_{i}"))),
                    to: ("beam", name(format!("external.table_step_force_{i}"))),
                },
            ]
        })
        .collect()
}

/// StickSlipBeam alone with the shipped plain network as its embedded friction law:
/// the monolithic counterpart of [`coupled`].
pub fn monolithic() -> System {
    System {
        name: "StickSlipMonolithic",
        description: "StickSlipBeam with the shipped plain network as its own friction law (friction.law = neural)",
        components: vec![Component {
            name: "beam",
            fmu: FmuKind::StickSlipBeam,
            set: vec![("friction.law", Setting::Choice("neural"))],
        }],
        connections: vec![],
    }
}

/// Every system fmu-build writes.
pub fn systems() -> Vec<System> {
    vec![
        coupled(),
        coupled_with_memory(),
        coupled_rate_and_state(),
        coupled_lugre(),
        monolithic(),
    ]
}

/// The variables of an FMU's table as ports.
pub fn ports(fmu: FmuKind) -> Vec<Port> {
    fn of<M: Model>() -> Vec<Port> {
        M::variables()
            .iter()
            .map(|v| Port {
                name: v.name,
                causality: v.causality,
                kind: match &v.access {
                    Access::Real { unit, .. } => ConnectorType::Real(*unit),
                    Access::Integer { .. } | Access::Choice { .. } => ConnectorType::Integer,
                    Access::Boolean { .. } => ConnectorType::Boolean,
                    Access::String { .. } => ConnectorType::String,
                },
            })
            .collect()
    }
    match fmu {
        FmuKind::StickSlipBeam => of::<StickSlipBeam>(),
        FmuKind::NeuralFriction => of::<NeuralFriction>(),
    }
}

/// Parameter names and values, in table order.
pub type Parameters = Vec<(&'static str, Value)>;

/// A parameter setting the FMU's table refuses: the variable, the setting and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Refusal {
    pub variable: &'static str,
    pub setting: Setting,
    pub reason: String,
}

/// Every parameter of the FMU `fmu` after `set`, in table order: `set` goes through the
/// table's setters on a default model, and the values are read back from it.
pub fn parameter_values(
    fmu: FmuKind,
    set: &[(&'static str, Setting)],
) -> Result<Parameters, Refusal> {
    fn of<M: Model>(set: &[(&'static str, Setting)]) -> Result<Parameters, Refusal> {
        let mut model = M::with_defaults();
        let variables = M::variables();
        for (name, setting) in set {
            let refused = |reason: String| Refusal {
                variable: name,
                setting: setting.clone(),
                reason,
            };
            let variable = variables
                .iter()
                .find(|v| v.name == *name)
                .ok_or_else(|| refused("no such variable".into()))?;
            if variable.causality != Causality::Parameter {
                return Err(refused(format!(
                    "an {} is not a parameter",
                    variable.causality.as_str()
                )));
            }
            let result: Result<(), AccessError> = match (&variable.access, setting) {
                (Access::Real { .. }, Setting::Real(x)) => variable.set_real(&mut model, *x),
                (Access::Integer { .. }, Setting::Integer(n)) => {
                    variable.set_integer(&mut model, *n)
                }
                (Access::Boolean { .. }, Setting::Boolean(b)) => {
                    variable.set_boolean(&mut model, *b)
                }
                (Access::String { .. }, Setting::String(s)) => variable.set_string(&mut model, s),
                (Access::Choice { kind, .. }, Setting::Choice(word)) => {
                    let code = kind
                        .items()
                        .find(|(_, w, _)| w == word)
                        .map(|(code, _, _)| code)
                        .ok_or_else(|| {
                            refused(format!(
                                "not a {} word; allowed: {}",
                                kind.name,
                                kind.codes()
                            ))
                        })?;
                    variable.set_integer(&mut model, code)
                }
                _ => return Err(refused("the setting's type is not the variable's".into())),
            };
            result.map_err(|e| refused(e.to_string()))?;
        }
        Ok(variables
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
            .map(|v| {
                let value = match &v.access {
                    Access::Real { unit, .. } => Value::Real(v.get_real(&model), *unit),
                    Access::Integer { .. } | Access::Choice { .. } => {
                        Value::Integer(v.get_integer(&model))
                    }
                    Access::Boolean { .. } => Value::Boolean(v.get_boolean(&model)),
                    Access::String { .. } => Value::String(v.get_string(&model)),
                };
                (v.name, value)
            })
            .collect())
    }
    match fmu {
        FmuKind::StickSlipBeam => of::<StickSlipBeam>(set),
        FmuKind::NeuralFriction => of::<NeuralFriction>(set),
    }
}

impl System {
    /// Resolves every name against the FMUs' tables (see the module documentation).
    pub fn check(&self) -> Result<CheckedSystem, SspError> {
        let system = self.name;
        for (k, c) in self.components.iter().enumerate() {
            if self.components[..k].iter().any(|d| d.name == c.name) {
                return Err(SspError::DuplicateComponent {
                    system,
                    component: c.name,
                });
            }
        }
        self.check_connections()?;
        let components = self
            .components
            .iter()
            .map(|c| self.checked_component(c))
            .collect::<Result<Vec<_>, SspError>>()?;
        let info = self
            .components
            .first()
            .map(|c| c.fmu.info())
            .unwrap_or(FmuKind::StickSlipBeam.info());
        Ok(CheckedSystem {
            name: self.name,
            description: self.description,
            components,
            connections: self.connections.clone(),
            start_time: info.start_time,
            stop_time: info.stop_time,
            step_size: info.step_size,
        })
    }

    /// Every connection runs from an output to an input of the same type, and no input
    /// is fed twice.
    fn check_connections(&self) -> Result<(), SspError> {
        let system = self.name;
        for (k, link) in self.connections.iter().enumerate() {
            let from = self.port(link.from, Causality::Output)?;
            let to = self.port(link.to, Causality::Input)?;
            if from.kind != to.kind {
                return Err(SspError::TypeMismatch {
                    system,
                    from: format!("{}.{}", link.from.0, link.from.1),
                    to: format!("{}.{}", link.to.0, link.to.1),
                    from_type: from.kind,
                    to_type: to.kind,
                });
            }
            if self.connections[..k].iter().any(|l| l.to == link.to) {
                return Err(SspError::InputFedTwice {
                    system,
                    component: link.to.0,
                    variable: link.to.1,
                });
            }
        }
        Ok(())
    }

    /// The port `variable` of `component`, which must have causality `expected`.
    fn port(
        &self,
        (component, variable): (&'static str, &'static str),
        expected: Causality,
    ) -> Result<Port, SspError> {
        let system = self.name;
        let fmu = self
            .components
            .iter()
            .find(|c| c.name == component)
            .ok_or(SspError::UnknownComponent { system, component })?
            .fmu;
        let port = ports(fmu).into_iter().find(|p| p.name == variable).ok_or(
            SspError::UnknownVariable {
                system,
                fmu: fmu.model_identifier(),
                variable,
            },
        )?;
        if port.causality != expected {
            return Err(SspError::WrongCausality {
                system,
                component,
                variable,
                causality: port.causality.as_str(),
                expected: expected.as_str(),
            });
        }
        Ok(port)
    }

    /// `c` with its parameter values resolved and its connectors: every output, and the
    /// inputs a connection feeds.
    fn checked_component(&self, c: &Component) -> Result<CheckedComponent, SspError> {
        let parameters = parameter_values(c.fmu, &c.set).map_err(|r| SspError::Refused {
            system: self.name,
            component: c.name,
            variable: r.variable,
            setting: r.setting,
            reason: r.reason,
        })?;
        let connectors = ports(c.fmu)
            .into_iter()
            .filter(|p| match p.causality {
                Causality::Output => true,
                Causality::Input => self.connections.iter().any(|l| l.to == (c.name, p.name)),
                Causality::Parameter => false,
            })
            .collect();
        Ok(CheckedComponent {
            name: c.name,
            fmu: c.fmu,
            parameters,
            connectors,
        })
    }
}

/// The path of an FMU inside the `.ssp`.
fn source(fmu: FmuKind) -> String {
    format!("{RESOURCES}/{}.fmu", fmu.model_identifier())
}

/// `<ssc:Unit>` elements for the units `used` (in `UNITS` order), indented by `indent`.
fn units(used: &[&str], indent: &str) -> String {
    let mut x = String::new();
    for unit in UNITS.iter().filter(|u| used.contains(&u.name)) {
        let _ = writeln!(x, "{indent}{}", unit_element(unit, "ssc:"));
    }
    x
}

/// The units of a component's parameter values, in first-use order.
fn parameter_units(c: &CheckedComponent) -> Vec<&'static str> {
    c.parameters
        .iter()
        .filter_map(|(_, value)| match value {
            Value::Real(_, unit) => *unit,
            _ => None,
        })
        .collect()
}

/// The units of a component's connectors and parameter values.
fn component_units(c: &CheckedComponent) -> Vec<&'static str> {
    let mut used = parameter_units(c);
    used.extend(c.connectors.iter().filter_map(|p| match p.kind {
        ConnectorType::Real(unit) => unit,
        _ => None,
    }));
    used
}

/// A component's `<ssd:Component>`: its connectors and its parameter set, which
/// declares the units its values use (SSP 1.0, ssv:Units).
fn write_component(w: &mut String, c: &CheckedComponent) {
    let _ = writeln!(
        w,
        r#"      <ssd:Component name="{}" type="application/x-fmu-sharedlibrary" source="{}">"#,
        escape(c.name),
        source(c.fmu)
    );
    let _ = writeln!(w, "        <ssd:Connectors>");
    for p in &c.connectors {
        let _ = writeln!(
            w,
            r#"          <ssd:Connector name="{}" kind="{}">{}</ssd:Connector>"#,
            escape(p.name),
            p.causality.as_str(),
            p.kind.ssc()
        );
    }
    let _ = writeln!(w, "        </ssd:Connectors>");
    let _ = writeln!(w, "        <ssd:ParameterBindings>");
    let _ = writeln!(w, "          <ssd:ParameterBinding>");
    let _ = writeln!(w, "            <ssd:ParameterValues>");
    let _ = writeln!(
        w,
        r#"              <ssv:ParameterSet version="1.0" name="{PARAMETER_SET}">"#
    );
    let _ = writeln!(w, "                <ssv:Parameters>");
    for (name, value) in &c.parameters {
        let _ = writeln!(
            w,
            r#"                  <ssv:Parameter name="{}">{}</ssv:Parameter>"#,
            escape(name),
            value.ssv()
        );
    }
    let _ = writeln!(w, "                </ssv:Parameters>");
    let used = parameter_units(c);
    if !used.is_empty() {
        let _ = writeln!(w, "                <ssv:Units>");
        let _ = write!(w, "{}", units(&used, "                  "));
        let _ = writeln!(w, "                </ssv:Units>");
    }
    let _ = writeln!(w, "              </ssv:ParameterSet>");
    let _ = writeln!(w, "            </ssd:ParameterValues>");
    let _ = writeln!(w, "          </ssd:ParameterBinding>");
    let _ = writeln!(w, "        </ssd:ParameterBindings>");
    let _ = writeln!(w, "      </ssd:Component>");
}

impl CheckedSystem {
    /// `SystemStructure.ssd`.
    pub fn ssd(&self) -> String {
        let mut x = String::new();
        let w = &mut x;
        let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
        let _ = writeln!(
            w,
            r#"<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" xmlns:osp="http://opensimulationplatform.com/SSP/OSPAnnotations" version="1.0" name="{}" generationTool="stickslip {}">"#,
            escape(self.name),
            env!("CARGO_PKG_VERSION")
        );
        let _ = writeln!(
            w,
            r#"  <ssd:System name="{}" description="{}">"#,
            escape(self.name),
            escape(self.description)
        );
        let _ = writeln!(w, "    <ssd:Elements>");
        for c in &self.components {
            write_component(w, c);
        }
        let _ = writeln!(w, "    </ssd:Elements>");
        if !self.connections.is_empty() {
            let _ = writeln!(w, "    <ssd:Connections>");
            for link in &self.connections {
                let _ = writeln!(
                    w,
                    r#"      <ssd:Connection startElement="{}" startConnector="{}" endElement="{}" endConnector="{}"/>"#,
                    escape(link.from.0),
                    escape(link.from.1),
                    escape(link.to.0),
                    escape(link.to.1)
                );
            }
            let _ = writeln!(w, "    </ssd:Connections>");
        }
        let _ = writeln!(w, "  </ssd:System>");
        let used: Vec<&str> = self.components.iter().flat_map(component_units).collect();
        if !used.is_empty() {
            let _ = writeln!(w, "  <ssd:Units>");
            let _ = write!(w, "{}", units(&used, "    "));
            let _ = writeln!(w, "  </ssd:Units>");
        }
        let _ = writeln!(
            w,
            r#"  <ssd:DefaultExperiment startTime="{}" stopTime="{}">"#,
            real(self.start_time),
            real(self.stop_time)
        );
        let _ = writeln!(w, "    <ssd:Annotations>");
        let _ = writeln!(
            w,
            r#"      <ssc:Annotation type="com.opensimulationplatform"><osp:Algorithm><osp:FixedStepAlgorithm baseStepSize="{}"/></osp:Algorithm></ssc:Annotation>"#,
            real(self.step_size)
        );
        let _ = writeln!(w, "    </ssd:Annotations>");
        let _ = writeln!(w, "  </ssd:DefaultExperiment>");
        let _ = writeln!(w, "</ssd:SystemStructureDescription>");
        x
    }

    /// The link list of `fmucontainer -container NAME.csv:STEP -no-auto-input
    /// -no-auto-output [-sequential]` (fmu-manipulation-toolbox 2.0: `;`-separated rule,
    /// from_fmu, from_port, to_fmu, to_port). The FMUs are named by their file names in
    /// the folder the CSV lies in; the components' order is the stepping order of
    /// `-sequential`. Every output connector becomes a container output and every input
    /// that no connection feeds a container input, both named `component.variable`;
    /// every parameter value becomes a START rule. (Its automatic inputs would try to
    /// expose NeuralFriction's `extra_feature[1..4]` as one FMI 2.0 array and log an
    /// error, hence explicit rules. fmucontainer also reads `.ssp` files, but without
    /// their parameter values or the sequential mode.)
    pub fn container_csv(&self) -> String {
        let file = |component: &str| {
            let fmu = self
                .components
                .iter()
                .find(|c| c.name == component)
                .map(|c| c.fmu)
                .unwrap_or(FmuKind::StickSlipBeam);
            format!("{}.fmu", fmu.model_identifier())
        };
        let mut x = String::from("rule;from_fmu;from_port;to_fmu;to_port\n");
        for c in &self.components {
            let _ = writeln!(x, "FMU;{};;;", file(c.name));
        }
        for link in &self.connections {
            let _ = writeln!(
                x,
                "LINK;{};{};{};{}",
                file(link.from.0),
                link.from.1,
                file(link.to.0),
                link.to.1
            );
        }
        // The inputs nothing feeds become container inputs, named like the outputs.
        for c in &self.components {
            for p in ports(c.fmu).iter().filter(|p| {
                p.causality == Causality::Input
                    && !self.connections.iter().any(|l| l.to == (c.name, p.name))
            }) {
                let _ = writeln!(
                    x,
                    "INPUT;;{}.{};{};{}",
                    c.name,
                    p.name,
                    file(c.name),
                    p.name
                );
            }
        }
        for c in &self.components {
            for p in c
                .connectors
                .iter()
                .filter(|p| p.causality == Causality::Output)
            {
                let _ = writeln!(
                    x,
                    "OUTPUT;{};{};;{}.{}",
                    file(c.name),
                    p.name,
                    c.name,
                    p.name
                );
            }
        }
        for c in &self.components {
            for (name, value) in &c.parameters {
                let _ = writeln!(x, "START;{};{};{};", file(c.name), name, value.text());
            }
        }
        x
    }
}

/// Writes `<out_dir>/<name>.ssp` with the FMUs from `fmu_dir` (as packaged); returns its
/// path.
pub fn write_ssp(
    system: &CheckedSystem,
    fmu_dir: &Path,
    out_dir: &Path,
) -> Result<PathBuf, BuildError> {
    let path = out_dir.join(format!("{}.ssp", system.name));
    let mut entries = vec![Entry::deflated(
        "SystemStructure.ssd",
        system.ssd().into_bytes(),
    )];
    for c in &system.components {
        let name = source(c.fmu);
        if entries.iter().any(|e| e.name == name) {
            continue;
        }
        let fmu = fmu_dir.join(format!("{}.fmu", c.fmu.model_identifier()));
        let bytes = fs::read(&fmu).map_err(io(&fmu))?;
        // The FMUs are zip archives already: stored, not compressed again.
        entries.push(Entry {
            method: CompressionMethod::Stored,
            ..Entry::deflated(name, bytes)
        });
    }
    fs::create_dir_all(out_dir).map_err(io(out_dir))?;
    write_zip(&path, entries)?;
    Ok(path)
}

/// Writes `<out_dir>/<name>.csv`, fmucontainer's link list of `system`; returns its path.
pub fn write_container_csv(system: &CheckedSystem, out_dir: &Path) -> Result<PathBuf, BuildError> {
    let path = out_dir.join(format!("{}.csv", system.name));
    fs::create_dir_all(out_dir).map_err(io(out_dir))?;
    stickslip::files::write_atomically(&path, system.container_csv())?;
    Ok(path)
}
