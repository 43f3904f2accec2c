//! Unit tests of the selection's parts.

use super::*;
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
        let law = LawSource::analytical(&Scene::default().friction).unwrap();
        let e = choose(&Scene::default(), &law, tolerance, &front, &mut |_| {}).unwrap_err();
        assert!(matches!(e, AutoError::Tolerance { .. }), "{e}");
        assert!(e.to_string().contains("tolerance"), "{e}");
    }
    for end in [0.0, -1.0, f64::NAN] {
        let law = LawSource::analytical(&Scene::default().friction).unwrap();
        let horizon = Horizon::Until(end);
        let e =
            choose_over(&Scene::default(), &law, 1e-5, horizon, &front, &mut |_| {}).unwrap_err();
        assert!(matches!(e, AutoError::Horizon { .. }), "{e}");
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
    let horizon = Horizon::Until(scene.time.end);
    let mut lines = Vec::new();
    let choice = |lines: &mut Vec<String>| {
        choose_cached(&scene, &law, horizon, &front, &mut |l| {
            lines.push(l.to_string())
        })
        .unwrap()
    };
    let first = choice(&mut lines);
    let announced = lines.len();
    let second = choice(&mut lines);
    // The first call may find the choice of a parallel test with this scene, but
    // then it too made no run; the second call never runs.
    assert_eq!(announced, first.runs.max(1));
    assert_eq!(second.runs, 0);
    assert_eq!(second.configuration, first.configuration);
    assert!(lines.last().unwrap().contains("already made"), "{lines:?}");
    // Another tolerance is another choice, and so is another horizon.
    let mut other = scene.clone();
    other.fidelity.tolerance = Some(0.4);
    let runs = |scene: &Scene, horizon| {
        choose_cached(scene, &law, horizon, &front, &mut |_| {})
            .unwrap()
            .runs
    };
    assert!(runs(&other, horizon) > 0);
    assert!(runs(&scene, Horizon::Until(0.03)) > 0);
}

#[test]
fn the_drift_rate_is_the_largest_growth_of_the_onset_difference() {
    // Onsets of b at 0.1, 0.3, 0.5 s; a is 1 ms late at the first, 3 ms at the second
    // (2 ms more over 0.2 s: 0.01) and 4 ms at the third (3 ms over 0.4 s: 0.0075).
    let b = measured(vec![0.0; 3], &[0.1, 0.3, 0.5]);
    let a = measured(vec![0.0; 3], &[0.101, 0.303, 0.504]);
    let rate = drift::drift_rate(&a, &b).unwrap();
    assert!((rate - 0.01).abs() < 1e-12, "{rate}");
    // A slip reported twice counts once.
    let twice = measured(vec![0.0; 3], &[0.101, 0.101, 0.303, 0.504]);
    assert_eq!(drift::distinct_onsets(&twice), [0.101, 0.303, 0.504]);
    // No sawtooth in either run: nothing drifts; in one only: not comparable.
    let none = measured(vec![0.0; 3], &[]);
    assert_eq!(drift::drift_rate(&none, &none), Some(0.0));
    assert_eq!(drift::drift_rate(&none, &b), None);
}

#[test]
fn a_shift_costs_the_sawtooths_modulus_of_continuity() {
    // A ramp rising 1 per sample, then a drop of 5: a shift of h samples costs h on the
    // ramp, and any shift reaching the drop up to its height.
    let tip = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 0.0, 1.0];
    let step = crate::study::COMPARISON_INTERVAL;
    // Half a sample into the drop: 2.5, linear between samples.
    assert!((drift::shift_deviation(&tip, 0.5 * step) - 2.5).abs() < 1e-12);
    assert!((drift::shift_deviation(&tip, step) - 5.0).abs() < 1e-12);
    // Nondecreasing, and the peak-to-peak height for a shift beyond the samples.
    let mut last = 0.0;
    for k in 0..40 {
        let d = drift::shift_deviation(&tip, 0.25 * k as f64 * step);
        assert!(d >= last, "{k}");
        last = d;
    }
    assert_eq!(drift::shift_deviation(&tip, f64::INFINITY), 5.0);
    // The largest shift within 1.0 is a fifth of a sample (the drop: 5 per sample).
    let within = drift::shift_within(&tip, 1.0, 10.0 * step);
    assert!((within - 0.2 * step).abs() < 2e-6, "{within}");
}
