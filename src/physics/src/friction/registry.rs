//! The law registry: one [`LawDescription`] per friction law, held in the law's own file,
//! and everything that lists laws or their parameters reads it.
//!
//! A description says how the law is built ([`LawBuild`]), which parameters it takes
//! besides the friction coefficients ([`LawParameter`]: dotted name, unit, range,
//! default, FMI value reference) and which checks span several of them. From it come:
//! - the scene file's `[friction.<section>]` tables and their checks ([`LawTables`]);
//! - the command line's `--law-parameter NAME=VALUE` and `--friction` values;
//! - both FMUs' parameter variables, their start values and their checks, hence the
//!   model descriptions and docs/variables.md (`stickslip_fmi`);
//! - NeuralFriction's list of laws ([`LawDescription::neural_friction_code`]);
//! - the study's law axis (`crate::study::law`, over [`FrictionLawKind::ALL`]).
//!
//! Adding a law: its file (the law, its parameters, its `LAW` description), one variant
//! in [`FrictionLawKind`] with its line in [`FrictionLawKind::description`], its tests.

use super::kind::FrictionLawKind;
use super::law::FrictionLaw;
use super::parameters::ParameterProblem;
use super::state::{StateVariable, StatefulLaw};
use crate::choice::{Choice, ChoiceType};
use serde::de::{self, MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;
use std::sync::Arc;

/// Where a real parameter's value must lie (it must be finite in every case).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// > 0.
    Positive,
    /// >= 0.
    NonNegative,
}

/// What kind of value a law parameter takes.
#[derive(Clone, Copy, Debug)]
pub enum ParameterKind {
    /// A real number in a unit (the FMI unit name, `None` for dimensionless) and a range.
    Real {
        unit: Option<&'static str>,
        range: Range,
    },
    /// One of a closed set of words, held as its 1-based code.
    Choice(ChoiceType),
}

/// One parameter of a law, as the scene file, the command line and both FMUs name it.
#[derive(Clone, Copy, Debug)]
pub struct LawParameter {
    /// Dotted name, `friction.<section>.<key>` (the FMU variable's name, the scene
    /// file's place).
    pub name: &'static str,
    /// One line for people: what it is, with its symbol.
    pub description: &'static str,
    pub kind: ParameterKind,
    /// The default: a real value, or a choice's code.
    pub default: f64,
    /// The FMI value reference, the same in every FMU that has the parameter; fixed once
    /// published (saved states and SSP files hold it).
    pub value_reference: u32,
    /// Whether the force at the law's initial state (before any step) depends on it;
    /// for a law without state, whether the force does at all. (An FMU's outputs in
    /// Initialization Mode depend on exactly these: `stickslip_fmi` declares them.)
    pub initial_force: bool,
    /// Whether the law's initial state depends on it.
    pub initial_state: bool,
}

impl LawParameter {
    /// The key inside the law's table (`bristle_stiffness` of
    /// `friction.lugre.bristle_stiffness`).
    pub fn key(&self) -> &'static str {
        self.name.rsplit('.').next().unwrap_or(self.name)
    }

    /// The FMI unit name, if any (a choice has none).
    pub fn unit(&self) -> Option<&'static str> {
        match self.kind {
            ParameterKind::Real { unit, .. } => unit,
            ParameterKind::Choice(_) => None,
        }
    }

    /// Why `value` is no value of this parameter, if it is not one.
    pub fn problem(&self, value: f64) -> Option<ParameterProblem> {
        let (holds, requirement) = match self.kind {
            ParameterKind::Real { unit, range } => {
                // Messages write products with a space (N s/m), FMI unit names with a dot.
                let unit = unit.unwrap_or("1").replace('.', " ");
                match range {
                    Range::Positive => (value > 0.0, format!("finite and > 0 ({unit})")),
                    Range::NonNegative => (value >= 0.0, format!("finite and >= 0 ({unit})")),
                }
            }
            ParameterKind::Choice(choice) => (
                value.fract() == 0.0 && choice.item(value as i32).is_ok(),
                format!("a {} code: {}", choice.name, choice.codes()),
            ),
        };
        (!(value.is_finite() && holds)).then_some(ParameterProblem {
            field: self.name,
            value,
            requirement,
        })
    }
}

