//! The shipped front and the partners along it.

use super::{
    AutoError, CHAIN_COST_RATIO, CHEAP_RUN_SECONDS, PARTNER_ACCURACY_RATIO, SAFETY_FACTOR,
    SAFETY_FACTOR_WITH_STATE,
};
use crate::friction::rate_and_state::{RateStateParameters, StateEvolution};
use crate::friction::FrictionLawKind;
use crate::law_source::LawSource;
use crate::scene::Scene;
use crate::study::FrontPoint;

/// A front `stickslip study` measured on the paper scene and shipped in data/: which
/// law family it was measured with. Each law is compared with its own reference (40
/// modes of the 0.005 m mesh; 1e-5 s for the memoryless laws, 2.5e-6 s for the laws with
/// state, whose reference at 1e-5 s is itself 0.3-0.7 um RMS off: speed-accuracy.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShippedFront {
    /// The memoryless laws (exponential, Coulomb, the plain network, ...):
    /// data/pareto_front.json, measured with the exponential law.
    Memoryless,
    /// LuGre: data/pareto_front-lugre.json.
    LuGre,
    /// Rate-and-state with the aging law: data/pareto_front-rate-and-state.json.
    RateAndState,
    /// Rate-and-state with the slip law: data/pareto_front-rate-and-state-slip.json. Its
    /// own front, not the aging law's: over the 251 configurations both ran, the slip
    /// law's RMS error was 0.14 to 2.4 times the aging law's (median 0.72), which moves
    /// the partners (speed-accuracy.md).
    RateAndStateSlip,
    /// The learned law with memory (`friction.law = neural` with a
    /// `stickslip-state-friction` weights file): data/pareto_front-learned-memory.json,
    /// measured with weights/rate-and-state-learned.json.
    LearnedMemory,
}

impl ShippedFront {
    /// The front for `law`, the law of `scene` resolved (the rate-and-state evolution
    /// law is the scene's).
    pub fn of(scene: &Scene, law: &LawSource) -> Self {
        match law {
            LawSource::LearnedState(_) => ShippedFront::LearnedMemory,
            LawSource::Analytical { kind, .. } => match kind {
                FrictionLawKind::Lugre => ShippedFront::LuGre,
                FrictionLawKind::RateAndState => {
                    match RateStateParameters::of(&scene.friction.laws).state_evolution {
                        StateEvolution::Aging => ShippedFront::RateAndState,
                        StateEvolution::Slip => ShippedFront::RateAndStateSlip,
                    }
                }
                _ => ShippedFront::Memoryless,
            },
            LawSource::Network(_) | LawSource::External { .. } => ShippedFront::Memoryless,
        }
    }

    /// Whether the front is a law with state's.
    pub fn has_state(self) -> bool {
        self != ShippedFront::Memoryless
    }

    /// The chain's safety factor for this front's laws: [`SAFETY_FACTOR`] for the
    /// memoryless laws, [`SAFETY_FACTOR_WITH_STATE`], measured on their verification
    /// scenes, for the others.
    pub fn safety_factor(self) -> f64 {
        if self.has_state() {
            SAFETY_FACTOR_WITH_STATE
        } else {
            SAFETY_FACTOR
        }
    }

    /// Its file, for messages.
    pub fn file(self) -> &'static str {
        match self {
            ShippedFront::Memoryless => "data/pareto_front.json",
            ShippedFront::LuGre => "data/pareto_front-lugre.json",
            ShippedFront::RateAndState => "data/pareto_front-rate-and-state.json",
            ShippedFront::RateAndStateSlip => "data/pareto_front-rate-and-state-slip.json",
            ShippedFront::LearnedMemory => "data/pareto_front-learned-memory.json",
        }
    }

    fn json(self) -> &'static str {
        match self {
            ShippedFront::Memoryless => super::PAPER_FRONT_JSON,
            ShippedFront::LuGre => include_str!("../../../../data/pareto_front-lugre.json"),
            ShippedFront::RateAndState => {
                include_str!("../../../../data/pareto_front-rate-and-state.json")
            }
            ShippedFront::RateAndStateSlip => {
                include_str!("../../../../data/pareto_front-rate-and-state-slip.json")
            }
            ShippedFront::LearnedMemory => {
                include_str!("../../../../data/pareto_front-learned-memory.json")
            }
        }
    }

    /// The front, cheapest first, checked ([`check_front`]).
    pub fn front(self) -> Result<Vec<FrontPoint>, AutoError> {
        let front: Vec<FrontPoint> =
            serde_json::from_str(self.json()).map_err(|source| AutoError::FrontJson {
                file: self.file(),
                source,
            })?;
        check_front(&front)?;
        Ok(front)
    }
}

