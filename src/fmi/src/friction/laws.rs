//! The laws NeuralFriction evaluates on their own: the one list of laws
//! (`stickslip::friction::FrictionLawKind`) restricted to those that give a force from
//! the inputs alone (no coulomb, no external), in NeuralFriction's own order. Its
//! parameter `law` (FMI enumeration type `FrictionLaw`) numbers them in this order,
//! which saved states and SSP files hold: neural = 1, exponential = 2, lugre = 3,
//! rate-and-state = 4.

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

impl Choice for NeuralFrictionLaw {
    const TYPE_NAME: &'static str = "FrictionLaw";
    const TYPE_DESCRIPTION: &'static str = "Which law gives the friction force";
    const ALL: &'static [Self] = &[
        Self::NEURAL,
        Self::EXPONENTIAL,
        Self::LUGRE,
        Self::RATE_AND_STATE,
    ];

    fn name(self) -> &'static str {
        self.0.name()
    }

    /// NeuralFriction's own words for each law: its parameters are named apart from the
    /// scene's (`weights`, not `friction.weights`), and the texts are part of its model
    /// description, whose hash is the GUID that every saved FMU state carries and is
    /// checked against: other words would refuse the states saved so far.
    fn description(self) -> &'static str {
        match self.0 {
            FrictionLawKind::Neural => "the network in weights",
            FrictionLawKind::Exponential => self.0.description(),
            FrictionLawKind::Lugre => {
                "LuGre bristle law, g(v) the exponential law (Canudas de Wit et al. 1995)"
            }
            FrictionLawKind::RateAndState => "regularised Dieterich-Ruina rate-and-state law",
            // Not in `ALL`: never a value of this type.
            FrictionLawKind::Coulomb | FrictionLawKind::External => self.0.description(),
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
        assert_eq!(
            codes,
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
        assert_eq!(
            refused.to_string(),
            "unknown variant `coulomb`, expected one of `neural`, `exponential`, `lugre`, `rate-and-state`"
        );
    }
}