impl LawParameter {
    /// `text` as a value of this parameter: a number, or for a choice its word (held as
    /// its code). The range is not checked here but where the scene is.
    pub fn parse_value(&self, text: &str) -> Result<f64, String> {
        match self.kind {
            ParameterKind::Real { .. } => text
                .trim()
                .parse::<f64>()
                .map_err(|_| format!("{}: '{text}' is not a number", self.name)),
            ParameterKind::Choice(choice) => choice
                .items()
                .find(|(_, word, _)| *word == text.trim())
                .map(|(code, _, _)| f64::from(code))
                .ok_or_else(|| {
                    let words: Vec<&str> = choice.items().map(|(_, w, _)| w).collect();
                    format!(
                        "{}: '{text}' is not a {} value; possible values: {}",
                        self.name,
                        choice.name,
                        words.join(", ")
                    )
                }),
        }
    }
}

/// `NAME=VALUE` (the command line's `--law-parameter`): the parameter named NAME (as
/// [`parameter`] finds it) and VALUE as its value ([`LawParameter::parse_value`]).
pub fn parse_assignment(text: &str) -> Result<(&'static LawParameter, f64), String> {
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| format!("'{text}': expected NAME=VALUE, e.g. lugre.bristle_damping=500"))?;
    let parameter = parameter(name.trim()).ok_or_else(|| {
        let names: Vec<&str> = parameters()
            .map(|p| p.name.trim_start_matches("friction."))
            .collect();
        format!(
            "'{}' is no law parameter; the parameters are {}",
            name.trim(),
            names.join(", ")
        )
    })?;
    Ok((parameter, parameter.parse_value(value)?))
}

/// The friction section's coefficients, which every law may be built from besides its
/// own table: mu_s, mu_k (1) and the decay alpha (s/m) of the paper's Eq. 6.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficients {
    pub static_coefficient: f64,
    pub kinetic_coefficient: f64,
    pub decay: f64,
}

/// How a law is made from a scene's friction section.
#[derive(Clone, Copy)]
pub enum LawBuild {
    /// From the friction section's coefficients and the law's own values in the order of
    /// its parameters, which have passed the scene's check
    /// (`crate::scene::Friction::check`).
    Analytical(fn(&Coefficients, &[f64]) -> Arc<dyn LawPrototype>),
    /// From a network the caller loads (`crate::law_source`).
    Network,
    /// From the inputs of the StickSlipBeam FMU (`friction.law = external`).
    External,
}

/// A law as built from its parameters, at its initial state: each run takes a fresh copy
/// ([`LawPrototype::fresh`]), since a law keeps scratch buffers and state.
pub trait LawPrototype: Send + Sync + fmt::Debug {
    fn fresh(&self) -> Box<dyn FrictionLaw>;
    /// The law, if it has state, to read its parameters and initial state.
    fn as_stateful(&self) -> Option<&dyn StatefulLaw>;
}

impl<L: FrictionLaw + Clone + Sync + fmt::Debug + 'static> LawPrototype for L {
    fn fresh(&self) -> Box<dyn FrictionLaw> {
        Box::new(self.clone())
    }

    fn as_stateful(&self) -> Option<&dyn StatefulLaw> {
        FrictionLaw::as_stateful(self)
    }
}

/// A check over a law's parameter values (in the order of its list): the problem, if any.
pub type JointCheck = fn(&[f64]) -> Option<ParameterProblem>;

/// One law: how it is built and what it takes. Its word and one-line description are
/// its [`FrictionLawKind`]'s.
#[derive(Clone, Copy)]
pub struct LawDescription {
    pub kind: FrictionLawKind,
    pub build: LawBuild,
    /// The law's own parameters (the coefficients mu_s, mu_k, alpha are the friction
    /// section's), all in the table `[friction.<section>]`; empty for none.
    pub parameters: &'static [LawParameter],
    /// A check that spans several of the law's parameters, run after each one's own
    /// range holds; the values in the order of `parameters`.
    pub joint_check: Option<JointCheck>,
    /// Whether the law has internal state ([`super::state`]): no set-valued stick, its
    /// state stepped with the structure.
    pub has_state: bool,
    /// Whether the law models presliding itself (LuGre's bristles hold the tip and let it
    /// creep): a structure coupled to it through an FMU is handed no set-valued static
    /// limit (NeuralFriction's `static_limit` is 0).
    pub presliding: bool,
    /// Its state variables (empty for a memoryless law), each listed in
    /// `super::state::STATE_VARIABLES`.
    pub state_variables: &'static [StateVariable],
    /// Its code in NeuralFriction's parameter `law` (FMI type `FrictionLaw`), if
    /// NeuralFriction evaluates it on its own; codes are fixed once published.
    pub neural_friction_code: Option<i32>,
}

