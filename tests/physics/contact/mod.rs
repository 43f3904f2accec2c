//! The tip contact (`stickslip::contact`) through its public API: Leine's switch and the
//! impulse clamp as rules, `Contact::resolve` on trial steps with round numbers under
//! both schemes (`switch`), the slip force it takes (`slip`), and the safeguarded Newton
//! solve against the fixed-point reference over many slip steps (`sweep`).

mod slip;
mod sweep;
mod switch;

use stickslip::contact::{Contact, ContactState, Previous};
use stickslip::friction::coulomb::CoulombLaw;
use stickslip::integrator::{Coefficients, TrialStep};
use stickslip::scene::{CheckedScene, HoldingForce, Scheme};

// Trial steps with round numbers near the paper's 1-DOF scale: the tip responds to F
// by du/dF = 1e-9 m/N and dv/dF = 2e-5 m/(s N), dt = 1e-4 s (Moreau-Jean:
// du/dF = dt theta dv/dF with theta = 1/2).
pub const TRIAL: TrialStep = TrialStep {
    dt: 1e-4,
    start_tip_displacement: 7e-3,
    start_tip_velocity: 0.02,
    // u_n + v_b dt - 1e-9 m: the stick reaction is 1 N.
    free_tip_displacement: 7.002e-3 - 1e-9,
    free_tip_velocity: 0.03,
    displacement_per_force: 1e-9,
    velocity_per_force: 2e-5,
};
pub const MJ_TRIAL: TrialStep = TrialStep {
    dt: 1e-4,
    start_tip_displacement: 7e-3,
    start_tip_velocity: 0.02,
    free_tip_displacement: 7.002e-3,
    // v_b + 2e-5 m/s: the stick reaction is -1 N.
    free_tip_velocity: 0.02 + 2e-5,
    displacement_per_force: 1e-9,
    velocity_per_force: 2e-5,
};
pub const BELT: f64 = 0.02;
pub const LIMIT: f64 = 50.0;

pub fn contact(scheme: Scheme, holding: HoldingForce) -> Contact {
    let mut scene = CheckedScene::paper().into_scene();
    scene.integrator.scheme = scheme;
    scene.contact.holding_force = holding;
    let scene = scene.check().unwrap();
    Contact::new(&scene, Coefficients::from_scene(&scene))
}

pub fn coulomb() -> CoulombLaw {
    CoulombLaw {
        kinetic_coefficient: 0.2,
    }
}

pub fn previous(state: ContactState, relative_velocity: f64, force: f64) -> Previous {
    Previous {
        state,
        relative_velocity,
        force,
    }
}

/// alpha_f of the paper scene's generalised-alpha scheme.
pub fn alpha_f() -> f64 {
    match Coefficients::from_scene(&CheckedScene::paper()) {
        Coefficients::GeneralizedAlpha { alpha_f, .. } => alpha_f,
        Coefficients::MoreauJean { .. } => unreachable!(),
    }
}

/// TRIAL with the tip 1e-4 m/s ahead of the belt before the force: v_rel(F) =
/// -1e-4 - 2e-5 F, so the slip force sits where a steep law is steep.
pub const NEAR_ZERO: TrialStep = TrialStep {
    free_tip_velocity: 0.02 + 1e-4,
    ..TRIAL
};
/// Below TRIAL's 1 N stick reaction: re-stick is inadmissible, the step slips
/// however slow.
pub const LOW_LIMIT: f64 = 0.5;

/// The law's argument at t_{n+1-alpha_f} after `trial` with tip force `force`.
pub fn level(trial: &TrialStep, previous_relative_velocity: f64, force: f64) -> f64 {
    let alpha_f = alpha_f();
    let v_rel = BELT - (trial.free_tip_velocity + force * trial.velocity_per_force);
    (1.0 - alpha_f) * v_rel + alpha_f * previous_relative_velocity
}
