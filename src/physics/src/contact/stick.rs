//! The stick reaction: the tip force that keeps the tip with the belt, and the holding
//! force F_hold the switch compares with mu_s F_n.

use crate::integrator::TrialStep;
use crate::scene::HoldingForce;

/// The stick reaction of a step: the force that keeps the tip with the belt (N) and the
/// tip displacement at t_{n+1} under it (m).
pub(super) struct StickReaction {
    pub(super) force: f64,
    pub(super) tip_displacement: f64,
}

impl StickReaction {
    /// Generalised-alpha's stick, at displacement level: u_tip,n+1 = u_tip,n + v_b dt
    /// (the paper's Eq. 4), at belt speed `belt_speed` (m/s).
    pub(super) fn displacement_level(trial: &TrialStep, belt_speed: f64) -> Self {
        let target = trial.start_tip_displacement + belt_speed * trial.dt;
        Self {
            force: (target - trial.free_tip_displacement) / trial.displacement_per_force,
            tip_displacement: target,
        }
    }

    /// Moreau-Jean's stick, at velocity level: v_tip,n+1 = v_b (m/s); the displacement
    /// follows through u_{n+1} = u_n + h v_{n+theta}.
    pub(super) fn velocity_level(trial: &TrialStep, belt_speed: f64) -> Self {
        let force = (belt_speed - trial.free_tip_velocity) / trial.velocity_per_force;
        Self {
            force,
            tip_displacement: trial.free_tip_displacement + force * trial.displacement_per_force,
        }
    }
}

/// How the holding force F_hold is taken, as the scene's `holding_force` asks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Holding {
    pub(super) kind: HoldingForce,
    /// 3 EI / L^3 (N/m), for `HoldingForce::EulerBernoulli`.
    pub(super) euler_bernoulli_stiffness: f64,
}

impl Holding {
    /// F_hold (N) of a stick reaction.
    pub(super) fn force(&self, stick: &StickReaction) -> f64 {
        match self.kind {
            HoldingForce::Reaction => stick.force,
            // The paper's rule, P = E h^3 delta / (4 L^3) = 3 EI delta / L^3 for b = 1.
            HoldingForce::EulerBernoulli => self.euler_bernoulli_stiffness * stick.tip_displacement,
        }
    }
}
