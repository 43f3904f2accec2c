//! The laws NeuralFriction evaluates on their own: the one list of laws
//! (`stickslip::friction::FrictionLawKind`) restricted to those the registry gives a
//! NeuralFriction code (`LawDescription::neural_friction_code`), in code order. Its
//! parameter `law` (FMI type `FrictionLaw`) numbers them so, which saved states and SSP
//! files hold: neural = 1, exponential = 2, lugre = 3, rate-and-state = 4.

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::sync::LazyLock;
use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;

/// One of the laws NeuralFriction evaluates: a [`FrictionLawKind`] from
/// [`NeuralFrictionLaw::ALL`], with its words and descriptions, numbered in that list's
/// order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NeuralFrictionLaw(FrictionLawKind);

impl NeuralFrictionLaw {
    /// The trained network (or the learned law with state, told by its file).
    pub const NEURAL: Self = Self(FrictionLawKind::Neural);
    /// The paper's exponential law, to compare the network with.
    pub const EXPONENTIAL: Self = Self(FrictionLawKind::Exponential);
    /// LuGre, g(v) the exponential law.
    pub const LUGRE: Self = Self(FrictionLawKind::Lugre);
    /// Rate-and-state.
    pub const RATE_AND_STATE: Self = Self(FrictionLawKind::RateAndState);

    /// The law in the one list of laws.
    pub fn kind(self) -> FrictionLawKind {
        self.0
    }

    /// `kind` as one of NeuralFriction's laws, if it is one.
    pub fn of(kind: FrictionLawKind) -> Option<Self> {
        Self::ALL.iter().copied().find(|law| law.0 == kind)
    }
}

/// How many laws NeuralFriction evaluates: those the registry gives a NeuralFriction
/// code (`LawDescription::neural_friction_code`).
const COUNT: usize = {
    let mut count = 0;
    let mut k = 0;
    while k < FrictionLawKind::ALL.len() {
        if FrictionLawKind::ALL[k]
            .entry()
            .neural_friction_code
            .is_some()
        {
            count += 1;
        }
        k += 1;
    }
    count
};

/// NeuralFriction's laws, each at its code's place (codes 1 to [`COUNT`], checked
/// distinct by the registry's tests).
const LIST: [NeuralFrictionLaw; COUNT] = {
    let mut list = [NeuralFrictionLaw::NEURAL; COUNT];
    let mut k = 0;
    while k < FrictionLawKind::ALL.len() {
        let kind = FrictionLawKind::ALL[k];
        if let Some(code) = kind.entry().neural_friction_code {
            list[(code - 1) as usize] = NeuralFrictionLaw(kind);
        }
        k += 1;
    }
    list
};

impl Choice for NeuralFrictionLaw {
    const TYPE_NAME: &'static str = "FrictionLaw";
    const TYPE_DESCRIPTION: &'static str = "Which law gives the friction force";
    const ALL: &'static [Self] = &LIST;

    fn name(self) -> &'static str {
        self.0.name()
    }

    /// The law's own description, but for the network, whose weights parameter
    /// NeuralFriction names `weights` (the scene file `friction.weights`).
    fn description(self) -> &'static str {
        match self.0 {
            FrictionLawKind::Neural => "the network in weights",
            kind => kind.description(),
        }
    }
}

/// The words of [`NeuralFrictionLaw::ALL`], for serde's message on an unknown one.
static NAMES: LazyLock<Vec<&'static str>> =
    LazyLock::new(|| NeuralFrictionLaw::ALL.iter().map(|l| l.name()).collect());

/// Saved states hold the law's word ("neural", "lugre", ...).
impl Serialize for NeuralFrictionLaw {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

/// The word of one of [`NeuralFrictionLaw::ALL`]; any other refused as serde refuses
/// an unknown variant (the words listed).
impl<'de> Deserialize<'de> for NeuralFrictionLaw {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let word = String::deserialize(deserializer)?;
        Self::from_name(&word)
            .ok_or_else(|| serde::de::Error::unknown_variant(&word, NAMES.as_slice()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The codes saved states and SSP files hold, and the words, are those of the
    /// enumeration NeuralFriction always had; a law it does not evaluate is none of
    /// them, and its word is refused as an unknown one.
    #[test]
    fn codes_words_and_refusals() {
        let codes: Vec<(i32, &str)> = NeuralFrictionLaw::ALL
            .iter()
            .map(|l| (l.code(), l.name()))
            .collect();
        // The published codes; laws added later append.
        assert_eq!(
            codes[..4],
            [
                (1, "neural"),
                (2, "exponential"),
                (3, "lugre"),
                (4, "rate-and-state")
            ]
        );
        assert_eq!(NeuralFrictionLaw::of(FrictionLawKind::Coulomb), None);
        assert_eq!(
            NeuralFrictionLaw::of(FrictionLawKind::Lugre),
            Some(NeuralFrictionLaw::LUGRE)
        );
        let saved = serde_json::to_string(&NeuralFrictionLaw::RATE_AND_STATE).unwrap();
        assert_eq!(saved, "\"rate-and-state\"");
        let read: NeuralFrictionLaw = serde_json::from_str(&saved).unwrap();
        assert_eq!(read, NeuralFrictionLaw::RATE_AND_STATE);
        let refused = serde_json::from_str::<NeuralFrictionLaw>("\"coulomb\"").unwrap_err();
        let words: Vec<String> = codes.iter().map(|(_, w)| format!("`{w}`")).collect();
        assert_eq!(
            refused.to_string(),
            format!(
                "unknown variant `coulomb`, expected one of {}",
                words.join(", ")
            )
        );
    }
}
