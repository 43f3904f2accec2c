//! The modal model of the plane-stress mesh (`fidelity.modal_basis = plane-stress`, the
//! study's `PlaneStressModal`): its frequencies against the mesh and against beam
//! theory, its static tip stiffness, and its stick-slip run against the full mesh's.

use stickslip::auto::first_cycle_deviation;
use stickslip::modal::{self, lanczos_modes};
use stickslip::scene::{CheckedScene, Scene, Scheme};
use stickslip::stability::cantilever_omega;
use stickslip::structure::StructuralModel;
use stickslip::study::{measure, Configuration, Resolution};

fn hz(omega_squared: f64) -> f64 {
    omega_squared.sqrt() / (2.0 * std::f64::consts::PI)
}

fn relative_error(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The lowest `count` frequencies (Hz) of a model.
fn frequencies(model: &StructuralModel, count: usize) -> Vec<f64> {
    lanczos_modes(model, count)
        .unwrap()
        .eigenvalues
        .into_iter()
        .map(hz)
        .collect()
}

fn stubby() -> CheckedScene {
    let mut scene = Scene::default();
    scene.geometry.length = 0.2;
    scene.geometry.height = 0.02;
    scene.material.youngs_modulus = 40e6;
    scene.check().unwrap()
}

#[test]
fn the_reduced_mesh_keeps_the_meshs_lowest_frequencies() {
    let scene = CheckedScene::paper();
    let full = StructuralModel::plane_stress(&scene, 0.02);
    let reduced = modal::reduce(&full, 10, true).unwrap();
    // The Ritz basis holds the exact eigenvectors, so the reduced model's lowest
    // frequencies are the mesh's to the solver's tolerance (1e-10 on omega^2).
    let f_full = frequencies(&full, 10);
    let f_reduced = reduced.natural_frequencies(10).unwrap();
    for (a, b) in f_reduced.iter().zip(&f_full) {
        assert!(relative_error(*a, *b) < 1e-8, "{a} vs {b}");
    }
}

#[test]
fn mesh_frequencies_converge_and_stay_near_beam_theory_on_the_slender_beam() {
    // L/h = 200: Timoshenko's shear and rotary inertia lower mode n by about
    // (beta_n h)^2 (1 + E / (kappa G)) / 24, 1.5e-5 for mode 1 and 2.6e-4 for mode 3, so
    // the mesh must converge to within a few 1e-4 of Euler-Bernoulli
    // (docs/measurements.md, "Statics and frequencies": +0.06 % at 0.02 m), with the
    // change from mesh to mesh shrinking.
    let scene = CheckedScene::paper();
    let eb: Vec<f64> = (1..=3)
        .map(|n| cantilever_omega(&scene, n).unwrap() / (2.0 * std::f64::consts::PI))
        .collect();
    let meshes: Vec<Vec<f64>> = [0.04, 0.02, 0.01]
        .into_iter()
        .map(|size| frequencies(&StructuralModel::plane_stress(&scene, size), 3))
        .collect();
    for mode in 0..3 {
        let f: Vec<f64> = meshes.iter().map(|m| m[mode]).collect();
        assert!(
            (f[2] - f[1]).abs() < (f[1] - f[0]).abs(),
            "mode {}: {f:?}",
            mode + 1
        );
        assert!(
            relative_error(f[2], eb[mode]) < 1e-3,
            "mode {}: {f:?} vs {}",
            mode + 1,
            eb[mode]
        );
    }
}

/// Timoshenko's first-order correction of an Euler-Bernoulli frequency for shear and
/// rotary inertia: omega_T = omega_EB / sqrt(1 + (beta r)^2 (1 + E / (kappa G))) with
/// r^2 = h^2 / 12, kappa = 5/6 (rectangle) and beta = beta_n L / L (Rao, Vibration of
/// Continuous Systems, Sec. 11.7, for small beta r).
fn timoshenko_hz(scene: &CheckedScene, mode: usize) -> f64 {
    let beta_l = stickslip::stability::CANTILEVER_BETA_L[mode - 1];
    let g = &scene.geometry;
    let r2 = g.height.powi(2) / 12.0;
    let e_over_kappa_g = 2.0 * (1.0 + scene.material.poisson_ratio) / (5.0 / 6.0);
    let beta = beta_l / g.length;
    cantilever_omega(scene, mode).unwrap()
        / (1.0 + beta * beta * r2 * (1.0 + e_over_kappa_g)).sqrt()
        / (2.0 * std::f64::consts::PI)
}

#[test]
fn on_a_stubby_beam_the_mesh_follows_timoshenko_not_euler_bernoulli() {
    // L/h = 10: shear lowers mode 2 by per cents. The mesh's bending modes (every mode
    // with a tip deflection; the axial ones between them have none) must be nearer
    // Timoshenko's estimate than Euler-Bernoulli's.
    let scene = stubby();
    let model = StructuralModel::plane_stress(&scene, 0.005);
    let modes = lanczos_modes(&model, 6).unwrap();
    let bending: Vec<f64> = modes
        .eigenvalues
        .iter()
        .zip(&modes.vectors)
        .filter(|(_, phi)| {
            model.tip_value(phi).abs() > 1e-3 * model.tip_value(&modes.vectors[0]).abs()
        })
        .map(|(w2, _)| hz(*w2))
        .collect();
    for mode in 1..=2 {
        let f = bending[mode - 1];
        let eb = cantilever_omega(&scene, mode).unwrap() / (2.0 * std::f64::consts::PI);
        let timoshenko = timoshenko_hz(&scene, mode);
        assert!(
            relative_error(f, timoshenko) < 0.5 * relative_error(f, eb),
            "mode {mode}: mesh {f} Hz, Euler-Bernoulli {eb} Hz, Timoshenko {timoshenko} Hz"
        );
    }
}

#[test]
fn the_reduced_mesh_has_the_meshs_static_tip_stiffness() {
    for scene in [CheckedScene::paper(), stubby()] {
        let full = StructuralModel::plane_stress(&scene, 0.01);
        let exact = full.static_tip_deflection(50.0).unwrap();
        for modes in [1, 5, 20] {
            let d = modal::reduce(&full, modes, true)
                .unwrap()
                .static_tip_deflection(50.0)
                .unwrap();
            // Exact in exact arithmetic (K^-1 c is in the basis); the rest is round-off
            // amplified by cond(K) (the same 2e-7 as for the beam basis).
            assert!(
                relative_error(d, exact) < 2e-7,
                "{modes} modes: {d} vs {exact}"
            );
        }
    }
}

#[test]
fn a_stick_slip_run_approaches_the_full_mesh_as_modes_are_added() {
    // Paper scene to 0.6 s (breakaway at 0.40 s and the first slip, 0.13 s), 0.02 m mesh,
    // dt 1e-4 s: the reduced model's deviation from the full mesh's run falls as modes
    // are added.
    let mut scene = Scene::default();
    scene.time.end = 0.6;
    let at = |resolution| Configuration {
        resolution,
        dt: 1e-4,
        scheme: Scheme::GeneralizedAlpha,
        inference: None,
    };
    let law = stickslip_tests::law_of(&scene);
    let full = measure(
        &scene,
        &law,
        at(Resolution::PlaneStress { element_size: 0.02 }),
    )
    .unwrap();
    let deviation = |modes| {
        let run = measure(
            &scene,
            &law,
            at(Resolution::PlaneStressModal {
                element_size: 0.02,
                modes,
            }),
        )
        .unwrap();
        first_cycle_deviation(&run.tip, &full)
    };
    let errors: Vec<f64> = [2, 5, 10].into_iter().map(deviation).collect();
    // Measured: 0.49 um, 6.5 nm, 6.5 nm. From 5 modes on, what is left are modes above
    // 325 Hz that the full mesh keeps but generalised-alpha at this step damps; more
    // modes may only change it by round-off.
    assert!(errors[0] > 10.0 * errors[1], "{errors:?}");
    assert!(errors[2] <= errors[1] * (1.0 + 1e-3), "{errors:?}");
    // 1e-8 m: a millionth of the paper scene's 8 mm breakaway deflection.
    assert!(errors[2] < 1e-8, "{errors:?}");
}
