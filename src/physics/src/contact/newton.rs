//! The safeguarded Newton solve of the slip force (see the module notes of `contact`).

use super::argument::{Point, SlipArgument};
use super::kinetic::CountedLaw;
use super::limits::{SLIP_ITERATIONS, SLIP_TOLERANCE};

/// One evaluation of r(F) = F - F_law(x(F)): the residual (N), its slope r' (1) and the
/// Newton iterate F - r / r' (N).
struct Residual {
    force: f64,
    direction: f64,
    law: f64,
    value: f64,
    slope: f64,
}

impl Residual {
    fn new(point: Point, law: &mut CountedLaw<'_, '_>) -> Self {
        let (law, law_slope) = law.force_and_slope(point.x);
        Self {
            force: point.force,
            direction: point.direction,
            law,
            value: point.force - law,
            slope: 1.0 - law_slope * point.slope,
        }
    }

    fn newton(&self) -> f64 {
        self.force - self.value / self.slope
    }
}

/// Safeguarded Newton on r(F) = F - F_law(x(F)) from `start` (N); see the module notes.
/// Returns the force (N) and whether it solves the equation.
///
/// r increases with F where the problem is well posed, so each evaluation narrows the
/// bracket (below, above) of the root: r(below) < 0 < r(above). A Newton iterate outside
/// it, or from a non-positive slope, is replaced by bisection (or, while one end is still
/// open, by the fixed-point step). The first iterate that would change the direction of
/// sliding, where the law jumps, is replaced by a look at both sides of the reversal
/// force F_j: r(F_j-) <= r(F_j+), so the root lies below (r(F_j-) > 0), above
/// (r(F_j+) < 0) or in the jump, where the equation has no solution and F_j itself is
/// the answer (see [`super::jump`]).
///
/// Converged when the Newton correction is below [`SLIP_TOLERANCE`] (or the law's
/// resolution, if coarser: [`FrictionLaw::resolution`](crate::friction::FrictionLaw::resolution)), or when two
/// successive Newton corrections shrink by q < 1/2 and the bound on the error of a
/// sequence converging at rate q, q / (1 - q) |correction|, is below it: Newton
/// converges faster than that bound assumes, and the test saves the evaluation that
/// would only confirm convergence.
pub(super) fn newton(
    argument: &SlipArgument,
    start: f64,
    law: &mut CountedLaw<'_, '_>,
) -> (f64, bool) {
    let reversal = argument.reversal();
    let mut reversal_seen = false;
    let (mut below, mut above) = (f64::NEG_INFINITY, f64::INFINITY);
    let resolution = law.kinetic.resolution();
    let mut current = Residual::new(argument.at(start), law);
    // The Newton correction that led to `current`, if a Newton step did.
    let mut last_correction: Option<f64> = None;
    for _ in 1..SLIP_ITERATIONS {
        if !current.law.is_finite() {
            // The simulation reports the non-finite force.
            return (current.law, false);
        }
        if current.value == 0.0 {
            return (current.force, true);
        }
        if current.value < 0.0 {
            below = below.max(current.force);
        } else {
            above = above.min(current.force);
        }
        let newton = current.newton();
        let newton_valid = current.slope > 0.0 && newton.is_finite();
        if newton_valid {
            let correction = (newton - current.force).abs();
            let tolerance = (SLIP_TOLERANCE * (1.0 + newton.abs())).max(resolution);
            let rate = last_correction.map_or(1.0, |last| correction / last);
            if correction <= tolerance
                || (rate < 0.5 && rate / (1.0 - rate) * correction <= tolerance)
            {
                return (newton, true);
            }
        }
        let next = if newton_valid && below < newton && newton < above {
            newton
        } else if below.is_finite() && above.is_finite() {
            0.5 * (below + above)
        } else {
            current.law
        };
        last_correction = (next == newton).then(|| (newton - current.force).abs());
        let next = argument.at(next);
        current = match reversal {
            Some(reversal)
                if !reversal_seen
                    && (current.direction == 0.0 || next.direction != current.direction) =>
            {
                reversal_seen = true;
                last_correction = None;
                // Look first on the side of the current iterate (below if it has none).
                let first_above = current.direction == argument.direction_above();
                let first = Residual::new(argument.beside_reversal(reversal, first_above), law);
                if first.value == 0.0 {
                    return (reversal, true);
                }
                if (first.value < 0.0) == first_above {
                    // r(F_j+) < 0 or r(F_j-) > 0: the root lies on this side.
                    if first_above {
                        below = reversal;
                    } else {
                        above = reversal;
                    }
                    first
                } else {
                    let second =
                        Residual::new(argument.beside_reversal(reversal, !first_above), law);
                    if second.value == 0.0 {
                        return (reversal, true);
                    }
                    if (second.value < 0.0) == first_above || !second.law.is_finite() {
                        // r(F_j-) < 0 < r(F_j+): zero lies in the jump, no solution
                        // of the single-valued equation; the set-valued law's is F_j.
                        return (reversal, false);
                    }
                    if first_above {
                        above = reversal;
                    } else {
                        below = reversal;
                    }
                    second
                }
            }
            // (A one-sided evaluation at the jump is the next iterate like any other:
            // its Newton step lies on its side, inside the bracket that now ends there.)
            _ => Residual::new(next, law),
        };
    }
    (current.force, false)
}
