//! The fixed-point iteration of earlier versions, kept as the reference solver and as
//! the answer where the slip equation has no solution.

use super::argument::SlipArgument;
use super::kinetic::CountedLaw;
use super::limits::{SLIP_ITERATIONS, SLIP_TOLERANCE};

/// The fixed-point iteration F <- F_law(x(F)) from `start` (N), stopped when an update
/// is below the slip tolerance or after [`SLIP_ITERATIONS`] passes: the slip solve of
/// earlier versions, bit for bit ([`SlipSolver::FixedPoint`](super::SlipSolver::FixedPoint)).
///
/// Where the equation has no solution (zero in the law's jump) the iteration settles on
/// a cycle between the two sides and runs all its passes. The map is deterministic, so
/// once an iterate repeats one p passes before, the sequence repeats with period p and
/// its last value is known; none of the passes in that cycle converged, so none of the
/// repeats would have either. The shortcut gives the number the full run gives.
pub(super) fn fixed_point(
    argument: &SlipArgument,
    start: f64,
    kinetic: &mut CountedLaw<'_, '_>,
) -> (f64, bool) {
    // Iterate F_i sits at history[i % CYCLE]; cycles of up to CYCLE - 1 passes are seen.
    const CYCLE: usize = 9;
    let mut history = [f64::NAN; CYCLE];
    history[0] = start;
    let mut force = start;
    for pass in 0..SLIP_ITERATIONS {
        let next = kinetic.force(argument.at(force).x);
        if (next - force).abs() <= SLIP_TOLERANCE * (1.0 + next.abs()) {
            return (next, true);
        }
        // next is F_m; F_m = F_{m-p} makes F_N = F_{m-p+((N-m) mod p)}, N the passes.
        let m = pass + 1;
        for period in 2..CYCLE.min(m + 1) {
            if next == history[(m - period) % CYCLE] {
                let rest = (SLIP_ITERATIONS - m) % period;
                return (history[(m - period + rest) % CYCLE], false);
            }
        }
        history[m % CYCLE] = next;
        force = next;
    }
    (force, false)
}
