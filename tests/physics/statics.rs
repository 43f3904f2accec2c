//! Static tip deflection and natural frequencies against Euler-Bernoulli theory.

use stickslip::modal;
use stickslip::scene::{CheckedScene, Clamp, Scene};
use stickslip::statics::convergence_study;
use stickslip::structure::{
    euler_bernoulli_tip_deflection, timoshenko_tip_deflection, StructuralModel,
};

/// The paper's static check: P = 50 N at the tip, delta_ref = 4 P L^3 / (E h^3) = 8 mm.
const LOAD: f64 = 50.0;

fn relative_error(d: f64, reference: f64) -> f64 {
    (d - reference).abs() / reference.abs()
}

#[test]
fn euler_bernoulli_reference_is_eight_millimetres() {
    let scene = CheckedScene::paper();
    assert!((euler_bernoulli_tip_deflection(&scene, LOAD) - 0.008).abs() < 1e-15);
}

#[test]
fn beam_elements_are_exact_at_the_tip() {
    // Hermite elements reproduce the cubic deflection of a tip-loaded cantilever
    // exactly; what is left is round-off of the ill-conditioned K (cond ~ n^4).
    let scene = CheckedScene::paper();
    for n in [1, 5, 20, 100] {
        let d = StructuralModel::beam(&scene, n)
            .static_tip_deflection(LOAD)
            .unwrap();
        assert!(relative_error(d, 0.008) < 1e-9, "{n} elements: {d}");
    }
}

#[test]
fn plane_stress_at_paper_mesh_is_within_half_a_per_mille() {
    let scene = CheckedScene::paper();
    let d = StructuralModel::plane_stress(&scene, 0.02)
        .static_tip_deflection(LOAD)
        .unwrap();
    // Paper: 0.04 % at element size 0.02 m.
    assert!(relative_error(d, 0.008) < 5e-4, "{d}");
}

#[test]
fn plane_stress_error_falls_with_refinement() {
    let scene = CheckedScene::paper();
    let rows = convergence_study(&scene, LOAD, &[0.16, 0.08, 0.04, 0.02, 0.01]).unwrap();
    for clamp in ["neutral-axis", "full"] {
        let errors: Vec<f64> = rows
            .iter()
            .filter(|r| r.clamp == clamp)
            .map(|r| r.error_timoshenko.abs())
            .collect();
        for pair in errors.windows(2) {
            assert!(pair[1] < pair[0], "{clamp}: {errors:?}");
        }
    }
    // The neutral-axis clamp converges to the Timoshenko (EB + shear) deflection at
    // better than second order; the full clamp at first order (corner singularities).
    let na: Vec<f64> = rows
        .iter()
        .filter(|r| r.clamp == "neutral-axis")
        .map(|r| r.error_timoshenko.abs())
        .collect();
    assert!(na[1] / na[2] > 4.0 && na[2] / na[3] > 4.0, "{na:?}");
    let full: Vec<f64> = rows
        .iter()
        .filter(|r| r.clamp == "full")
        .map(|r| r.error_timoshenko.abs())
        .collect();
    let rate = full[3] / full[4];
    assert!(
        (1.7..2.3).contains(&rate),
        "full clamp halving ratio {rate}"
    );
    // The converged value is Timoshenko's, 0.002 % above Euler-Bernoulli.
    let finest = rows
        .iter()
        .find(|r| r.clamp == "neutral-axis" && r.element_size == 0.01);
    let timo = timoshenko_tip_deflection(&scene, LOAD);
    assert!(relative_error(finest.unwrap().deflection, timo) < 5e-6);
}