/// The memoryless laws' paper-scene front, cheapest first.
pub fn paper_front() -> Result<Vec<FrontPoint>, AutoError> {
    ShippedFront::Memoryless.front()
}

/// The shipped front `auto` walks for `law`, the law of `scene` resolved
/// ([`ShippedFront::of`]).
pub fn front_for(scene: &Scene, law: &LawSource) -> Result<Vec<FrontPoint>, AutoError> {
    ShippedFront::of(scene, law).front()
}

/// A usable front: at least two points, cost rising and error falling along it.
pub fn check_front(front: &[FrontPoint]) -> Result<(), AutoError> {
    if front.len() < 2 {
        return Err(AutoError::FrontTooShort);
    }
    for pair in front.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if !(a.seconds <= b.seconds && a.rms_error > b.rms_error) {
            return Err(AutoError::FrontUnordered {
                first: *a,
                second: *b,
            });
        }
    }
    Ok(())
}

/// The front as `scene` takes it: its mode counts as the scene's spectrum asks for them
/// (`crate::transfer::front_for_scene`), and only the points whose configuration the
/// scene's own rules admit. The paper authors' contact options (a free first slip step,
/// the lagged slip force, damping only in slip) belong to generalised-alpha's switch, so
/// a scene with them has no Moreau-Jean point; such a point would fail its calibration
/// run. Refused with the scene's reason when no point is left.
pub fn for_scene(scene: &Scene, front: &[FrontPoint]) -> Result<Vec<FrontPoint>, AutoError> {
    let mut refusal = None;
    let admitted: Vec<FrontPoint> = crate::transfer::front_for_scene(scene, front)
        .into_iter()
        .filter(|point| match point.configuration.apply(scene).check() {
            Ok(_) => true,
            Err(reason) => {
                refusal.get_or_insert(reason);
                false
            }
        })
        .collect();
    match refusal {
        Some(reason) if admitted.is_empty() => Err(AutoError::Scene(reason)),
        _ => Ok(admitted),
    }
}

/// The comparison partner of front point `k`, if it has one.
pub fn partner(front: &[FrontPoint], k: usize) -> Option<usize> {
    if k + 1 >= front.len() {
        return None;
    }
    let target = front[k].rms_error / PARTNER_ACCURACY_RATIO;
    Some(
        (k + 1..front.len())
            .find(|&j| front[j].rms_error <= target)
            .unwrap_or(front.len() - 1),
    )
}

/// The model-refinement partner of front point `k`: the first later plane-stress point
/// (the full mesh or a modal basis of it, [`crate::study::Resolution::is_continuum`]) at least [`PARTNER_ACCURACY_RATIO`] times more accurate on the paper scene.
pub fn refinement(front: &[FrontPoint], k: usize) -> Option<usize> {
    let target = front[k].rms_error / PARTNER_ACCURACY_RATIO;
    (k + 1..front.len())
        .find(|&j| front[j].configuration.resolution.is_continuum() && front[j].rms_error <= target)
}

/// Whether the chain may run front point `next`: cheap in itself, or at most
/// [`CHAIN_COST_RATIO`] times the first partner's paper-scene cost.
pub(super) fn affordable(front: &[FrontPoint], next: usize, first_partner: usize) -> bool {
    front[next].seconds <= CHEAP_RUN_SECONDS
        || front[next].seconds <= CHAIN_COST_RATIO * front[first_partner].seconds
}
