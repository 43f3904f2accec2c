//! The study's friction-law axis (issue 24): which law a run of the grid uses.
//!
//! A law is a scene friction law ([`FrictionLawKind`]) other than `external`, whose force
//! comes from an FMU's inputs and which no stand-alone run has. The neural law may name
//! its weights file, so that the learned law with memory (a weights file of format
//! `stickslip-state-friction`, e.g. weights/rate-and-state-learned.json) can stand on the
//! axis beside the plain network: written `neural:PATH` (`neural` alone is the shipped
//! plain network). The other laws take their coefficients from the scene
//! (`friction.lugre`, `friction.rate_and_state`, mu_s, mu_k, alpha).

use crate::choice::Choice;
use crate::friction::FrictionLawKind;
use crate::scene::Scene;
use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// One point of the law axis: a law kind and, for `neural` only, its weights file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Law {
    kind: FrictionLawKind,
    weights: Option<String>,
}

/// Why a law cannot be on the axis.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LawError {
    #[error(
        "friction law '{0}': {reason}",
        reason = "its force comes from StickSlipBeam.fmu's inputs, which a study run does not have"
    )]
    External(&'static str),
    #[error(
        "friction law '{law}:{weights}': only the neural law takes a weights file (neural:PATH)"
    )]
    WeightsOfAnalyticalLaw { law: &'static str, weights: String },
    #[error("'{0}': expected one of {names}, or neural:PATH (a weights file)", names = law_names())]
    Unknown(String),
    #[error("'neural:': the weights file is missing after the colon")]
    EmptyWeights,
}

fn law_names() -> String {
    FrictionLawKind::ALL
        .iter()
        .filter(|k| **k != FrictionLawKind::External)
        .map(|k| k.name())
        .collect::<Vec<_>>()
        .join(", ")
}

impl Law {
    /// `kind` with `weights` (neural only); `external` refused.
    pub fn new(kind: FrictionLawKind, weights: Option<String>) -> Result<Self, LawError> {
        if kind == FrictionLawKind::External {
            return Err(LawError::External(kind.name()));
        }
        match weights {
            Some(w) if kind != FrictionLawKind::Neural => Err(LawError::WeightsOfAnalyticalLaw {
                law: kind.name(),
                weights: w,
            }),
            Some(w) if w.is_empty() => Err(LawError::EmptyWeights),
            weights => Ok(Self { kind, weights }),
        }
    }

    /// The scene's own law (the axis of a study without `laws`); `external` refused.
    pub fn of_scene(scene: &Scene) -> Result<Self, LawError> {
        let weights = (scene.friction.law == FrictionLawKind::Neural)
            .then(|| scene.friction.weights.clone())
            .flatten();
        Self::new(scene.friction.law, weights)
    }

    pub fn kind(&self) -> FrictionLawKind {
        self.kind
    }

    pub fn weights(&self) -> Option<&str> {
        self.weights.as_deref()
    }

    /// `scene` with this law; every other field kept (the laws' coefficients too, which
    /// are the scene's for every law of the axis). The neural law without a weights file
    /// is the shipped network, whatever file the scene names.
    pub fn apply(&self, scene: &Scene) -> Scene {
        let mut scene = scene.clone();
        scene.friction.law = self.kind;
        if self.kind == FrictionLawKind::Neural {
            scene.friction.weights = self.weights.clone();
        }
        scene
    }

    /// A name for file names (`front-<slug>.json`): the kind, and for a weights file its
    /// stem (`neural-rate-and-state-learned`).
    pub fn slug(&self) -> String {
        match &self.weights {
            None => self.kind.name().into(),
            Some(path) => {
                let stem = Path::new(path)
                    .file_stem()
                    .map_or_else(|| path.clone(), |s| s.to_string_lossy().into_owned());
                let stem: String = stem
                    .chars()
                    .map(|c| {
                        if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                            c
                        } else {
                            '-'
                        }
                    })
                    .collect();
                format!("{}-{stem}", self.kind.name())
            }
        }
    }
}

/// `kind` or `neural:PATH`, as `--laws` and study.csv's `law` column write it.
impl fmt::Display for Law {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.weights {
            None => f.write_str(self.kind.name()),
            Some(path) => write!(f, "{}:{path}", self.kind.name()),
        }
    }
}

impl FromStr for Law {
    type Err = LawError;

    fn from_str(text: &str) -> Result<Self, LawError> {
        let (name, weights) = match text.split_once(':') {
            Some((name, weights)) => (name.trim(), Some(weights.trim().to_string())),
            None => (text.trim(), None),
        };
        let kind =
            FrictionLawKind::from_name(name).ok_or_else(|| LawError::Unknown(text.into()))?;
        Self::new(kind, weights)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn external_and_a_weights_file_on_an_analytical_law_are_refused_with_the_reason() {
        let external = "external".parse::<Law>().unwrap_err();
        assert!(external.to_string().contains("inputs"), "{external}");
        assert!(matches!(
            "lugre:w.json".parse::<Law>(),
            Err(LawError::WeightsOfAnalyticalLaw { .. })
        ));
        assert_eq!("neural:".parse::<Law>(), Err(LawError::EmptyWeights));
        let unknown = "dahl".parse::<Law>().unwrap_err().to_string();
        assert!(
            unknown.contains("rate-and-state") && !unknown.contains("external"),
            "{unknown}"
        );
    }

    #[test]
    fn a_law_reads_back_from_its_own_spelling_and_names_its_file() {
        for text in [
            "exponential",
            "lugre",
            "rate-and-state",
            "neural",
            "neural:weights/rate-and-state-learned.json",
        ] {
            let law: Law = text.parse().unwrap();
            assert_eq!(law.to_string(), text);
            assert_eq!(law.to_string().parse::<Law>().unwrap(), law);
        }
        let learned: Law = "neural:weights/rate-and-state-learned.json"
            .parse()
            .unwrap();
        assert_eq!(learned.slug(), "neural-rate-and-state-learned");
        assert_eq!(learned.kind(), FrictionLawKind::Neural);
        let scene = learned.apply(&Scene::default());
        assert_eq!(scene.friction.weights.as_deref(), learned.weights());
        // The shipped network replaces a scene's own weights file.
        let mut neural_scene = Scene::default();
        neural_scene.friction.weights = Some("other.json".into());
        let shipped: Law = "neural".parse().unwrap();
        assert_eq!(shipped.apply(&neural_scene).friction.weights, None);
    }
}
