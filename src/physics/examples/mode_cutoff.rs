//! Measures how many modes a scene needs: the modal truncation error against the full
//! model the modes come from (same time step, same integrator), on the verification
//! scenes whose frequencies differ from the paper's. It is the measurement behind
//! `stickslip::transfer` (which rule carries a mode count from the paper scene to
//! another): run with `cargo run --release -p stickslip --example mode_cutoff`.
//!
//! The error is the largest tip deviation over the first stick-slip cycle
//! (`auto::first_cycle_deviation`), absolute (um) and relative to the scene's
//! Euler-Bernoulli quasi-static breakaway deflection mu_s F_n / k (the sawtooth's scale).

use std::time::Instant;
use stickslip::auto::{first_cycle_deviation, paper_front, verification_scenes};
use stickslip::law_source::LawSource;
use stickslip::modal::modes_of;
use stickslip::scene::Scheme;
use stickslip::stability::cantilever_omega;
use stickslip::structure::StructuralModel;
use stickslip::study::{measure, Configuration, Resolution};
use stickslip::transfer::front_for_scene;

fn main() {
    // What `transfer` makes of the shipped front on each verification scene, and what
    // the mapping costs (first call: the spectra; second: the cache).
    let front = paper_front().expect("the shipped front");
    for (name, scene) in verification_scenes() {
        let started = Instant::now();
        let mapped = front_for_scene(&scene, &front);
        let first = started.elapsed().as_secs_f64();
        let started = Instant::now();
        front_for_scene(&scene, &front);
        let again = started.elapsed().as_secs_f64();
        let changes: Vec<String> = front
            .iter()
            .zip(&mapped)
            .filter(|(a, b)| a.configuration != b.configuration)
            .map(|(a, b)| {
                format!(
                    "{} -> {}",
                    a.configuration.resolution, b.configuration.resolution
                )
            })
            .collect();
        println!(
            "{name}: mapping {:.1} ms (again {:.2} ms); {}",
            first * 1e3,
            again * 1e3,
            if changes.is_empty() {
                "every point kept".to_string()
            } else {
                changes.join("; ")
            }
        );
    }
    let modes = [2, 3, 4, 5, 6, 7, 8, 10, 12, 15, 20];
    let scheme = Scheme::GeneralizedAlpha;
    let at = |resolution, dt| Configuration {
        resolution,
        dt,
        scheme,
        inference: None,
    };
    for (name, scene) in verification_scenes() {
        if !["paper", "beam 1.5 m", "beam 2.5 m", "aluminium", "stubby"]
            .iter()
            .any(|w| name.starts_with(w))
        {
            continue;
        }
        let checked = scene
            .clone()
            .check()
            .expect("verification scenes are valid");
        let f1 = cantilever_omega(&checked, 1).unwrap() / (2.0 * std::f64::consts::PI);
        let scale = checked.friction.static_coefficient * checked.loading.normal_force
            / checked.euler_bernoulli_tip_stiffness();
        let stubby = name.starts_with("stubby");
        let (full, reduced): (Resolution, Box<dyn Fn(usize) -> Resolution>) = if stubby {
            (
                Resolution::PlaneStress {
                    element_size: 0.005,
                },
                Box::new(|modes| Resolution::PlaneStressModal {
                    element_size: 0.005,
                    modes,
                }),
            )
        } else {
            (
                Resolution::Beam { elements: 100 },
                Box::new(|modes| Resolution::Modal { modes }),
            )
        };
        // The stubby beam's modes reach 3 kHz: 1e-4 s does not resolve them, so it is
        // measured at 2e-5 s too.
        let steps: &[f64] = if stubby { &[1e-4, 2e-5] } else { &[1e-4] };
        let law = LawSource::resolve(&checked).expect("the scene's law");
        for &dt in steps {
            let reference = measure(&scene, &law, at(full, dt)).expect("full model runs");
            let model = if stubby {
                StructuralModel::plane_stress(&checked, 0.005)
            } else {
                StructuralModel::beam(&checked, 100)
            };
            let highest = *modes.iter().max().unwrap();
            let hz: Vec<f64> = modes_of(&model, highest)
                .expect("modes")
                .eigenvalues
                .iter()
                .map(|w2| w2.sqrt() / (2.0 * std::f64::consts::PI))
                .collect();
            println!(
            "{name}: f1 = {f1:.2} Hz, breakaway deflection {:.3} mm, against {full} at dt {dt:e} s",
            scale * 1e3
        );
            for &n in &modes {
                let run = measure(&scene, &law, at(reduced(n), dt)).expect("modal model runs");
                let e = first_cycle_deviation(&run.tip, &reference);
                println!(
                "  {n:>2} modes (f_n {:>8.1} Hz, omega_n dt {:.3}): {:>9.3} um, {:.2e} of the breakaway deflection",
                hz[n - 1],
                2.0 * std::f64::consts::PI * hz[n - 1] * dt,
                e * 1e6,
                e / scale
            );
            }
        }
    }
}
