//! Where a run's friction law comes from: [`LawSource`], the one place that turns a
//! scene's `friction` settings (or a network an FMU has already loaded) into the
//! `Box<dyn FrictionLaw>` a [`crate::simulation::Simulator`] takes.
//!
//! Everything that runs the beam takes a source: `run::run_scene`, `auto`, the study,
//! the command line and the StickSlipBeam FMU. The NeuralFriction FMU does not: it runs
//! no simulation, but evaluates the exponential law or the network directly at its
//! inputs, extra features (which `FrictionLaw`, a law of v and F_n, has no room for) and
//! the force's slope included.

use crate::choice::Choice;
use crate::friction::learned_state::{LearnedStateFriction, LearnedStateLaw};
use crate::friction::registry::{LawBuild, LawPrototype};
use crate::friction::FrictionLawKind;
use crate::friction::{exponential::ExponentialLaw, FrictionLaw};
use crate::neural::inference::Inference;
use crate::neural::table::TableLaw;
use crate::neural::{NeuralError, NeuralLaw, SceneLawError};
use crate::scene::{CheckedScene, Friction};
use std::hash::{Hash, Hasher};
use std::path::Path;
use std::sync::Arc;

pub mod learned_state;

/// The friction law a run uses, resolved once and then asked for a fresh law per
/// simulation ([`LawSource::law`]).
///
/// Why resolved once: a scene is run many times from one source (the `auto` fidelity's
/// calibration runs, the study's grid, an FMU rebuilt at every reset), and reading and
/// checking a weights file is the costly, fallible part; so the file is read when the
/// source is made ([`LawSource::resolve`]) and never again for the runs that follow.
///
/// Why shared: the network is held as an `Arc<NeuralLaw>`, so that the source is cheap
/// to clone and to hand on (an FMU hands its already-loaded network to `auto`, which
/// passes it to every calibration run); each [`LawSource::law`] clones the network into
/// a law of its own, because a law keeps scratch buffers (`&mut self`). The same weights
/// therefore give the same numbers in every run, bit for bit.
///
/// A new law built from its parameters is no new variant: its registry entry
/// (`friction::registry`) makes it an [`LawSource::Analytical`]; every caller goes
/// through [`LawSource::law`], so none of them changes.
#[derive(Clone, Debug)]
pub enum LawSource {
    /// A law built from the coefficients and its table (exponential, Coulomb, LuGre,
    /// rate-and-state, ...), at its initial state.
    Analytical {
        kind: FrictionLawKind,
        prototype: Arc<dyn LawPrototype>,
    },
    /// A trained network, evaluated as `friction.inference` asks.
    Network(NetworkSource),
    /// `friction.law = external`: the force comes from the StickSlipBeam FMU's inputs.
    /// The simulator still holds a law, the exponential law of the scene's coefficients
    /// (`stand_in`), which the FMU's calibration runs also use; a stand-alone run refuses
    /// this source (`run::RunError::External`).
    External { stand_in: ExponentialLaw },
    /// The learned law with state (`friction::learned_state`): `friction.law = neural` with a
    /// weights file of format `stickslip-state-friction`.
    LearnedState(Arc<LearnedStateLaw>),
}

/// A loaded network with what its law needs besides: the evaluation, the normal force
/// (N) a table is built at, and where the network came from (for messages).
#[derive(Clone, Debug)]
pub struct NetworkSource {
    network: Arc<NeuralLaw>,
    inference: Inference,
    normal_force: f64,
    origin: NetworkOrigin,
    /// The network's identity for caches, computed once when the source is made (the
    /// weights serialise to about 650 kB of JSON, too much to hash at every lookup);
    /// `None` when the model does not serialise, which is then never cached.
    identity: Option<u64>,
}

impl NetworkSource {
    fn new(
        network: Arc<NeuralLaw>,
        inference: Inference,
        normal_force: f64,
        origin: NetworkOrigin,
    ) -> Self {
        let identity = network_identity(&network);
        NetworkSource {
            network,
            inference,
            normal_force,
            origin,
            identity,
        }
    }

    /// The loaded network.
    pub fn network(&self) -> &Arc<NeuralLaw> {
        &self.network
    }

    pub fn inference(&self) -> Inference {
        self.inference
    }
}

/// What makes two networks compute the same forces: the model (weights, scaling,
/// features, ranges) and the values given to its fixed features. Not its file name: two
/// files may hold one network, one name two networks.
fn network_identity(network: &NeuralLaw) -> Option<u64> {
    let model = serde_json::to_string(network.model()).ok()?;
    let fixed: Vec<Option<u64>> = network
        .fixed_features()
        .iter()
        .map(|value| value.map(f64::to_bits))
        .collect();
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    (model, fixed).hash(&mut hasher);
    Some(hasher.finish())
}

