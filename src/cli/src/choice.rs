//! Command-line values of the scene's choices, read off the physics crate's
//! [`Choice`] enums: the words, their order and their help lines are not retyped here.
//!
//! A command may add older words as aliases (`--friction analytical` is the scene's
//! `exponential`), shown in the value's help line, and may refuse a value it cannot
//! honour (`--friction external`), with the reason as the error message.

use clap::builder::{PossibleValue, TypedValueParser};
use clap::error::ErrorKind;
use std::ffi::OsStr;
use stickslip::choice::Choice;

/// A clap value parser that accepts the words of `T` and the aliases given, with each
/// value's description as its help line.
pub fn parser<T: Choice>() -> ChoiceParser<T> {
    ChoiceParser {
        aliases: Vec::new(),
        refused: Vec::new(),
    }
}

/// The value parser built by [`parser`].
#[derive(Clone, Debug)]
pub struct ChoiceParser<T: Choice> {
    /// (alias, the value it stands for).
    aliases: Vec<(&'static str, T)>,
    /// (value, why this command cannot honour it).
    refused: Vec<(T, &'static str)>,
}

impl<T: Choice> ChoiceParser<T> {
    /// Also accepts `word` for `value` (a name scripts already use).
    pub fn alias(mut self, word: &'static str, value: T) -> Self {
        self.aliases.push((word, value));
        self
    }

    /// Refuses `value` with `reason`; it is left out of the listed values.
    pub fn refuse(mut self, value: T, reason: &'static str) -> Self {
        self.refused.push((value, reason));
        self
    }

    fn is_refused(&self, value: T) -> Option<&'static str> {
        self.refused
            .iter()
            .find(|(v, _)| *v == value)
            .map(|(_, reason)| *reason)
    }

    /// The values this parser accepts, each with its aliases, in [`Choice::ALL`] order.
    pub fn accepted(&self) -> Vec<(T, Vec<&'static str>)> {
        T::ALL
            .iter()
            .filter(|c| self.is_refused(**c).is_none())
            .map(|&c| {
                let aliases = self
                    .aliases
                    .iter()
                    .filter(|(_, v)| *v == c)
                    .map(|(word, _)| *word)
                    .collect();
                (c, aliases)
            })
            .collect()
    }

    /// The value of a command-line word, or why it is not accepted.
    pub fn value(&self, word: &str) -> Result<T, ChoiceValueError> {
        let value = T::from_name(word).or_else(|| {
            self.aliases
                .iter()
                .find(|(alias, _)| *alias == word)
                .map(|(_, v)| *v)
        });
        match value {
            Some(value) => match self.is_refused(value) {
                Some(reason) => Err(ChoiceValueError::Refused {
                    word: word.to_string(),
                    reason,
                }),
                None => Ok(value),
            },
            None => Err(ChoiceValueError::Unknown {
                word: word.to_string(),
                type_name: T::TYPE_NAME,
                accepted: self
                    .accepted()
                    .into_iter()
                    .flat_map(|(c, aliases)| std::iter::once(c.name()).chain(aliases))
                    .collect(),
            }),
        }
    }
}

/// Why a command-line word is not taken as a value of a choice (the message follows
/// "invalid value for --option: ").
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ChoiceValueError {
    /// A value of the choice that this command cannot honour, and why.
    #[error("{word}: {reason}")]
    Refused { word: String, reason: &'static str },
    /// Neither a word of the choice nor an alias; `accepted` lists the words that are,
    /// in [`Choice::ALL`] order, each followed by its aliases.
    #[error("{word} is not a {type_name} value; possible values: {}", .accepted.join(", "))]
    Unknown {
        word: String,
        type_name: &'static str,
        accepted: Vec<&'static str>,
    },
}

impl<T: Choice> TypedValueParser for ChoiceParser<T> {
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<T, clap::Error> {
        let word = value.to_string_lossy();
        self.value(&word).map_err(|error| {
            let option = arg.map_or_else(|| "the value".to_string(), |a| a.to_string());
            clap::Error::raw(
                ErrorKind::InvalidValue,
                format!("invalid value for {option}: {error}\n"),
            )
            .with_cmd(cmd)
        })
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(self.accepted().into_iter().map(|(c, aliases)| {
            let help = if aliases.is_empty() {
                c.description().to_string()
            } else {
                format!("{} (also: {})", c.description(), aliases.join(", "))
            };
            PossibleValue::new(c.name()).aliases(aliases).help(help)
        })))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_args::{friction_parser, SceneArgs};
    use clap::Parser;
    use stickslip::friction::FrictionLawKind;
    use stickslip::scene::{FidelityLevel, Scheme};

    /// (word, help line) of every listed value.
    fn listed<P: TypedValueParser>(parser: &P) -> Vec<(String, String)> {
        parser
            .possible_values()
            .unwrap()
            .map(|v| {
                let help = v.get_help().map(|h| h.to_string()).unwrap_or_default();
                (v.get_name().to_string(), help)
            })
            .collect()
    }

    fn words_and_descriptions<T: Choice>() -> Vec<(String, String)> {
        T::ALL
            .iter()
            .map(|c| (c.name().to_string(), c.description().to_string()))
            .collect()
    }

    #[test]
    fn the_values_are_the_scene_words_with_their_descriptions() {
        assert_eq!(
            listed(&parser::<FidelityLevel>()),
            words_and_descriptions::<FidelityLevel>()
        );
        assert_eq!(
            listed(&parser::<Scheme>()),
            words_and_descriptions::<Scheme>()
        );
        for c in FidelityLevel::ALL {
            assert_eq!(parser::<FidelityLevel>().value(c.name()), Ok(*c));
        }
    }

    #[test]
    fn friction_takes_the_scene_laws_and_analytical_but_not_external() {
        let parser = friction_parser();
        let words: Vec<String> = listed(&parser).into_iter().map(|(w, _)| w).collect();
        let laws: Vec<&str> = FrictionLawKind::ALL
            .iter()
            .filter(|l| **l != FrictionLawKind::External)
            .map(|l| l.name())
            .collect();
        assert_eq!(words, laws);
        assert!(listed(&parser)[0].1.contains("also: analytical"));
        assert_eq!(parser.value("analytical"), Ok(FrictionLawKind::Exponential));
        assert_eq!(
            parser.value("exponential"),
            Ok(FrictionLawKind::Exponential)
        );
        let refused = parser.value("external").unwrap_err();
        assert!(
            matches!(&refused, ChoiceValueError::Refused { word, .. } if word == "external"),
            "{refused:?}"
        );
        assert!(refused.to_string().contains("StickSlipBeam"), "{refused}");
        let unknown = parser.value("Coulomb").unwrap_err();
        // The accepted words: the laws a stand-alone run has, with `analytical` after
        // `exponential`.
        let mut accepted = laws.clone();
        accepted.insert(1, "analytical");
        assert_eq!(
            unknown,
            ChoiceValueError::Unknown {
                word: "Coulomb".into(),
                type_name: FrictionLawKind::TYPE_NAME,
                accepted: accepted.clone(),
            }
        );
        assert_eq!(
            unknown.to_string(),
            format!(
                "Coulomb is not a {} value; possible values: {}",
                FrictionLawKind::TYPE_NAME,
                accepted.join(", ")
            )
        );
        assert!(unknown
            .to_string()
            .contains("exponential, analytical, coulomb, neural, lugre, rate-and-state"));
    }

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        scene: SceneArgs,
    }

    /// The words scripts use parse through clap into the scene's values.
    #[test]
    fn the_command_line_contract_parses() {
        let args = Cli::try_parse_from([
            "stickslip",
            "--fidelity",
            "plane-stress",
            "--friction",
            "analytical",
            "--integrator",
            "moreau-jean",
        ])
        .unwrap()
        .scene;
        assert_eq!(args.fidelity, Some(FidelityLevel::PlaneStress));
        assert_eq!(args.friction, Some(FrictionLawKind::Exponential));
        assert_eq!(args.integrator, Some(Scheme::MoreauJean));
        let auto = Cli::try_parse_from(["stickslip", "--fidelity", "auto"]).unwrap();
        assert_eq!(auto.scene.fidelity, Some(FidelityLevel::Auto));
        let error = Cli::try_parse_from(["stickslip", "--friction", "external"])
            .err()
            .unwrap()
            .to_string();
        assert!(
            error.contains("--friction") && error.contains("StickSlipBeam"),
            "{error}"
        );
        assert!(Cli::try_parse_from(["stickslip", "--integrator", "euler"]).is_err());
    }
}
