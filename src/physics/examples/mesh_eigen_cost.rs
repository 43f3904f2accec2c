//! The cost of the plane-stress mesh's lowest modes: shift-invert Lanczos
//! (`modal::lanczos_modes`, the mesh's solver) against subspace iteration
//! (`modal::lowest_modes`, the beam's), timed one after the other in the same run, best
//! of three. `cargo run --release -p stickslip --example mesh_eigen_cost`.

use std::time::Instant;
use stickslip::modal::{lanczos_modes, lowest_modes, Modes};
use stickslip::scene::CheckedScene;
use stickslip::structure::{ModelError, StructuralModel};

fn best_of_three(
    solve: &dyn Fn() -> Result<Modes, ModelError>,
) -> Result<(f64, Modes), ModelError> {
    let mut best = f64::INFINITY;
    let mut modes = None;
    for _ in 0..3 {
        let started = Instant::now();
        let m = solve()?;
        best = best.min(started.elapsed().as_secs_f64());
        modes = Some(m);
    }
    Ok((best, modes.expect("three runs")))
}

fn main() {
    let scene = CheckedScene::paper();
    println!("| mesh | dofs | modes | Lanczos (ms) | subspace iteration (ms) | ratio | largest omega^2 difference |");
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for size in [0.02, 0.01, 0.005] {
        let model = StructuralModel::plane_stress(&scene, size);
        for modes in [5, 10, 20, 40] {
            let (lanczos, a) =
                best_of_three(&|| lanczos_modes(&model, modes)).expect("Lanczos converges");
            // Subspace iteration takes seconds beyond 20 modes of the finest mesh.
            let (subspace, difference) = if modes > 20 {
                ("-".into(), "- | -".into())
            } else {
                match best_of_three(&|| lowest_modes(&model, modes)) {
                    Ok((t, b)) => {
                        let d = a
                            .eigenvalues
                            .iter()
                            .zip(&b.eigenvalues)
                            .map(|(x, y)| (x - y).abs() / y)
                            .fold(0.0, f64::max);
                        (
                            format!("{:.1}", t * 1e3),
                            format!("{:.0}x | {d:.1e}", t / lanczos),
                        )
                    }
                    Err(e) => (format!("fails: {e}"), "- | -".into()),
                }
            };
            println!(
                "| {size} m | {} | {modes} | {:.1} | {subspace} | {difference} |",
                model.dofs(),
                lanczos * 1e3
            );
        }
    }
}