impl fmt::Debug for LawDescription {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LawDescription")
            .field("kind", &self.kind)
            .finish_non_exhaustive()
    }
}

impl LawDescription {
    /// A law without parameters of its own.
    pub const fn plain(kind: FrictionLawKind, build: LawBuild) -> Self {
        Self {
            kind,
            build,
            parameters: &[],
            joint_check: None,
            has_state: false,
            presliding: false,
            state_variables: &[],
            neural_friction_code: None,
        }
    }

    /// The table's name in the scene file (`lugre` of `[friction.lugre]`), if the law
    /// has parameters.
    pub fn section(&self) -> Option<&'static str> {
        let name = self.parameters.first()?.name;
        name.strip_prefix("friction.")?.split('.').next()
    }

    /// The parameters' defaults, in order.
    pub fn defaults(&self) -> Vec<f64> {
        self.parameters.iter().map(|p| p.default).collect()
    }

    /// The first of `values` (in the order of `parameters`) out of range, then the joint
    /// check.
    pub fn problem(&self, values: &[f64]) -> Option<ParameterProblem> {
        self.parameters
            .iter()
            .zip(values)
            .find_map(|(p, &v)| p.problem(v))
            .or_else(|| self.joint_check.and_then(|check| check(values)))
    }
}

/// Every law, in [`FrictionLawKind::ALL`]'s order.
pub fn laws() -> impl Iterator<Item = &'static LawDescription> {
    FrictionLawKind::ALL.iter().map(|kind| kind.entry())
}

/// Every law parameter, law by law in [`laws`]' order.
pub fn parameters() -> impl Iterator<Item = &'static LawParameter> {
    laws().flat_map(|law| law.parameters.iter())
}

/// The parameter named `name` (dotted, `friction.` optional).
pub fn parameter(name: &str) -> Option<&'static LawParameter> {
    let dotted = if name.starts_with("friction.") {
        name.to_owned()
    } else {
        format!("friction.{name}")
    };
    parameters().find(|p| p.name == dotted)
}

/// The values of every law's parameters: the scene file's `[friction.<section>]`
/// tables, each key absent from the file at its default.
///
/// Serialised as one map per law (`lugre = { bristle_stiffness = 1e7, ... }`), a choice
/// by its word; read from the same, refusing any key no law has.
#[derive(Clone, Debug, PartialEq)]
pub struct LawTables {
    /// Per law with parameters, in [`laws`]' order: its values in the order of its
    /// parameters.
    tables: Vec<(FrictionLawKind, Vec<f64>)>,
}

impl Default for LawTables {
    fn default() -> Self {
        Self {
            tables: laws()
                .filter(|law| !law.parameters.is_empty())
                .map(|law| (law.kind, law.defaults()))
                .collect(),
        }
    }
}

impl LawTables {
    /// The values of `kind`'s parameters, in order (empty for a law without any).
    pub fn values(&self, kind: FrictionLawKind) -> &[f64] {
        self.tables
            .iter()
            .find(|(k, _)| *k == kind)
            .map_or(&[], |(_, values)| values.as_slice())
    }

    fn position(&self, parameter: &LawParameter) -> Option<(usize, usize)> {
        self.tables.iter().enumerate().find_map(|(t, (kind, _))| {
            kind.entry()
                .parameters
                .iter()
                .position(|p| p.name == parameter.name)
                .map(|k| (t, k))
        })
    }

    /// The value of `parameter` (NaN for a parameter of no registered law).
    pub fn get(&self, parameter: &LawParameter) -> f64 {
        self.position(parameter)
            .map_or(f64::NAN, |(t, k)| self.tables[t].1[k])
    }

