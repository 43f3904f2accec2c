//! The modal fidelity of a user's structure (issue 35 item 2): `fidelity.level = "modal"`
//! on a `[structure]` reduces the structure's full model to its lowest modes plus the
//! static shape under a unit force at the contact DOF, as the beam's modal level does.
//! Checked on the CalculiX paper beam (examples/calculix-beam: 1002 free DOFs, contact
//! at node 502 in y): the reduced model's spectrum and static tip against the full
//! model's, and the paper scene's run with k modes against the full run.

use std::path::{Path, PathBuf};
use std::time::Instant;
use stickslip::law_source::LawSource;
use stickslip::modal::{lanczos_modes, reduce};
use stickslip::run::run_scene;
use stickslip::scene::{CheckedScene, FidelityLevel, Scene};
use stickslip::structure::StructuralModel;

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/calculix-beam")
}

/// The example scene with `fidelity.level` and `fidelity.modes` set, checked.
fn scene_with(level: FidelityLevel, modes: usize) -> CheckedScene {
    let loaded = Scene::load(&example().join("scene.toml")).unwrap();
    let mut scene = loaded.scene().clone();
    scene.fidelity.level = level;
    scene.fidelity.modes = modes;
    scene.check().unwrap()
}

/// The reduction keeps the full model's modes: the basis holds the exact eigenvectors
/// (to Lanczos' 1e-10 residual), so the Rayleigh-Ritz values on it are the full model's
/// eigenvalues, and the one extra value (the static shape's) lies above the next full
/// eigenvalue (Poincare's separation: the i-th Ritz value is at least the i-th
/// eigenvalue). The built model is `reduce` of the full one, bit for bit.
#[test]
fn the_reduced_structure_keeps_the_full_models_lowest_frequencies() {
    let full = StructuralModel::build(&scene_with(FidelityLevel::PlaneStress, 10)).unwrap();
    let exact = lanczos_modes(&full, 21).unwrap().eigenvalues;
    for k in [2, 5, 10, 20] {
        let scene = scene_with(FidelityLevel::Modal, k);
        let reduced = StructuralModel::build(&scene).unwrap();
        let direct = reduce(&full, k, true).unwrap();
        assert_eq!(reduced.stiffness.diagonal(), direct.stiffness.diagonal());
        assert_eq!(reduced.tip, direct.tip);
        assert_eq!(reduced.level, FidelityLevel::Modal);
        assert_eq!(reduced.dofs(), k + 1, "{}", reduced.label);
        assert!(
            reduced
                .label
                .contains("static correction of structure, 1002 DOFs"),
            "{}",
            reduced.label
        );
        // M = I, K = diag(omega^2) ascending: the reduced spectrum is K's diagonal.
        let values = reduced.stiffness.diagonal();
        let own = lanczos_modes(&full, k).unwrap().eigenvalues;
        let relative = |a: f64, b: f64| ((a - b) / b).abs();
        let (mut same, mut longer): (f64, f64) = (0.0, 0.0);
        for i in 0..k {
            same = same.max(relative(values[i], own[i]));
            longer = longer.max(relative(values[i], exact[i]));
        }
        println!(
            "{k} modes: largest relative omega^2 difference {same:.1e} from its own modes, {longer:.1e} from a 21-mode Lanczos run; extra value {:.6e} >= omega_{}^2 {:.6e}",
            values[k],
            k + 1,
            exact[k]
        );
        // In exact arithmetic the static shape, M-orthogonalised against the modes, has
        // no stiffness coupling with them (c . phi_i = p_i omega_i^2, `modal::reduce`);
        // computed, that difference of two products is round-off of K's condition
        // (~7e10), and the dense (k+1) x (k+1) eigen solve moves the modes by its square
        // over the gap. Measured against its own Lanczos modes and against an
        // independent 21-mode run alike: 3e-13 at 2 modes, 4.5e-12 at 5, 2.6e-10 at 20.
        // 1e-9 relative on omega^2 (5e-10 on frequency) fails on any lost or shifted
        // mode (the next one is 20 % or more away).
        assert!(same < 1e-9, "{k} modes: {same:e}");
        assert!(longer < 1e-9, "{k} modes: {longer:e}");
        assert!(values[k] >= exact[k] * (1.0 - 1e-10), "{k} modes");
    }
}