/// Euler-Bernoulli cantilever frequencies f_i = (beta_i L)^2 / (2 pi L^2) sqrt(EI / rho A)
/// with beta L = 1.87510, 4.69409, 7.85476: 5.711, 35.79, 100.22 Hz for the paper's beam.
fn euler_bernoulli_frequencies(scene: &CheckedScene) -> [f64; 3] {
    let base = (scene.bending_stiffness() / scene.mass_per_length()).sqrt()
        / (2.0 * std::f64::consts::PI * scene.geometry.length.powi(2));
    [1.875_104_07f64, 4.694_091_13, 7.854_757_44].map(|b| b * b * base)
}

#[test]
fn analytical_frequencies_match_the_notes() {
    let f = euler_bernoulli_frequencies(&CheckedScene::paper());
    for (got, want) in f.iter().zip([5.711, 35.79, 100.22]) {
        assert!(relative_error(*got, want) < 2e-4, "{got} vs {want}");
    }
}

#[test]
fn beam_frequencies_within_a_per_mille() {
    let scene = CheckedScene::paper();
    let reference = euler_bernoulli_frequencies(&scene);
    let f = StructuralModel::beam(&scene, 100)
        .natural_frequencies(3)
        .unwrap();
    for (got, want) in f.iter().zip(reference) {
        assert!(relative_error(*got, want) < 1e-3, "{got} vs {want}");
    }
}

#[test]
fn plane_stress_frequencies_within_half_a_percent() {
    let scene = CheckedScene::paper();
    let reference = euler_bernoulli_frequencies(&scene);
    let f = StructuralModel::plane_stress(&scene, 0.02)
        .natural_frequencies(3)
        .unwrap();
    for (got, want) in f.iter().zip(reference) {
        assert!(relative_error(*got, want) < 5e-3, "{got} vs {want}");
    }
}

/// Tolerance for identities that are exact in exact arithmetic but go through solves with
/// the ill-conditioned stiffness matrix (measured: 4e-9 beam, 5e-8 plane stress).
const ROUND_OFF: f64 = 2e-7;

#[test]
fn modal_model_keeps_exact_static_stiffness_for_any_mode_count() {
    let scene = CheckedScene::paper();
    let full = StructuralModel::beam(&scene, 40);
    let exact = full.static_tip_deflection(LOAD).unwrap();
    for modes in [1, 2, 5, 20] {
        let reduced = modal::reduce(&full, modes, true).unwrap();
        let d = reduced.static_tip_deflection(LOAD).unwrap();
        // Exact in exact arithmetic (psi = K^-1 c lies in the basis); what remains is
        // round-off amplified by cond(K) (~1e8 for the beam, ~1e10 for the 2D mesh).
        assert!(
            relative_error(d, exact) < ROUND_OFF,
            "{modes} modes: {d} vs {exact}"
        );
    }
    // Without the correction, one mode is too stiff: phi_1(L)^2 / omega_1^2 misses the
    // compliance of every higher mode (about 3 % for a cantilever).
    let one = modal::reduce(&full, 1, false).unwrap();
    let d = one.static_tip_deflection(LOAD).unwrap();
    assert!(d < 0.98 * exact, "{d} vs {exact}");
    // The reduced model keeps the lowest frequencies.
    let f = modal::reduce(&full, 5, true)
        .unwrap()
        .natural_frequencies(3)
        .unwrap();
    let f_full = full.natural_frequencies(3).unwrap();
    for (a, b) in f.iter().zip(&f_full) {
        assert!(relative_error(*a, *b) < ROUND_OFF);
    }
}

#[test]
fn modal_from_plane_stress_keeps_its_static_stiffness() {
    let mut scene = Scene::default();
    scene.fidelity.element_size = 0.04;
    scene.fidelity.clamp = Clamp::NeutralAxis;
    let scene = scene.check().unwrap();
    let full = StructuralModel::plane_stress(&scene, 0.04);
    let exact = full.static_tip_deflection(LOAD).unwrap();
    let reduced = modal::reduce(&full, 3, true).unwrap();
    let d = reduced.static_tip_deflection(LOAD).unwrap();
    assert!(relative_error(d, exact) < ROUND_OFF, "{d} vs {exact}");
}
