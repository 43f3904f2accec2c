//! The fixed-point iteration of earlier versions, kept as the reference solver.

use super::argument::SlipArgument;
use super::jump::inside_jump;
use super::kinetic::CountedLaw;
use super::limits::{SLIP_ITERATIONS, SLIP_TOLERANCE};

/// The fixed-point iteration F <- F_law(x(F)) from `start` (N), stopped when an update
/// is below the slip tolerance or after [`SLIP_ITERATIONS`] passes: the slip solve of
/// earlier versions ([`SlipSolver::FixedPoint`](super::SlipSolver::FixedPoint)), bit for
/// bit where it converges.
///
/// Where the equation has no solution (zero in the law's jump) the iteration settles on
/// a cycle between the two sides. The map is deterministic, so once an iterate repeats
/// one p passes before, the sequence repeats with period p and none of its passes
/// would converge: the cycle is detected rather than run to [`SLIP_ITERATIONS`]
/// passes. An iteration that did not converge takes the reversal force F_j where zero
/// lies in the jump (as the Newton solve does, [`super::jump`]); elsewhere (a law
/// steeper than the tip's response, |F_law' x'| > 1) its last iterate, as the full run
/// of passes gives it.
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
                return unconverged(argument, history[(m - period + rest) % CYCLE], kinetic);
            }
        }
        history[m % CYCLE] = next;
        force = next;
    }
    unconverged(argument, force, kinetic)
}

/// The answer of an iteration that stopped at `last` (N) without converging.
fn unconverged(
    argument: &SlipArgument,
    last: f64,
    kinetic: &mut CountedLaw<'_, '_>,
) -> (f64, bool) {
    (inside_jump(argument, kinetic).unwrap_or(last), false)
}
