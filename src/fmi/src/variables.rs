//! The one table of an FMU's variables.
//!
//! Each model lists its variables once, as `Variable`s: name, value reference,
//! causality, variability, unit, description, and the functions that read and write the
//! value in the model. The modelDescription.xml is generated from this table (start
//! values are read from a model with default settings), and the FMI calls dispatch
//! through it, so the XML and the binary cannot disagree.

pub use stickslip::choice::{choice_at, ChoiceType};

/// FMI 2.0 causality (only the ones our models use).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    Input,
    Output,
}

impl Causality {
    pub fn as_str(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
        }
    }
}

/// FMI 2.0 variability (only the ones our models use).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    /// Set before initialisation ends, then constant.
    Fixed,
    /// Changes only at communication points (Integer, Boolean outputs).
    Discrete,
    /// Real inputs and outputs.
    Continuous,
}

impl Variability {
    pub fn as_str(self) -> &'static str {
        match self {
            Variability::Fixed => "fixed",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

/// Reads a value off model `M`. A function rather than a field path, so that rows can
/// be made from data (a law's parameters come from the registry,
/// `stickslip::friction::registry`, and are read by their name).
pub type Getter<M, T> = Box<dyn Fn(&M) -> T + Send + Sync>;

/// Writes a value into model `M`, or says why it refuses it.
pub type Setter<M, T> = Option<Box<dyn Fn(&mut M, T) -> Result<(), String> + Send + Sync>>;

/// Writes a string into model `M`, or says why it refuses it.
pub type StringSetter<M> = Option<Box<dyn Fn(&mut M, &str) -> Result<(), String> + Send + Sync>>;

/// How a variable of model `M` is read and written. A setter returns the reason when it
/// refuses a value.
pub enum Access<M: 'static> {
    Real {
        /// Unit name from `UNITS`, or None for dimensionless.
        unit: Option<&'static str>,
        get: Getter<M, f64>,
        set: Setter<M, f64>,
    },
    Integer {
        min: i32,
        max: i32,
        get: Getter<M, i32>,
        set: Setter<M, i32>,
    },
    Boolean {
        get: Getter<M, bool>,
        set: Setter<M, bool>,
    },
    /// A closed set of values, set and read as its code (an FMI Integer, see
    /// [`ChoiceType`]).
    Choice {
        kind: ChoiceType,
        get: Getter<M, i32>,
        set: Setter<M, i32>,
    },
    String {
        get: Getter<M, String>,
        set: StringSetter<M>,
    },
}

/// The FMI base type of a variable, for type-checked get/set calls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BaseType {
    Real,
    /// Integer variables, choices included.
    Integer,
    Boolean,
    String,
}

impl<M> Access<M> {
    pub fn base_type(&self) -> BaseType {
        match self {
            Access::Real { .. } => BaseType::Real,
            Access::Integer { .. } | Access::Choice { .. } => BaseType::Integer,
            Access::Boolean { .. } => BaseType::Boolean,
            Access::String { .. } => BaseType::String,
        }
    }

    pub fn is_settable(&self) -> bool {
        match self {
            Access::Real { set, .. } => set.is_some(),
            Access::Integer { set, .. } => set.is_some(),
            Access::Boolean { set, .. } => set.is_some(),
            Access::Choice { set, .. } => set.is_some(),
            Access::String { set, .. } => set.is_some(),
        }
    }
}

/// How a known enters an output (FMI 2.0 section 2.2.8, attribute `dependenciesKind`;
/// only the kinds our models use).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DependencyKind {
    /// No particular structure: y = h(..., v, ...).
    Dependent,
    /// A fixed factor: y = p v, with p fixed once fmi2ExitInitializationMode returns (a
    /// function of `fixed` parameters). Only for Real outputs at communication points.
    Fixed,
    /// A constant factor: y = c v, c known before the FMU runs.
    Constant,
}

impl DependencyKind {
    pub fn as_str(self) -> &'static str {
        match self {
            DependencyKind::Dependent => "dependent",
            DependencyKind::Fixed => "fixed",
            DependencyKind::Constant => "constant",
        }
    }
}

/// The knowns an output is computed from in Initialization Mode (FMI 2.0 section 2.2.8,
/// `InitialUnknowns`): there the knowns are the inputs and every variable with
/// `initial = "exact"`, which for our models are the parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InitialDependencies {
    /// The inputs of [`Dependencies::inputs`] and these parameters (value references).
    InputsAnd(&'static [u32]),
    /// Every parameter and these inputs (value references).
    AllParametersAnd(&'static [u32]),
}

/// What an output depends on, written to the ModelStructure of modelDescription.xml
/// (FMI 2.0 section 2.2.8). A master reads it to know which outputs change as soon as
/// an input is set (direct feedthrough, which can close an algebraic loop between FMUs)
/// and which change only in fmi2DoStep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dependencies {
    /// At a communication point (`Outputs`): the inputs (value references) that change
    /// the output when set, without a step, and how each enters it. Empty: the output
    /// changes only in fmi2DoStep (`dependencies=""`). States and time are not listed:
    /// the FMU declares no state variables, and a Co-Simulation FMU without directional
    /// derivatives does not list continuous-time dependencies.
    pub inputs: &'static [(u32, DependencyKind)],
    /// In Initialization Mode (`InitialUnknowns`).
    pub initial: InitialDependencies,
}

