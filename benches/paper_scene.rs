//! Wall time of the paper scene (1.2 s, dt = 1e-4 s, analytical friction) at each
//! fidelity level, as a real-time factor, and the banded solver against a dense
//! Cholesky on the same effective matrix, measured in the same run.
//!
//! Run: `cargo bench --bench paper_scene`.

use std::time::Instant;
use stickslip::run::run_scene;
use stickslip::scene::{FidelityLevel, Scene};
use stickslip::structure::StructuralModel;

fn best_of<T>(repeats: usize, mut f: impl FnMut() -> T) -> f64 {
    (0..repeats)
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(f());
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    println!("paper scene, 12 000 steps of 1e-4 s (best of 3 runs)");
    println!(
        "{:<58} {:>10} {:>12} {:>14}",
        "model", "dofs", "wall (s)", "x real time"
    );
    let cases: [(FidelityLevel, usize, f64); 6] = [
        (FidelityLevel::Modal, 100, 0.02),
        (FidelityLevel::Beam, 20, 0.02),
        (FidelityLevel::Beam, 100, 0.02),
        (FidelityLevel::PlaneStress, 100, 0.04),
        (FidelityLevel::PlaneStress, 100, 0.02),
        (FidelityLevel::PlaneStress, 100, 0.01),
    ];
    for (level, elements, size) in cases {
        let mut scene = Scene::default();
        scene.fidelity.level = level;
        scene.fidelity.beam_elements = elements;
        scene.fidelity.element_size = size;
        let checked = scene.check().unwrap();
        let model = StructuralModel::build(&checked).unwrap();
        let seconds = best_of(3, || run_scene(checked.clone(), 1).unwrap());
        println!(
            "{:<58} {:>10} {:>12.4} {:>14.1}",
            model.label,
            model.dofs(),
            seconds,
            checked.time.end / seconds
        );
    }

    // Solver choice: factorisation and one solve, banded against dense (nalgebra), on the
    // plane-stress effective matrix at the paper's mesh.
    let checked = Scene::default().check().unwrap();
    let model = StructuralModel::plane_stress(&checked, 0.02);
    let n = model.dofs();
    let s = model
        .mass
        .linear_combination(1.0 / (0.25 * 1e-8), &model.stiffness, 1.0);
    let rhs: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
    let banded_factor = best_of(5, || s.cholesky().unwrap());
    let factor = s.cholesky().unwrap();
    let banded_solve = best_of(5, || {
        let mut x = rhs.clone();
        factor.solve_in_place(&mut x);
        x
    });
    let dense = nalgebra::DMatrix::from_fn(n, n, |i, j| s.get(i, j));
    let dense_factor = best_of(3, || dense.clone().cholesky().unwrap());
    let dense_chol = dense.clone().cholesky().unwrap();
    let b = nalgebra::DVector::from_vec(rhs.clone());
    let dense_solve = best_of(5, || dense_chol.solve(&b));
    println!();
    println!(
        "solver on the plane-stress effective matrix ({n} dofs, half-bandwidth {})",
        s.half_bandwidth()
    );
    println!(
        "  factorisation: banded {:.3e} s, dense {:.3e} s, dense / banded = {:.0}",
        banded_factor,
        dense_factor,
        dense_factor / banded_factor
    );
    println!(
        "  solve:         banded {:.3e} s, dense {:.3e} s, dense / banded = {:.0}",
        banded_solve,
        dense_solve,
        dense_solve / banded_solve
    );
}
