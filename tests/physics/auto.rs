//! `fidelity = auto` end to end on three scenes, with a small front measured here (the
//! shipped front needs the full study; `stickslip study --verify-auto` checks that one).
//!
//! The front: five beam/modal configurations, their first-cycle deviations measured on the paper scene
//! to 0.6 s (breakaway and the first slip) against a 100-element beam at dt = 1e-5 s.
//! On each scene the tolerance is put halfway (geometrically) between the true errors
//! of two consecutive front points k-1 and k that differ by at least 3x: auto must
//! choose exactly k, which meets the tolerance while k-1 does not.

use stickslip::auto::{check_front, choose, first_cycle_deviation};
use stickslip::scene::{Scene, Scheme};
use stickslip::study::{measure, Configuration, FrontPoint, Measured, Resolution};

fn configuration(resolution: Resolution, dt: f64, scheme: Scheme) -> Configuration {
    Configuration {
        resolution,
        dt,
        scheme,
        inference: None,
    }
}

fn candidates() -> Vec<Configuration> {
    vec![
        configuration(Resolution::Modal { modes: 1 }, 1e-3, Scheme::MoreauJean),
        configuration(Resolution::Beam { elements: 5 }, 2e-4, Scheme::MoreauJean),
        configuration(Resolution::Modal { modes: 5 }, 1e-4, Scheme::MoreauJean),
        configuration(
            Resolution::Beam { elements: 10 },
            5e-5,
            Scheme::GeneralizedAlpha,
        ),
        configuration(
            Resolution::Beam { elements: 20 },
            2e-5,
            Scheme::GeneralizedAlpha,
        ),
    ]
}

fn reference(scene: &Scene) -> Measured {
    let finest = configuration(
        Resolution::Beam { elements: 100 },
        1e-5,
        Scheme::GeneralizedAlpha,
    );
    measure(scene, finest).unwrap()
}

fn short(mut scene: Scene) -> Scene {
    scene.time.end = 0.6;
    scene
}

#[test]
fn auto_chooses_the_cheapest_point_that_meets_the_tolerance_on_three_scenes() {
    let paper = short(Scene::default());
    let paper_reference = reference(&paper);
    // The front in cost order, as the study builds it; cost here is steps x dofs,
    // which orders these runs as their wall time does without timing noise.
    let mut front: Vec<FrontPoint> = candidates()
        .into_iter()
        .map(|c| {
            let run = measure(&paper, c).unwrap();
            FrontPoint {
                configuration: c,
                seconds: run.dofs as f64 / c.dt,
                rms_error: first_cycle_deviation(&run.tip, &paper_reference),
            }
        })
        .collect();
    front.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
    check_front(&front).expect("the candidates form a front on the paper scene");

    let mut fast_belt = paper.clone();
    fast_belt.loading.belt_speed = 0.04;
    let mut short_beam = paper.clone();
    short_beam.geometry.length = 1.6;
    let mut checked = 0;
    for (name, scene) in [
        ("paper", paper),
        ("belt 0.04 m/s", fast_belt),
        ("beam 1.6 m", short_beam),
    ] {
        let reference = reference(&scene);
        let errors: Vec<f64> = front
            .iter()
            .map(|p| {
                let run = measure(&scene, p.configuration).unwrap();
                first_cycle_deviation(&run.tip, &reference)
            })
            .collect();
        // The widest gap among points that have a partner; the tolerance sits inside.
        let k = (1..front.len() - 1)
            .filter(|&k| errors[k - 1] >= 3.0 * errors[k])
            .max_by(|&a, &b| (errors[a - 1] / errors[a]).total_cmp(&(errors[b - 1] / errors[b])))
            .unwrap_or_else(|| panic!("{name}: no gap of 3x between front points: {errors:?}"));
        // Auto may stop earlier only if an earlier point also meets the tolerance.
        let tolerance = (errors[k - 1] * errors[k]).sqrt();
        let first_meeting = errors.iter().position(|&e| e <= tolerance).unwrap();
        let choice = choose(&scene, tolerance, &front, &mut |_| {}).unwrap();
        println!(
            "{name}: errors {errors:?} m, tolerance {tolerance:.3e} m, chose point {} (estimated {:.3e} m)",
            choice.index, choice.estimated_error
        );
        assert_eq!(choice.index, first_meeting, "{name}: errors {errors:?}");
        assert!(errors[choice.index] <= tolerance, "{name}");
        if choice.index > 0 {
            assert!(errors[choice.index - 1] > tolerance, "{name}");
        }
        checked += 1;
    }
    assert_eq!(checked, 3);
}