/// One scalar variable of model `M`.
pub struct Variable<M: 'static> {
    pub name: &'static str,
    pub value_reference: u32,
    pub causality: Causality,
    pub variability: Variability,
    pub description: &'static str,
    pub access: Access<M>,
    /// Outputs only: what the output depends on (None for parameters and inputs).
    pub depends_on: Option<Dependencies>,
}

/// A Real output a model declares beyond its static table, known from its start
/// values: an exported FMU's sensors (`beam::exported`), named by the user's scene.
/// Continuous, `initial = "calculated"`, read through `Model::dynamic_output_value`,
/// never set; its value reference lies above the table's, and its dependencies
/// (ModelStructure) are those of the table's output `like`.
#[derive(Clone, Debug, PartialEq)]
pub struct DynamicOutput {
    pub name: String,
    pub value_reference: u32,
    /// A unit of [`UNITS`].
    pub unit: &'static str,
    pub description: String,
    /// The value reference of the table output computed the same way (from the
    /// simulation's state, changed only by a step).
    pub like: u32,
}

/// An FMI 3.0 array variable made of scalar rows of the same table (one
/// `<Dimension start="N"/>`). The rows stay the variables of the FMI 2.0 description,
/// which has no arrays; the FMI 3.0 description writes the array in place
/// of its first element and leaves the others out, and fmi3GetFloat64/fmi3SetFloat64
/// read and write the elements in this order (a vector: row-major order is this order).
/// The elements must be Real rows of one causality, variability and unit (checked by
/// [`ArrayVariable::check`]).
#[derive(Debug)]
pub struct ArrayVariable {
    pub name: &'static str,
    /// Its own value reference: no FMI 2.0 variable has it, so that no value reference
    /// names a scalar in one version and an array in the other.
    pub value_reference: u32,
    pub description: &'static str,
    /// The value references of its elements in the table, element 1 first.
    pub elements: &'static [u32],
}

impl ArrayVariable {
    /// The array of `arrays` that element `vr` belongs to, with the element's 1-based
    /// index.
    pub fn containing(
        arrays: &'static [ArrayVariable],
        vr: u32,
    ) -> Option<(&'static ArrayVariable, usize)> {
        arrays
            .iter()
            .find_map(|a| a.elements.iter().position(|&e| e == vr).map(|k| (a, k + 1)))
    }

    /// Checks the array against the table: every element exists, is a Real and shares
    /// the first element's causality, variability and unit, and the array's own value
    /// reference names no row. Returns the first element's row.
    pub fn check<M>(&self, table: &'static [Variable<M>]) -> Result<&'static Variable<M>, String> {
        if table
            .iter()
            .any(|v| v.value_reference == self.value_reference)
        {
            return Err(format!(
                "array {}: value reference {} is also a scalar's",
                self.name, self.value_reference
            ));
        }
        let rows: Vec<&'static Variable<M>> = self
            .elements
            .iter()
            .map(|&vr| {
                table
                    .iter()
                    .find(|v| v.value_reference == vr)
                    .ok_or_else(|| {
                        format!("array {}: no element has value reference {vr}", self.name)
                    })
            })
            .collect::<Result<_, _>>()?;
        let first = *rows
            .first()
            .ok_or_else(|| format!("array {} has no elements", self.name))?;
        let unit = |v: &Variable<M>| match v.access {
            Access::Real { unit, .. } => Ok(unit),
            _ => Err(format!(
                "array {}: element {} is not a Real",
                self.name, v.name
            )),
        };
        let first_unit = unit(first)?;
        for row in &rows {
            if unit(row)? != first_unit
                || row.causality != first.causality
                || row.variability != first.variability
            {
                return Err(format!(
                    "array {}: element {} differs from {} in unit, causality or variability",
                    self.name, row.name, first.name
                ));
            }
        }
        Ok(first)
    }
}

/// A unit in SI base-unit exponents (kg, m, s).
#[derive(Debug)]
pub struct Unit {
    pub name: &'static str,
    pub kg: i32,
    pub m: i32,
    pub s: i32,
}

/// Every unit any of our FMUs uses.
pub const UNITS: &[Unit] = &[
    Unit {
        name: "m",
        kg: 0,
        m: 1,
        s: 0,
    },
    Unit {
        name: "s",
        kg: 0,
        m: 0,
        s: 1,
    },
    Unit {
        name: "1/s",
        kg: 0,
        m: 0,
        s: -1,
    },
    Unit {
        name: "m/s",
        kg: 0,
        m: 1,
        s: -1,
    },
    Unit {
        name: "s/m",
        kg: 0,
        m: -1,
        s: 1,
    },
    Unit {
        name: "N",
        kg: 1,
        m: 1,
        s: -2,
    },
    Unit {
        name: "N/m",
        kg: 1,
        m: 0,
        s: -2,
    },
    Unit {
        name: "N.s/m",
        kg: 1,
        m: 0,
        s: -1,
    },
    Unit {
        name: "Pa",
        kg: 1,
        m: -1,
        s: -2,
    },
    Unit {
        name: "kg/m3",
        kg: 1,
        m: -3,
        s: 0,
    },
];

/// Why a get or set was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AccessError {
    #[error("no variable has value reference {0}")]
    UnknownReference(u32),
    #[error("{name} is of type {expected:?}; it cannot be accessed as {called:?}")]
    WrongType {
        name: &'static str,
        expected: BaseType,
        called: BaseType,
    },
    #[error("{name} is an {} and cannot be set", .causality.as_str())]
    NotSettable {
        name: &'static str,
        causality: Causality,
    },
    /// The setter refused the value; `reason` is its message (see [`Setter`]).
    #[error("{name}: {reason}")]
    Refused { name: &'static str, reason: String },
}

/// Finds variable `vr` and checks that it is accessed with its own base type.
pub fn lookup<M>(
    table: &'static [Variable<M>],
    vr: u32,
    called: BaseType,
) -> Result<&'static Variable<M>, AccessError> {
    let variable = table
        .iter()
        .find(|v| v.value_reference == vr)
        .ok_or(AccessError::UnknownReference(vr))?;
    let expected = variable.access.base_type();
    if expected != called {
        return Err(AccessError::WrongType {
            name: variable.name,
            expected,
            called,
        });
    }
    Ok(variable)
}