    /// Writes `value` into `parameter`, unchecked (the scene's check, or the FMU's at
    /// initialisation, refuses it if out of range).
    pub fn set(&mut self, parameter: &LawParameter, value: f64) {
        if let Some((t, k)) = self.position(parameter) {
            self.tables[t].1[k] = value;
        }
    }

    /// The first parameter out of range of the law `kind`.
    pub fn problem_of(&self, kind: FrictionLawKind) -> Option<ParameterProblem> {
        let law = kind.entry();
        if law.parameters.is_empty() {
            return None;
        }
        law.problem(self.values(kind))
    }

    /// The first parameter out of range of any law.
    pub fn problem(&self) -> Option<ParameterProblem> {
        self.tables
            .iter()
            .find_map(|(kind, _)| self.problem_of(*kind))
    }
}

/// A parameter's value as the scene file writes it: a number, or a choice's word.
fn serialise_value<S: SerializeMap>(
    map: &mut S,
    parameter: &LawParameter,
    value: f64,
) -> Result<(), S::Error> {
    match parameter.kind {
        ParameterKind::Choice(choice) => match choice.item(value as i32) {
            Ok(word) => map.serialize_entry(parameter.key(), word),
            Err(_) => map.serialize_entry(parameter.key(), &value),
        },
        ParameterKind::Real { .. } => map.serialize_entry(parameter.key(), &value),
    }
}

/// One law's table, serialised.
struct Table<'a>(FrictionLawKind, &'a [f64]);

impl Serialize for Table<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let parameters = self.0.entry().parameters;
        let mut map = serializer.serialize_map(Some(parameters.len()))?;
        for (parameter, &value) in parameters.iter().zip(self.1) {
            serialise_value(&mut map, parameter, value)?;
        }
        map.end()
    }
}

impl Serialize for LawTables {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.tables.len()))?;
        for (kind, values) in &self.tables {
            let section = kind.entry().section().unwrap_or_default();
            map.serialize_entry(section, &Table(*kind, values))?;
        }
        map.end()
    }
}

/// A number (integer or float) or a word: what a table's entry may hold.
#[derive(Deserialize)]
#[serde(untagged)]
enum Entry {
    Number(f64),
    Word(String),
}

/// One law's table read into `values` (which hold the defaults).
struct TableSeed<'a> {
    kind: FrictionLawKind,
    values: &'a mut Vec<f64>,
}

impl<'de> de::DeserializeSeed<'de> for TableSeed<'_> {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<(), D::Error> {
        deserializer.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for TableSeed<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "the table of friction law {}", self.kind.name())
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let parameters = self.kind.entry().parameters;
        while let Some(key) = map.next_key::<String>()? {
            let Some(k) = parameters.iter().position(|p| p.key() == key) else {
                let keys: Vec<&str> = parameters.iter().map(|p| p.key()).collect();
                return Err(de::Error::custom(format!(
                    "unknown field `{key}` in friction.{}, expected one of {}",
                    self.kind.entry().section().unwrap_or_default(),
                    quoted(&keys)
                )));
            };
            let parameter = &parameters[k];
            self.values[k] = match (map.next_value::<Entry>()?, parameter.kind) {
                (Entry::Number(v), ParameterKind::Real { .. }) => v,
                (Entry::Word(word), ParameterKind::Choice(choice)) => choice
                    .items()
                    .find(|(_, w, _)| *w == word)
                    .map(|(code, _, _)| f64::from(code))
                    .ok_or_else(|| {
                        let words: Vec<&str> = choice.items().map(|(_, w, _)| w).collect();
                        de::Error::custom(format!(
                            "unknown variant `{word}`, expected one of {}",
                            quoted(&words)
                        ))
                    })?,
                (Entry::Number(v), ParameterKind::Choice(_)) => {
                    return Err(de::Error::invalid_type(de::Unexpected::Float(v), &"a word"))
                }
                (Entry::Word(word), ParameterKind::Real { .. }) => {
                    return Err(de::Error::invalid_type(
                        de::Unexpected::Str(&word),
                        &"a number",
                    ))
                }
            };
        }
        Ok(())
    }
}

