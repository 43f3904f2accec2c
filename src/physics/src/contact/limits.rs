//! The limits of every slip solver: the most law evaluations and the convergence
//! tolerance.

/// Most law evaluations of one slip solve: Newton needs 1 to 3 and the fixed-point
/// reference 6 to 15 where it converges; a guard, not a tuning knob.
pub const SLIP_ITERATIONS: usize = 50;

/// Convergence of the slip force: the last correction |dF| <= SLIP_TOLERANCE (1 + |F|)
/// (N). For Newton the correction estimates the error of the iterate it starts from, and
/// the iterate it gives is closer still (quadratic convergence).
pub const SLIP_TOLERANCE: f64 = 1e-12;
