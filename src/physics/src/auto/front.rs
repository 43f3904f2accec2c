//! The shipped front and the partners along it.

use super::{
    AutoError, CHAIN_COST_RATIO, CHEAP_RUN_SECONDS, PAPER_FRONT_JSON, PARTNER_ACCURACY_RATIO,
};
use crate::scene::Scene;
use crate::study::FrontPoint;

/// The paper-scene front, cheapest first.
pub fn paper_front() -> Result<Vec<FrontPoint>, AutoError> {
    let front: Vec<FrontPoint> =
        serde_json::from_str(PAPER_FRONT_JSON).map_err(AutoError::FrontJson)?;
    check_front(&front)?;
    Ok(front)
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