/// With the static correction the reduced static tip under a unit force at the contact
/// DOF is the full model's (the static shape is in the basis: the Ritz projection is
/// exact for that load); without it, the truncated modal series is stiffer by what the
/// missing modes would have added.
#[test]
fn the_static_correction_makes_the_reduced_static_tip_exact() {
    let full = StructuralModel::build(&scene_with(FidelityLevel::PlaneStress, 10)).unwrap();
    let exact = full.static_tip_deflection(1.0).unwrap();
    for k in [2, 5, 10, 20] {
        let corrected = reduce(&full, k, true).unwrap();
        let truncated = reduce(&full, k, false).unwrap();
        let with = corrected.static_tip_deflection(1.0).unwrap();
        let without = truncated.static_tip_deflection(1.0).unwrap();
        let (e_with, e_without) = ((with - exact) / exact, (without - exact) / exact);
        println!(
            "{k} modes: static tip {exact:.10e} m; corrected {e_with:+.1e}, truncated {e_without:+.1e} relative"
        );
        // Exact in exact arithmetic (K^-1 c is in the basis); the rest is round-off
        // amplified by cond(K) ~7e10, as for the built-in mesh's reduction (2e-7 in
        // tests/physics/statics.rs and mesh_modes.rs, 5e-8 measured there).
        assert!(e_with.abs() < 2e-7, "{k} modes: {e_with:e}");
        // The truncated series misses the higher modes' compliance, a fraction that
        // falls as modes are added but stays ten times the round-off above at 20
        // (measured -4.6e-3 at 2, -4.1e-5 at 10): the correction is what makes it exact.
        assert!(e_without < -2e-6, "{k} modes: {e_without:e}");
    }
}

/// The largest |tip(t) - full tip(t)| (m) over two runs' common samples.
fn largest_deviation(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The 20-mode reduction's frequencies against scipy's: `eigsh(K, 20, M, sigma=0)` on
/// the committed files (scipy 1.17.1; python-checks/tests/test_structures.py recomputes
/// them and checks these constants to 1e-6, the spread of scipy itself on this K between
/// CPUs being 2e-7).
#[test]
fn the_reduced_structure_has_scipys_lowest_frequencies() {
    let eigsh_20 = [
        5.71097354581e+00,
        3.57886855627e+01,
        1.00196778777e+02,
        1.96309712543e+02,
        3.24437202654e+02,
        4.84512385218e+02,
        6.76483421080e+02,
        9.00287140833e+02,
        1.15585084158e+03,
        1.44309244911e+03,
        1.76192080591e+03,
        1.76776654443e+03,
        2.11223598464e+03,
        2.49392962994e+03,
        2.90688532990e+03,
        3.35097901077e+03,
        3.82607935854e+03,
        4.33204826127e+03,
        4.86874127286e+03,
        5.30328983650e+03,
    ];
    let reduced = StructuralModel::build(&scene_with(FidelityLevel::Modal, 20)).unwrap();
    let values = reduced.stiffness.diagonal();
    let mut worst: f64 = 0.0;
    for (w2, f) in values.iter().zip(eigsh_20) {
        let ours = w2.sqrt() / (2.0 * std::f64::consts::PI);
        worst = worst.max(((ours - f) / f).abs());
    }
    println!("20 modes against scipy's eigsh: largest relative difference {worst:.1e}");
    // Independent solvers on this K (condition ~7e10) spread by about 1e-6 on f1
    // (docs/structures.md: scipy's dense eigh against its eigsh); the same 1e-6 as
    // calculix_beam.rs's `the_read_structure_has_scipys_frequencies`.
    assert!(worst < 1e-6, "{worst:e}");
}

/// The paper scene on the CalculiX beam with k = 2, 5, 10, 20 modes against the full
/// model at the same step (1e-4 s, generalised-alpha, 1.2 s): the largest tip deviation
/// over the run falls as modes are added. Wall times are printed, not asserted.
#[test]
fn more_modes_bring_the_run_closer_to_the_full_model() {
    let full_scene = scene_with(FidelityLevel::PlaneStress, 10);
    let law = LawSource::resolve(&full_scene).unwrap();
    let full = run_scene(full_scene, &law, 1).unwrap();
    let full_tip: Vec<f64> = full.samples.iter().map(|s| s.tip_deflection).collect();
    println!(
        "full: {} DOFs, {:.3} s, {} samples",
        full.dofs,
        full.seconds,
        full_tip.len()
    );
    let mut deviations = Vec::new();
    for k in [2, 5, 10, 20] {
        let started = Instant::now();
        let run = run_scene(scene_with(FidelityLevel::Modal, k), &law, 1).unwrap();
        let wall = started.elapsed().as_secs_f64();
        let tip: Vec<f64> = run.samples.iter().map(|s| s.tip_deflection).collect();
        assert_eq!(tip.len(), full_tip.len());
        let d = largest_deviation(&tip, &full_tip);
        println!(
            "{k} modes: {} DOFs, {wall:.3} s (reduction included), largest tip deviation {d:.3e} m",
            run.dofs
        );
        deviations.push(d);
    }
    // Falling: each count's deviation at most half the previous one's. Measured:
    // 3.96e-4 m (2 modes), 2.72e-6 (5), 2.10e-8 (10), 7.4e-9 (20): two orders of
    // magnitude per step while the slip's dynamics are being resolved, then a ratio of
    // 0.35 where what is left is the truncated modes' dynamics at this step (the static
    // correction carries their statics). 0.5 fails a count that gains nothing.
    for pair in deviations.windows(2) {
        assert!(pair[1] < 0.5 * pair[0], "{deviations:?}");
    }
}
