//! Unit tests of the selection's parts.

use super::*;
use crate::friction::ExponentialLaw;
use crate::law_source::LawSource;
use crate::scene::{FidelityLevel, Scene, Scheme};
use crate::study::Resolution;
use crate::study::{Configuration, Measured};

fn point(elements: usize, seconds: f64, rms_error: f64) -> FrontPoint {
    FrontPoint {
        configuration: Configuration {
            resolution: Resolution::Beam { elements },
            dt: 1e-3,
            scheme: Scheme::GeneralizedAlpha,
            inference: None,
        },
        seconds,
        rms_error,
    }
}

#[test]
fn the_partner_is_the_first_point_five_times_more_accurate() {
    assert_eq!(PARTNER_ACCURACY_RATIO, 5.0);
    let front = [
        point(1, 1.0, 1.0),
        point(2, 2.0, 0.5),
        point(3, 3.0, 0.3),
        point(4, 4.0, 0.1),
        point(5, 5.0, 0.08),
    ];
    // 1.0 / 5 = 0.2: the first point at or below is the fourth.
    assert_eq!(partner(&front, 0), Some(3));
    assert_eq!(partner(&front, 1), Some(3));
    // None is five times better than 0.3: the last point.
    assert_eq!(partner(&front, 2), Some(4));
    assert_eq!(partner(&front, 4), None);
}

#[test]
fn the_refinement_is_the_first_plane_stress_point_five_times_more_accurate() {
    let plane_stress = |seconds: f64, rms_error: f64| FrontPoint {
        configuration: Configuration {
            resolution: Resolution::PlaneStress { element_size: 0.02 },
            ..point(1, seconds, rms_error).configuration
        },
        seconds,
        rms_error,
    };
    let front = [
        point(1, 1.0, 1.0),
        point(2, 2.0, 0.1),
        plane_stress(3.0, 0.3),
        plane_stress(4.0, 0.15),
        plane_stress(5.0, 0.05),
    ];
    // The beam at 0.1 is 5x better than 1.0 but is no refinement; 0.15 is the
    // first plane-stress point at or below 0.2.
    assert_eq!(refinement(&front, 0), Some(3));
    assert_eq!(refinement(&front, 1), None);
    assert_eq!(refinement(&front, 2), Some(4));
}

#[test]
fn an_unordered_front_or_a_bad_tolerance_is_refused() {
    let unordered = [point(1, 1.0, 1.0), point(2, 2.0, 2.0)];
    let e = check_front(&unordered).unwrap_err();
    assert!(matches!(e, AutoError::FrontUnordered { .. }), "{e}");
    assert!(e.to_string().contains("not ordered"), "{e}");
    assert!(matches!(
        check_front(&unordered[..1]),
        Err(AutoError::FrontTooShort)
    ));
    let front = [point(1, 1.0, 1.0), point(2, 2.0, 0.5)];
    for tolerance in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let law = LawSource::Exponential(ExponentialLaw::of(&Scene::default().friction));
        let e = choose(&Scene::default(), &law, tolerance, &front, &mut |_| {}).unwrap_err();
        assert!(matches!(e, AutoError::Tolerance { .. }), "{e}");
        assert!(e.to_string().contains("tolerance"), "{e}");
    }
}

#[test]
fn the_shipped_front_is_ordered_and_reachable() {
    let front = paper_front().unwrap();
    assert!(front.len() >= 3);
    for p in &front {
        assert!(Configuration::apply(&p.configuration, &Scene::default())
            .check()
            .is_ok());
    }
}

fn measured(tip: Vec<f64>, onsets: &[f64]) -> Measured {
    let mut summary = crate::metrics::Summary::new(&[], &[]);
    summary.major_slips = onsets
        .iter()
        .map(|&onset| crate::metrics::MajorSlip {
            onset,
            duration: None,
        })
        .collect();
    Measured {
        configuration: point(1, 1.0, 1.0).configuration,
        dofs: 2,
        seconds: 0.0,
        summary,
        tip,
    }
}

#[test]
fn the_deviation_stops_at_the_second_major_slip_of_the_reference() {
    // Samples every 1 ms; the second slip starts at 2.5 ms, so samples 0, 1, 2
    // count and the large difference at 3 ms does not.
    let reference = measured(vec![0.0; 5], &[0.0005, 0.0025]);
    let tip = [0.0, 2e-6, -3e-6, 1.0, 1.0];
    assert_eq!(first_cycle_deviation(&tip, &reference), 3e-6);
    // With fewer than two major slips the whole run counts.
    let single = measured(vec![0.0; 5], &[0.0005]);
    assert_eq!(first_cycle_deviation(&tip, &single), 1.0);
    // A slip reported twice with the same onset is one slip: the window runs to the
    // next later onset (3.5 ms: samples 0 to 3), not to the first.
    let twice = measured(vec![0.0; 5], &[0.0005, 0.0005, 0.0035]);
    assert_eq!(first_cycle_deviation(&tip, &twice), 1.0);
    let twice_only = measured(vec![0.0; 5], &[0.0005, 0.0005]);
    assert_eq!(first_cycle_deviation(&tip, &twice_only), 1.0);
}

#[test]
fn a_second_choice_for_the_same_scene_and_tolerance_comes_from_the_cache() {
    let mut scene = Scene::default();
    scene.time.end = 0.02;
    scene.fidelity.level = FidelityLevel::Auto;
    // A tolerance so loose that the cheapest point meets it.
    scene.fidelity.tolerance = Some(0.5);
    let front = paper_front().unwrap();
    let law = LawSource::resolve(&scene.clone().check().unwrap()).unwrap();
    let mut lines = Vec::new();
    let first = choose_cached(
        &scene,
        &law,
        Horizon::Until(scene.time.end),
        &front,
        &mut |l| lines.push(l.to_string()),
    )
    .unwrap();
    let announced = lines.len();
    let second = choose_cached(
        &scene,
        &law,
        Horizon::Until(scene.time.end),
        &front,
        &mut |l| lines.push(l.to_string()),
    )
    .unwrap();
    // The first call may find the choice of a parallel test with this scene, but
    // then it too made no run; the second call never runs.
    assert_eq!(announced, first.runs.max(1));
    assert_eq!(second.runs, 0);
    assert_eq!(second.configuration, first.configuration);
    assert!(lines.last().unwrap().contains("already made"), "{lines:?}");
    // Another tolerance is another choice.
    scene.fidelity.tolerance = Some(0.4);
    assert!(
        choose_cached(
            &scene,
            &law,
            Horizon::Until(scene.time.end),
            &front,
            &mut |_| {}
        )
        .unwrap()
        .runs
            > 0
    );
}
