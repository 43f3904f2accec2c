//! The slip force where the slip equation has no solution: zero inside the law's jump
//! at v = 0 (see the module notes of `contact`).
//!
//! A law sign(v) g(|v|) jumps at v = 0 by 2 g(0) (2 mu_s F_n = 100 N for the paper's
//! exponential law). Within one step the law's argument x(F) crosses 0 at the reversal
//! force F_j, so r(F) = F - F_law(x(F)) jumps up by 2 g(0) there (x falls as F rises:
//! the force drags the tip towards the belt), from F_j - g(0) to F_j + g(0). When
//! |F_j| < g(0), r(F_j-) < 0 < r(F_j+) and no F solves F = F_law(x(F)): with the force
//! of one side the step ends on the other. This is the tip reaching the belt's speed
//! within the step with less than g(0) needed to keep it there: the
//! set-valued law (Filippov's convention) has its solution there, F = F_j, x = 0, and
//! F_j lies inside the jump, [-g(0), g(0)]. The step then ends with
//! v_rel,n+1 = -alpha_f / (1 - alpha_f) v_rel,n (x = 0 at t_{n+1-alpha_f}): v_rel has
//! changed sign, and the switch re-sticks where stick is admissible.
//!
//! Either side's force instead (the fixed-point iteration's cycle ends on one of them,
//! which one by the parity of its passes, as the slip solve of earlier versions took
//! it) puts the full -mu_s F_n on the tip for a step when the tip only touched the
//! belt's speed: issue 37 counted 58 such samples over 3 s at beam fidelity and the
//! paper's step, where the converged run has none (docs/decisions.md).

use super::argument::SlipArgument;
use super::kinetic::CountedLaw;

/// F_j (N) if zero lies inside the law's jump at the reversal force F_j, i.e.
/// r(F_j-) < 0 < r(F_j+) (two law evaluations); None if the slip equation does not
/// cross the jump (or the direction of sliding does not depend on F).
pub(super) fn inside_jump(argument: &SlipArgument, law: &mut CountedLaw<'_, '_>) -> Option<f64> {
    let reversal = argument.reversal()?;
    let residual = |law: &mut CountedLaw<'_, '_>, above: bool| {
        let point = argument.beside_reversal(reversal, above);
        point.force - law.force(point.x)
    };
    let (below, above) = (residual(law, false), residual(law, true));
    (below < 0.0 && 0.0 < above).then_some(reversal)
}