fn refused(name: &'static str) -> impl Fn(String) -> AccessError {
    move |reason| AccessError::Refused { name, reason }
}

fn not_settable<M>(v: &Variable<M>) -> AccessError {
    AccessError::NotSettable {
        name: v.name,
        causality: v.causality,
    }
}

impl<M> Variable<M> {
    pub fn get_real(&self, model: &M) -> f64 {
        match &self.access {
            Access::Real { get, .. } => get(model),
            _ => f64::NAN,
        }
    }

    pub fn get_integer(&self, model: &M) -> i32 {
        match &self.access {
            Access::Integer { get, .. } | Access::Choice { get, .. } => get(model),
            _ => 0,
        }
    }

    pub fn get_boolean(&self, model: &M) -> bool {
        match &self.access {
            Access::Boolean { get, .. } => get(model),
            _ => false,
        }
    }

    pub fn get_string(&self, model: &M) -> String {
        match &self.access {
            Access::String { get, .. } => get(model),
            _ => String::new(),
        }
    }

    /// Sets a Real; NaN and infinities are refused for every variable.
    pub fn set_real(&self, model: &mut M, value: f64) -> Result<(), AccessError> {
        let Access::Real { set: Some(set), .. } = &self.access else {
            return Err(not_settable(self));
        };
        if !value.is_finite() {
            return Err(AccessError::Refused {
                name: self.name,
                reason: format!("{value} is not a finite number"),
            });
        }
        set(model, value).map_err(refused(self.name))
    }

    /// Sets an Integer or a choice's code, refusing values outside its range (for a
    /// choice, with the allowed codes in the reason).
    pub fn set_integer(&self, model: &mut M, value: i32) -> Result<(), AccessError> {
        match &self.access {
            Access::Integer {
                set: Some(set),
                min,
                max,
                ..
            } => {
                if value < *min || value > *max {
                    return Err(AccessError::Refused {
                        name: self.name,
                        reason: format!("{value} is outside [{min}, {max}]"),
                    });
                }
                set(model, value).map_err(refused(self.name))
            }
            Access::Choice {
                set: Some(set),
                kind,
                ..
            } => {
                kind.item(value).map_err(refused(self.name))?;
                set(model, value).map_err(refused(self.name))
            }
            _ => Err(not_settable(self)),
        }
    }

    pub fn set_boolean(&self, model: &mut M, value: bool) -> Result<(), AccessError> {
        match &self.access {
            Access::Boolean { set: Some(set), .. } => set(model, value).map_err(refused(self.name)),
            _ => Err(not_settable(self)),
        }
    }

    pub fn set_string(&self, model: &mut M, value: &str) -> Result<(), AccessError> {
        match &self.access {
            Access::String { set: Some(set), .. } => set(model, value).map_err(refused(self.name)),
            _ => Err(not_settable(self)),
        }
    }
}

/// Writes every settable variable of `from` into `into` through its setter, so that each
/// value meets the checks an importer's fmi2Set* call meets (a saved state's values,
/// checked as if set one by one). The first refusal names the variable.
pub fn set_all<M>(
    table: &'static [Variable<M>],
    from: &M,
    into: &mut M,
) -> Result<(), AccessError> {
    for v in table {
        if v.causality == Causality::Output || !v.access.is_settable() {
            continue;
        }
        match &v.access {
            Access::Real { get, .. } => v.set_real(into, get(from))?,
            Access::Integer { get, .. } | Access::Choice { get, .. } => {
                v.set_integer(into, get(from))?
            }
            Access::Boolean { get, .. } => v.set_boolean(into, get(from))?,
            Access::String { get, .. } => v.set_string(into, &get(from))?,
        }
    }
    Ok(())
}