/// Where a network was read from: its messages name it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NetworkOrigin {
    /// A weights file, as `friction.weights` (or an FMU's weights parameter) names it.
    Weights(String),
    /// The shipped plain-variant network (the paper's model).
    Shipped,
}

impl NetworkOrigin {
    fn error(&self, source: NeuralError) -> SceneLawError {
        match self {
            NetworkOrigin::Weights(path) => SceneLawError::weights(path, source),
            NetworkOrigin::Shipped => SceneLawError::Shipped(source),
        }
    }
}

impl LawSource {
    /// The law `friction` names, with `network` asked for the network of the neural law
    /// (and only for it): every other law is made from the coefficients
    /// ([`LawSource::analytical`]).
    pub fn with_network<E>(
        friction: &Friction,
        normal_force: f64,
        network: impl FnOnce() -> Result<(Arc<NeuralLaw>, NetworkOrigin), E>,
    ) -> Result<Self, E> {
        if let Some(source) = Self::analytical(friction) {
            return Ok(source);
        }
        let (network, origin) = network()?;
        Ok(LawSource::Network(NetworkSource::new(
            network,
            friction.inference,
            normal_force,
            origin,
        )))
    }

    /// The one place where a friction section becomes a law made from its coefficients
    /// and parameters: every law but the neural one (`None`), whose network the caller
    /// loads. `friction` must have passed `Friction::check` (a scene's check, or
    /// NeuralFriction's at initialisation), which checks every parameter read here.
    pub fn analytical(friction: &Friction) -> Option<Self> {
        let law = friction.law.entry();
        match law.build {
            LawBuild::Analytical(build) => Some(LawSource::Analytical {
                kind: law.kind,
                prototype: build(&friction.coefficients(), friction.laws.values(law.kind)),
            }),
            LawBuild::External => Some(LawSource::External {
                stand_in: friction.exponential_law(),
            }),
            LawBuild::Network => None,
        }
    }

    /// The law a checked scene asks for. The neural law reads its weights file
    /// (`friction.weights`) here, once, or takes the shipped plain network when none is
    /// given.
    pub fn resolve(scene: &CheckedScene) -> Result<Self, SceneLawError> {
        if let Some(law) = learned_state::scene_state_law(scene)? {
            return Ok(LawSource::LearnedState(law));
        }
        Self::with_network(&scene.friction, scene.loading.normal_force, || {
            let (read, origin) = match &scene.friction.weights {
                Some(path) => (
                    NeuralLaw::from_file(Path::new(path)),
                    NetworkOrigin::Weights(path.clone()),
                ),
                None => (NeuralLaw::paper_default(), NetworkOrigin::Shipped),
            };
            match read {
                Ok(network) => Ok((Arc::new(network), origin)),
                Err(source) => Err(origin.error(source)),
            }
        })
    }

    /// `network` (already loaded) as the beam's law, evaluated as `inference` asks.
    pub fn network(
        network: Arc<NeuralLaw>,
        origin: NetworkOrigin,
        inference: Inference,
        normal_force: f64,
    ) -> Self {
        LawSource::Network(NetworkSource::new(network, inference, normal_force, origin))
    }

    /// This source evaluated as `inference` asks (a configuration of the study may
    /// change it); the network stays shared. Analytical laws have no inference.
    pub fn with_inference(&self, inference: Inference) -> Self {
        let mut source = self.clone();
        if let LawSource::Network(network) = &mut source {
            network.inference = inference;
        }
        source
    }

    /// The law a run without the FMU's inputs uses: the external law's stand-in, every
    /// other law itself.
    pub fn stand_alone(&self) -> Self {
        match self {
            LawSource::External { stand_in } => LawSource::Analytical {
                kind: FrictionLawKind::Exponential,
                prototype: Arc::new(stand_in.clone()),
            },
            other => other.clone(),
        }
    }

    /// Whether this is `friction.law = external`.
    pub fn is_external(&self) -> bool {
        matches!(self, LawSource::External { .. })
    }

    /// A fresh law for one simulation. Refused with the reason if the network cannot
    /// serve the beam (features) or its inference (the table's inputs).
    pub fn law(&self) -> Result<Box<dyn FrictionLaw>, SceneLawError> {
        match self {
            LawSource::Analytical { prototype, .. } => Ok(prototype.fresh()),
            LawSource::External { stand_in } => Ok(Box::new(stand_in.clone())),
            LawSource::LearnedState(law) => Ok(Box::new(LearnedStateFriction::new(law.clone()))),
            LawSource::Network(n) => network_law((*n.network).clone(), n.inference, n.normal_force)
                .map_err(|source| n.origin.error(source)),
        }
    }