/// `a`, `b`, `c`: serde's way of listing the words it expected.
fn quoted(words: &[&str]) -> String {
    let quoted: Vec<String> = words.iter().map(|w| format!("`{w}`")).collect();
    quoted.join(", ")
}

impl<'de> Deserialize<'de> for LawTables {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct TablesVisitor;
        impl<'de> Visitor<'de> for TablesVisitor {
            type Value = LawTables;

            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("the friction laws' tables")
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<LawTables, A::Error> {
                let mut tables = LawTables::default();
                while let Some(section) = map.next_key::<String>()? {
                    let Some(t) = tables
                        .tables
                        .iter()
                        .position(|(kind, _)| kind.entry().section() == Some(&section))
                    else {
                        let sections: Vec<&str> =
                            laws().filter_map(LawDescription::section).collect();
                        return Err(de::Error::custom(format!(
                            "unknown field `{section}` in friction: neither a key of the section nor a law's table ({})",
                            quoted(&sections)
                        )));
                    };
                    let (kind, values) = &mut tables.tables[t];
                    map.next_value_seed(TableSeed {
                        kind: *kind,
                        values,
                    })?;
                }
                Ok(tables)
            }
        }
        deserializer.deserialize_map(TablesVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parameter_has_its_own_name_and_value_reference_and_a_default_in_range() {
        let all: Vec<&LawParameter> = parameters().collect();
        for (i, p) in all.iter().enumerate() {
            assert!(
                p.problem(p.default).is_none(),
                "{}: {:?}",
                p.name,
                p.problem(p.default)
            );
            for q in &all[i + 1..] {
                assert_ne!(p.name, q.name);
                assert_ne!(
                    p.value_reference, q.value_reference,
                    "{} {}",
                    p.name, q.name
                );
            }
        }
        for law in laws() {
            assert_eq!(law.kind.entry().kind, law.kind);
            assert!(law.problem(&law.defaults()).is_none());
            for p in law.parameters {
                assert_eq!(
                    p.name,
                    format!("friction.{}.{}", law.section().unwrap(), p.key())
                );
            }
        }
    }

    #[test]
    fn assignments_name_a_parameter_and_parse_its_value() {
        let (p, v) = parse_assignment("lugre.bristle_damping=500").unwrap();
        assert_eq!((p.name, v), ("friction.lugre.bristle_damping", 500.0));
        let (p, v) = parse_assignment("friction.rate_and_state.state_evolution=slip").unwrap();
        assert_eq!((p.key(), v), ("state_evolution", 2.0));
        let no_name = parse_assignment("lugre.stiffness=1").unwrap_err();
        assert!(no_name.contains("lugre.bristle_stiffness"), "{no_name}");
        assert!(parse_assignment("lugre.bristle_damping").is_err());
        let word = parse_assignment("rate_and_state.state_evolution=ageing").unwrap_err();
        assert!(word.contains("aging, slip"), "{word}");
        assert!(parse_assignment("lugre.bristle_damping=soft").is_err());
    }

    #[test]
    fn neural_friction_codes_are_distinct_and_start_at_one() {
        let mut codes: Vec<i32> = laws().filter_map(|l| l.neural_friction_code).collect();
        codes.sort_unstable();
        assert_eq!(codes, (1..=codes.len() as i32).collect::<Vec<_>>());
    }

    #[test]
    fn tables_read_back_what_they_write_and_refuse_unknown_keys() {
        let mut tables = LawTables::default();
        let first = parameters().next().unwrap();
        tables.set(first, 3.5);
        let json = serde_json::to_string(&tables).unwrap();
        let back: LawTables = serde_json::from_str(&json).unwrap();
        assert_eq!(back, tables);
        assert_eq!(back.get(first), 3.5);
        let section = first.name.split('.').nth(1).unwrap();
        let unknown = format!("{{\"{section}\": {{\"no_such_key\": 1.0}}}}");
        let error = serde_json::from_str::<LawTables>(&unknown).unwrap_err();
        assert!(error.to_string().contains("no_such_key"), "{error}");
        assert!(serde_json::from_str::<LawTables>("{\"no_such_law\": {}}").is_err());
        assert_eq!(
            serde_json::from_str::<LawTables>("{}").unwrap(),
            LawTables::default()
        );
    }
}
