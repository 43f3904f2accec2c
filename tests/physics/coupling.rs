//! A coupled friction model's signed law, handed to the simulation as its tangent
//! (`ExternalKinetic::Signed`: value, slope and the velocity they hold at), against the
//! same law embedded in the simulation.
//!
//! For a linear law F(v) = b v the tangent at any velocity v_k is the law itself,
//! F(v_k) + b (v - v_k) = b v. Holding it over a communication step then loses
//! nothing: the coupled run must be the embedded run, at any communication step and
//! whichever velocity the model was evaluated at (the current one, as Gauss-Seidel
//! hands it over, or the one a step before, as Jacobi does). Only the slip solves
//! differ: Newton's method on the tangent against the embedded fixed-point iteration,
//! both converged to 1e-12 of the force.

use stickslip::friction::FrictionLaw;
use stickslip::scene::{CheckedScene, FidelityLevel, Scheme};
use stickslip::simulation::{ExternalFriction, ExternalKinetic, Simulator};

/// Viscous friction F = b v (N, with v in m/s): continuous, with F v >= 0, so the
/// coupling never meets the direction rule for tangents that point against v_rel.
struct Viscous {
    /// b (N s/m).
    damping: f64,
}

impl FrictionLaw for Viscous {
    fn name(&self) -> &str {
        "viscous"
    }

    fn sliding_force(&mut self, sliding_velocity: f64, _normal_force: f64) -> f64 {
        self.damping * sliding_velocity
    }

    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, _normal_force: f64) -> (f64, f64) {
        (self.damping * sliding_velocity, self.damping)
    }
}

/// b = 1000 N s/m: breakaway at the paper's 0.4 s, then slip towards rest at
/// u = b v_b / k = 3.2 mm (viscous friction damps; there is no stick-slip cycle). The
/// embedded slip equation is affine for this law, so Newton solves it in one pass, like
/// the coupled tangent.
const DAMPING: f64 = 1000.0;

/// Belt speed (m/s) over the step from `t` (s): the paper's 0.02 m/s, stopped from
/// 0.8 s to 1 s, so that the resting tip re-sticks (v_rel = 0, holding force 20 N below
/// mu_s F_n) and breaks away again once the belt runs.
fn belt_speed(t: f64) -> f64 {
    if (0.8 - 1e-9..1.0 - 1e-9).contains(&t) {
        0.0
    } else {
        0.02
    }
}

fn scene(scheme: Scheme) -> CheckedScene {
    let mut scene = CheckedScene::paper().into_scene();
    scene.fidelity.level = FidelityLevel::Modal;
    scene.integrator.scheme = scheme;
    // eps = 0.01 m/s: the tip creeping back after the belt stops (v_rel = k u / b,
    // 0.02 m/s at u = 3.2 mm) re-sticks within the stop.
    scene.friction.stick_threshold = 0.01;
    scene.check().unwrap()
}

/// Tip deflection (m) at the communication points k h up to the scene's end, and the
/// number of stick/slip transitions: the law embedded.
fn embedded(scheme: Scheme, h: f64) -> (Vec<f64>, u64) {
    let scene = scene(scheme);
    let n = (scene.time.end / h).round() as usize;
    let mut simulator = Simulator::new(scene, Box::new(Viscous { damping: DAMPING })).unwrap();
    let mut deflection = vec![simulator.sample().tip_deflection];
    for k in 1..=n {
        simulator.set_belt_speed(belt_speed((k - 1) as f64 * h));
        simulator.advance_to(k as f64 * h).unwrap();
        deflection.push(simulator.sample().tip_deflection);
    }
    (deflection, simulator.state().transition_count)
}

/// The same, with the law outside: at each communication point the model is evaluated
/// at the current v_rel (`stale = false`) or at the one a step before (`stale = true`),
/// and its tangent is held over the step, with the static limit mu_s F_n.
fn coupled(scheme: Scheme, h: f64, stale: bool) -> (Vec<f64>, u64) {
    coupled_with_slope(scheme, h, stale, DAMPING)
}

/// `coupled` with the slope handed over as `slope` (N s/m) instead of the law's.
fn coupled_with_slope(scheme: Scheme, h: f64, stale: bool, slope: f64) -> (Vec<f64>, u64) {
    let scene = scene(scheme);
    let n = (scene.time.end / h).round() as usize;
    let limit = scene.friction.static_coefficient * scene.loading.normal_force;
    // The simulator's own law never acts while the external friction is set.
    let mut simulator =
        Simulator::new(scene.clone(), Box::new(scene.friction.exponential_law())).unwrap();
    let mut law = Viscous { damping: DAMPING };
    let mut deflection = vec![simulator.sample().tip_deflection];
    let mut before = simulator.state().relative_velocity;
    for k in 1..=n {
        let now = simulator.state().relative_velocity;
        let velocity = if stale { before } else { now };
        before = now;
        simulator.set_external_friction(Some(ExternalFriction {
            kinetic: ExternalKinetic::Signed {
                force: law.sliding_force(velocity, 100.0),
                slope,
                velocity,
            },
            static_limit: limit,
        }));
        simulator.set_belt_speed(belt_speed((k - 1) as f64 * h));
        simulator.advance_to(k as f64 * h).unwrap();
        deflection.push(simulator.sample().tip_deflection);
    }
    (deflection, simulator.state().transition_count)
}

#[test]
fn a_linear_law_coupled_by_its_tangent_is_the_embedded_law_at_any_communication_step() {
    for scheme in [Scheme::GeneralizedAlpha, Scheme::MoreauJean] {
        for h in [1e-3, 1e-2] {
            let (reference, transitions) = embedded(scheme, h);
            // The run exercises the switch: breakaway, re-stick, breakaway.
            assert!(transitions >= 3, "{scheme:?}: {transitions} transitions");
            for stale in [false, true] {
                let (u, count) = coupled(scheme, h, stale);
                let deviation = u
                    .iter()
                    .zip(&reference)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                println!("{scheme:?} h = {h} s, stale = {stale}: max |du| = {deviation:e} m, {count} transitions");
                assert_eq!(count, transitions, "{scheme:?} h = {h} s, stale = {stale}");
                // The solves agree to 1e-12 of the force (~1e-10 N), which moves the
                // tip by ~1e-19 m per step through du/dF ~ 1e-9 m/N: ~1e-15 m after
                // 12 000 steps, as measured (4e-15 m); 1e-12 m is 1e-10 of the
                // deflection corridor.
                assert!(
                    deviation <= 1e-12,
                    "{scheme:?} h = {h} s, stale = {stale}: max |du| = {deviation:e} m"
                );
            }
        }
    }
}

/// Without the slope the held force is a zero-order hold of the law: b v_k held over
/// 10 ms, while v changes within the step. The same run then differs by millimetres
/// (2.2 mm measured), not by rounding.
#[test]
fn without_the_slope_the_held_force_lags() {
    let h = 1e-2;
    let (reference, _) = embedded(Scheme::GeneralizedAlpha, h);
    let (u, _) = coupled_with_slope(Scheme::GeneralizedAlpha, h, false, 0.0);
    let deviation = u
        .iter()
        .zip(&reference)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("slope 0, h = {h} s: max |du| = {deviation:e} m");
    assert!(deviation > 1e-6, "{deviation:e} m");
}
