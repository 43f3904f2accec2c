//! Closed-form estimates of the Euler-Bernoulli cantilever that the scripts need to set
//! up a sweep: its natural frequencies, the Rayleigh damping that gives a ratio at two of
//! them, and the belt speed above which steady sliding is linearly stable.

use crate::elementary;
use crate::friction::FrictionLawKind;
use crate::scene::{CheckedScene, Damping, SlidingVelocity};

/// beta_n L of the clamped-free beam: the roots of cos(x) cosh(x) = -1 (Meirovitch,
/// Fundamentals of Vibrations, Sec. 8.7), for modes 1 to 4.
pub const CANTILEVER_BETA_L: [f64; 4] = [
    1.875_104_068_711_961,
    4.694_091_132_974_175,
    7.854_757_438_237_613,
    10.995_540_734_875_467,
];

/// Angular frequency omega_n = (beta_n L)^2 sqrt(EI / (rho A L^4)) (rad/s) of bending
/// mode `mode` (1-based, at most 4) of the Euler-Bernoulli cantilever.
pub fn cantilever_omega(scene: &CheckedScene, mode: usize) -> Option<f64> {
    let beta_l = CANTILEVER_BETA_L.get(mode.checked_sub(1)?)?;
    let length = scene.geometry.length;
    Some(
        beta_l.powi(2)
            * (scene.bending_stiffness() / (scene.mass_per_length() * length.powi(4))).sqrt(),
    )
}

/// Rayleigh damping C = a M + b K with damping ratio `ratio` at modes 1 and 3 of the
/// cantilever (zeta(w) = a / (2 w) + b w / 2; Chopra, Dynamics of Structures, Sec. 11.4).
pub fn rayleigh_at_modes_1_and_3(scene: &CheckedScene, ratio: f64) -> Damping {
    let to_hz = |omega: Option<f64>| omega.unwrap_or(f64::NAN) / (2.0 * std::f64::consts::PI);
    Damping::from_ratio(
        ratio,
        to_hz(cantilever_omega(scene, 1)),
        to_hz(cantilever_omega(scene, 3)),
    )
}

/// Belt speed v_b (m/s) above which steady sliding is linearly stable in mode 1, or
/// `None` where the estimate does not apply (a law other than the exponential one, or
/// the paper-literal tip velocity fed to it).
///
/// Linearised about steady sliding, the exponential law's slope
/// dF/dv_rel = -alpha (mu_s - mu_k) F_n exp(-alpha v_b) feeds the tip velocity back as
/// negative damping. The mass-normalised modes of a uniform cantilever all have
/// phi_n(L)^2 = 4 / M at the tip (M = rho A L), so mode 1, the least damped
/// (2 zeta_1 omega_1 = a + b omega_1^2), is stable when
/// (4 / M) alpha (mu_s - mu_k) F_n exp(-alpha v_b) < a + b omega_1^2. The higher modes
/// and the coupling through the static correction are left out. Returns 0 when the law
/// has no falling branch and infinity when the beam has no damping.
pub fn sliding_stability_speed(scene: &CheckedScene) -> Option<f64> {
    let omega_1 = cantilever_omega(scene, 1)?;
    let mass = scene.mass_per_length() * scene.geometry.length;
    sliding_stability_speed_in_mode(scene, omega_1, 4.0 / mass)
}

/// [`sliding_stability_speed`] for a mode of angular frequency `omega` (rad/s) whose
/// M-normalised shape has phi(tip)^2 = `participation` (1/kg) at the friction's DOF:
/// stable when participation alpha (mu_s - mu_k) F_n exp(-alpha v_b) < a + b omega^2.
/// The beam's mode 1 has participation 4 / M; a `[structure]`'s comes from its own
/// modes (`linear_structure::estimates`). The scene's Rayleigh damping only: a
/// structure's damping file C0 is left out.
pub fn sliding_stability_speed_in_mode(
    scene: &CheckedScene,
    omega: f64,
    participation: f64,
) -> Option<f64> {
    if scene.friction.law != FrictionLawKind::Exponential
        || scene.contact.sliding_velocity != SlidingVelocity::Relative
    {
        return None;
    }
    let damping =
        scene.damping.mass_proportional + scene.damping.stiffness_proportional * omega.powi(2);
    let friction = &scene.friction;
    let alpha = friction.decay;
    let gain = participation
        * alpha
        * (friction.static_coefficient - friction.kinetic_coefficient)
        * scene.loading.normal_force;
    if alpha <= 0.0 || gain <= 0.0 {
        return Some(0.0);
    }
    if damping <= 0.0 {
        return Some(f64::INFINITY);
    }
    Some(elementary::ln(gain / damping).max(0.0) / alpha)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn the_roots_solve_the_cantilever_frequency_equation() {
        for x in CANTILEVER_BETA_L {
            assert!(
                (elementary::cos(x) * elementary::cosh(x) + 1.0).abs()
                    < 1e-12 * elementary::cosh(x),
                "{x}"
            );
        }
    }

    #[test]
    fn the_paper_beam_has_the_notes_frequencies() {
        // physics notes: f1, f2, f3 = 5.711, 35.79, 100.22 Hz.
        let scene = Scene::default().check().unwrap();
        let hz = |n| cantilever_omega(&scene, n).unwrap() / (2.0 * std::f64::consts::PI);
        assert!((hz(1) - 5.711).abs() < 5e-4);
        assert!((hz(2) - 35.79).abs() < 5e-3);
        assert!((hz(3) - 100.22).abs() < 5e-3);
        assert_eq!(cantilever_omega(&scene, 5), None);
        assert_eq!(cantilever_omega(&scene, 0), None);
    }

    #[test]
    fn rayleigh_damping_gives_the_ratio_at_both_modes() {
        let scene = Scene::default().check().unwrap();
        let d = rayleigh_at_modes_1_and_3(&scene, 0.02);
        for n in [1, 3] {
            let w = cantilever_omega(&scene, n).unwrap();
            let zeta = d.mass_proportional / (2.0 * w) + d.stiffness_proportional * w / 2.0;
            assert!((zeta - 0.02).abs() < 1e-12, "mode {n}: {zeta}");
        }
    }

    #[test]
    fn the_stability_speed_balances_the_friction_slope_and_the_damping() {
        let mut raw = Scene {
            damping: Damping::none(),
            ..Scene::default()
        };
        let scene = raw.clone().check().unwrap();
        assert_eq!(sliding_stability_speed(&scene), Some(f64::INFINITY));
        raw.damping = Damping {
            mass_proportional: 1.0,
            stiffness_proportional: 0.0,
        };
        let scene = raw.clone().check().unwrap();
        let v = sliding_stability_speed(&scene).unwrap();
        // At v the negative damping of the law equals a + b omega_1^2 = 1 / s.
        let mass = scene.mass_per_length() * scene.geometry.length;
        let slope = 5.0 * 0.3 * 100.0 * elementary::exp(-5.0 * v);
        assert!((4.0 / mass * slope - 1.0).abs() < 1e-12);
        raw.friction.law = FrictionLawKind::Coulomb;
        assert_eq!(sliding_stability_speed(&raw.check().unwrap()), None);
    }
}
