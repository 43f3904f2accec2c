//! The safeguarded Newton solve of the slip force (see the module notes of `contact`).

use std::ops::ControlFlow;

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
    let mut bracket = RootBracket {
        below: f64::NEG_INFINITY,
        above: f64::INFINITY,
    };
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
        bracket.narrow(&current);
        let newton = current.newton();
        let newton_valid = current.slope > 0.0 && newton.is_finite();
        if newton_valid && converged(&current, newton, last_correction, resolution) {
            return (newton, true);
        }
        let next = bracket.next(newton, newton_valid, &current);
        last_correction = (next == newton).then(|| (newton - current.force).abs());
        let next = argument.at(next);
        current = match reversal {
            Some(reversal)
                if !reversal_seen
                    && (current.direction == 0.0 || next.direction != current.direction) =>
            {
                reversal_seen = true;
                last_correction = None;
                match across_reversal(argument, reversal, &current, &mut bracket, law) {
                    ControlFlow::Continue(beside) => beside,
                    ControlFlow::Break(answer) => return answer,
                }
            }
            // (A one-sided evaluation at the jump is the next iterate like any other:
            // its Newton step lies on its side, inside the bracket that now ends there.)
            _ => Residual::new(next, law),
        };
    }
    (current.force, false)
}

/// The bracket (below, above) of the root (N): r(below) < 0 < r(above).
struct RootBracket {
    below: f64,
    above: f64,
}

impl RootBracket {
    /// Moves the end on the residual's side to its force.
    fn narrow(&mut self, r: &Residual) {
        if r.value < 0.0 {
            self.below = self.below.max(r.force);
        } else {
            self.above = self.above.min(r.force);
        }
    }

    /// The next iterate (N): the Newton iterate if valid and inside the bracket, else
    /// bisection, else (an end still open) the fixed-point step F_law.
    fn next(&self, newton: f64, newton_valid: bool, current: &Residual) -> f64 {
        if newton_valid && self.below < newton && newton < self.above {
            newton
        } else if self.below.is_finite() && self.above.is_finite() {
            0.5 * (self.below + self.above)
        } else {
            current.law
        }
    }

    /// Closes the bracket at the reversal force F_j (N), the root lying above it
    /// (`root_above`) or below.
    fn close_at(&mut self, reversal: f64, root_above: bool) {
        if root_above {
            self.below = reversal;
        } else {
            self.above = reversal;
        }
    }
}

/// The convergence test of [`newton`] for the Newton iterate `newton` (N) from
/// `current`: the correction below the tolerance, or shrinking at a rate q < 1/2 with
/// the error bound q / (1 - q) |correction| below it.
fn converged(
    current: &Residual,
    newton: f64,
    last_correction: Option<f64>,
    resolution: f64,
) -> bool {
    let correction = (newton - current.force).abs();
    let tolerance = (SLIP_TOLERANCE * (1.0 + newton.abs())).max(resolution);
    let rate = last_correction.map_or(1.0, |last| correction / last);
    correction <= tolerance || (rate < 0.5 && rate / (1.0 - rate) * correction <= tolerance)
}

/// The first iterate that would change the direction of sliding: looks at the sides of
/// the reversal force F_j (N), first the current iterate's (below if it has none).
/// Continues from the side that holds the root, with the bracket closed at F_j, or
/// breaks with the answer: F_j where r is 0 beside it or where the root lies in the
/// jump (no solution of the single-valued equation; the set-valued law's is F_j).
fn across_reversal(
    argument: &SlipArgument,
    reversal: f64,
    current: &Residual,
    bracket: &mut RootBracket,
    law: &mut CountedLaw<'_, '_>,
) -> ControlFlow<(f64, bool), Residual> {
    let first_above = current.direction == argument.direction_above();
    let first = Residual::new(argument.beside_reversal(reversal, first_above), law);
    if first.value == 0.0 {
        return ControlFlow::Break((reversal, true));
    }
    if (first.value < 0.0) == first_above {
        // r(F_j+) < 0 or r(F_j-) > 0: the root lies on this side.
        bracket.close_at(reversal, first_above);
        return ControlFlow::Continue(first);
    }
    let second = Residual::new(argument.beside_reversal(reversal, !first_above), law);
    if second.value == 0.0 {
        return ControlFlow::Break((reversal, true));
    }
    if (second.value < 0.0) == first_above || !second.law.is_finite() {
        // r(F_j-) < 0 < r(F_j+): zero lies in the jump, no solution
        // of the single-valued equation; the set-valued law's is F_j.
        return ControlFlow::Break((reversal, false));
    }
    bracket.close_at(reversal, !first_above);
    ControlFlow::Continue(second)
}
