//! The example law of the registry, Stribeck with viscous friction
//! (`stickslip::friction::stribeck`), in the time loop against closed forms: breakaway
//! where the tip spring reaches mu_s F_n, and, where the viscous term makes steady
//! sliding stable, the tip at rest at F(v_b) / k with k = 3 EI / L^3; and through the
//! scene file and the command line's parameter names.

use stickslip::friction::registry;
use stickslip::friction::stribeck::{self, StribeckLaw};
use stickslip::friction::{FrictionLaw, FrictionLawKind};
use stickslip::law_source::LawSource;
use stickslip::run::run_scene;
use stickslip::scene::{FidelityLevel, Scene};

/// The paper beam at beam fidelity (exact static tip stiffness for a tip load: cubic
/// Hermite elements) with the Stribeck law.
fn scene(belt_speed: f64, viscous: f64, t_end: f64) -> Scene {
    let mut s = Scene::default();
    s.friction.law = FrictionLawKind::Stribeck;
    s.friction.laws.set(&stribeck::VISCOUS_COEFFICIENT, viscous);
    s.loading.belt_speed = belt_speed;
    s.fidelity.level = FidelityLevel::Beam;
    s.time.end = t_end;
    s
}

/// 3 EI / L^3 (N/m) of the scene's beam.
fn tip_stiffness(s: &Scene) -> f64 {
    let g = &s.geometry;
    let inertia = g.width * g.height.powi(3) / 12.0;
    3.0 * s.material.youngs_modulus * inertia / g.length.powi(3)
}

/// At belt speed 0.2 m/s (u = v_b / v_s = 2) the Gaussian falls with slope
/// -2 u (mu_s - mu_k) exp(-u^2) F_n / v_s = -22 N s/m and sigma_v = 100 N s/m turns the
/// net slope of the kinetic force to +78 N s/m: positive damping on the first mode (tip
/// mass ~ 5 kg, k = 6.25e3 N/m, damping ratio 78 / (2 sqrt(k m)) = 22 %), so steady
/// sliding is stable and the transient after breakaway (8 mm - 6.5 mm) decays as
/// exp(-7.8 t / s), by 2.5 s to below 1e-8 of itself. The kinetic force there,
/// F(v_b) = [mu_k + (mu_s - mu_k) exp(-4)] F_n + sigma_v v_b = 40.5 N, stays below the
/// static limit mu_s F_n = 50 N, so the tip does not stick again. It then rests at
/// F(v_b) / k. Asserted: the mean tip deflection over 2.5 to 3 s within 1e-6 relative of
/// it (the beam elements' static tip stiffness is exact), the residual motion below
/// 1 nm, and the relative velocity the belt's.
#[test]
fn with_stable_sliding_the_tip_rests_where_the_spring_holds_the_kinetic_force() {
    let (belt, viscous) = (0.2, 100.0);
    let s = scene(belt, viscous, 3.0);
    let k = tip_stiffness(&s);
    let mut law = StribeckLaw::of(&s.friction.coefficients(), &s.friction.laws);
    let force = law.sliding_force(belt, s.loading.normal_force);
    assert!(force < s.friction.static_coefficient * s.loading.normal_force);
    let expected = force / k;
    let checked = s.check().unwrap();
    let source = LawSource::resolve(&checked).unwrap();
    let run = run_scene(checked, &source, 1).unwrap();
    let tail: Vec<f64> = run
        .samples
        .iter()
        .filter(|p| p.time > 2.5)
        .map(|p| p.tip_deflection)
        .collect();
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    let spread = tail.iter().fold(0.0f64, |m, x| m.max((x - mean).abs()));
    assert!(
        ((mean - expected) / expected).abs() < 1e-6,
        "tip {mean:e} m, F(v_b) / k = {expected:e} m"
    );
    assert!(spread < 1e-9, "residual motion {spread:e} m");
    // Sliding throughout the tail: the relative velocity is the belt's.
    let last = run.samples.last().unwrap();
    assert!((last.relative_velocity - belt).abs() < 1e-9, "{last:?}");
}

/// Breakaway does not depend on the kinetic law: the tip sticks until the tip spring
/// holds mu_s F_n, at deflection mu_s F_n / k = 8 mm and time 8 mm / v_b. Asserted within
/// 1 % (the stuck beam's tip spring is the static one: the belt drags slowly against
/// the first period, 0.18 s).
#[test]
fn breakaway_is_where_the_tip_spring_reaches_the_static_limit() {
    let s = scene(0.02, 0.0, 0.6);
    let k = tip_stiffness(&s);
    let limit = s.friction.static_coefficient * s.loading.normal_force;
    let checked = s.check().unwrap();
    let source = LawSource::resolve(&checked).unwrap();
    let run = run_scene(checked, &source, 1).unwrap();
    let first_slip = run
        .samples
        .iter()
        .find(|p| !p.stick)
        .expect("a slip within 0.6 s");
    let deflection = limit / k;
    assert!(
        ((first_slip.tip_deflection - deflection) / deflection).abs() < 1e-2,
        "{first_slip:?} against {deflection:e} m"
    );
    assert!(((first_slip.time - deflection / 0.02) / (deflection / 0.02)).abs() < 1e-2);
}

/// The law's table reads from the scene file under the registry's names, refuses an
/// unknown key and a value out of range by name, and the command line's
/// `--law-parameter` names the same parameters.
#[test]
fn the_table_comes_from_the_scene_file_and_is_checked_by_name() {
    let text = "[friction]\nlaw = \"stribeck\"\n[friction.stribeck]\nstribeck_velocity = 0.05\nviscous_coefficient = 3\n";
    let scene: Scene = toml::from_str(text).unwrap();
    assert_eq!(scene.friction.law, FrictionLawKind::Stribeck);
    let law = StribeckLaw::of(&scene.friction.coefficients(), &scene.friction.laws);
    assert_eq!(
        (law.stribeck_velocity, law.viscous_coefficient),
        (0.05, 3.0)
    );
    let written = toml::to_string(&scene).unwrap();
    let back: Scene = toml::from_str(&written).unwrap();
    assert_eq!(back, scene);
    let unknown = toml::from_str::<Scene>("[friction.stribeck]\nstribeck_speed = 1\n")
        .unwrap_err()
        .to_string();
    assert!(unknown.contains("stribeck_speed"), "{unknown}");
    let mut bad = scene.clone();
    bad.friction.laws.set(&stribeck::STRIBECK_VELOCITY, 0.0);
    let refused = bad.check().unwrap_err().to_string();
    assert!(
        refused.contains("friction.stribeck.stribeck_velocity") && refused.contains("> 0 (m/s)"),
        "{refused}"
    );
    let (parameter, value) = registry::parse_assignment("stribeck.viscous_coefficient=7").unwrap();
    assert_eq!(
        (parameter.name, value),
        (stribeck::VISCOUS_COEFFICIENT.name, 7.0)
    );
}
