//! The input Jacobian of a kinetic friction law: the force F and its velocity slope
//! S = dF/dv at one point, with their first derivatives with respect to every input.
//! Co-simulation masters and training tools that wrap a friction FMU (FMIFlux) ask for
//! these instead of finite differences; S is itself a derivative, so its gradient holds
//! the law's second derivatives d2F/dv dx_k.
//!
//! The neural network's Jacobian is in `neural::jacobian`; the exponential law's closed
//! form beside the law (`friction::exponential`).
//!
//! # Conventions at the kinks
//! Both laws are F = sign(v) g(|v|, ...), with a jump at v = 0. The derivatives there are
//! those of the branch v > 0 (the one-sided limits, as `FrictionLaw::sliding_force_and_slope`
//! gives the slope): dF/dv = g'(0+) and dS/dv = g''(0+), while the derivatives with respect
//! to the other inputs are 0, since F(0, ...) = 0 for every value of them.

/// A law's force and slope at one point, and their gradients over the law's inputs (in the
/// law's input order: for the exponential law (v, F_n), for a network its features).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LawJacobian {
    /// F (N).
    pub force: f64,
    /// S = dF/dv (N s/m), the slope the law reports (0 where v is clamped).
    pub slope: f64,
    /// dF/dx_k, one per input (N per unit of input k).
    pub force_gradient: Vec<f64>,
    /// dS/dx_k = d2F/dv dx_k, one per input.
    pub slope_gradient: Vec<f64>,
}

/// d|v|/dv with the branch v > 0 at v = 0 (see the module notes).
pub fn magnitude_slope(sliding_velocity: f64) -> f64 {
    if sliding_velocity < 0.0 {
        -1.0
    } else {
        1.0
    }
}