    /// A fingerprint of the law for caches keyed by what a run computes (`auto`): equal
    /// for the same law and the same network (its model and fixed feature values),
    /// whoever loaded it. The coefficients and the inference are the scene's, so a cache
    /// must key the scene with it, the scene this source was made from. `None` for a
    /// network whose model does not serialise: such a law is not cached.
    pub fn fingerprint(&self) -> Option<String> {
        match self {
            LawSource::Network(n) => n.identity.map(|id| format!("network {id:016x}")),
            LawSource::Analytical { kind, .. } => Some(kind.name().into()),
            LawSource::External { .. } => Some("external".into()),
            LawSource::LearnedState(law) => learned_state::fingerprint(law),
        }
    }
}

/// `law` as the beam's friction law, evaluated as `friction.inference` asks: speed for
/// accuracy, each option's largest error measured when it is built.
///
/// - `exact`: the network in f64, as trained (`NeuralLaw`).
/// - `f32`: the same network in single precision ([`NeuralLaw::in_f32`]): half the
///   bytes of weights to stream and twice the values per vector register. Its largest
///   deviation from the exact network is measured at build over the training range.
/// - `table`: the network tabulated at initialisation over its training range
///   (`neural::table::LawTable`) at `normal_force` (N), the force the beam will press
///   with: piecewise cubic in the sliding velocity, linear in the normal force, refined
///   until its error is below `neural::table::TABLE_TOLERANCE`, the largest error
///   verified at build on points between the nodes. It supports networks whose inputs
///   are the sliding velocity and the normal force (or the velocity alone) and refuses
///   others.
///
/// The slip solve uses the law's slope either way: the f32 network differentiates in
/// f32, the table its own interpolant (so Newton sees a consistent law). Refused with
/// the reason if the model cannot serve the beam, or the table cannot cover its inputs.
fn network_law(
    law: NeuralLaw,
    inference: Inference,
    normal_force: f64,
) -> Result<Box<dyn FrictionLaw>, NeuralError> {
    use crate::choice::Choice;
    match inference {
        Inference::Exact => law.into_friction_law(),
        Inference::F32 => law.in_f32().into_friction_law(),
        Inference::Table => {
            if let Some(reason) = TableLaw::refusal(&law) {
                return Err(NeuralError::Inference {
                    inference: Inference::Table.name(),
                    reason,
                });
            }
            if let Some(problem) = law.beam_problem() {
                return Err(NeuralError::NotAFrictionLaw(problem));
            }
            Ok(Box::new(TableLaw::build(law, normal_force)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn neural_scene() -> CheckedScene {
        let mut scene = Scene::default();
        scene.friction.law = FrictionLawKind::Neural;
        scene.check().unwrap()
    }

    /// Every law of one source is the same law (the same numbers, bit for bit), and the
    /// source's clones share its network rather than copy it.
    #[test]
    fn one_source_gives_the_same_law_every_time_and_shares_its_network() {
        let source = LawSource::resolve(&neural_scene()).unwrap();
        let (mut a, mut b) = (source.law().unwrap(), source.law().unwrap());
        for v in [-0.3, -1e-3, 0.0, 2e-4, 0.05, 1.0] {
            let (fa, sa) = a.sliding_force_and_slope(v, 100.0);
            let (fb, sb) = b.sliding_force_and_slope(v, 100.0);
            assert_eq!((fa.to_bits(), sa.to_bits()), (fb.to_bits(), sb.to_bits()));
        }
        let (LawSource::Network(n), LawSource::Network(m)) =
            (&source, &source.with_inference(Inference::F32))
        else {
            panic!("the neural scene's source is a network");
        };
        assert!(Arc::ptr_eq(&n.network, &m.network));
        assert_eq!(m.inference, Inference::F32);
    }

    /// `auto` keys its cache by the fingerprint: the same network read twice is one
    /// entry, another network another, an analytical law names itself.
    #[test]
    fn the_fingerprint_tells_networks_apart_whoever_loaded_them() {
        let scene = neural_scene();
        let read = |law: NeuralLaw| {
            LawSource::network(
                Arc::new(law),
                NetworkOrigin::Shipped,
                Inference::Exact,
                100.0,
            )
        };
        let plain = LawSource::resolve(&scene).unwrap().fingerprint();
        assert!(plain.is_some());
        assert_eq!(
            plain,
            read(NeuralLaw::paper_default().unwrap()).fingerprint()
        );
        assert_ne!(
            plain,
            read(NeuralLaw::paper_signed().unwrap()).fingerprint()
        );
        let exponential = LawSource::resolve(&Scene::default().check().unwrap()).unwrap();
        assert_eq!(exponential.fingerprint().as_deref(), Some("exponential"));
    }
}
