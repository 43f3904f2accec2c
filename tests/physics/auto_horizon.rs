//! `fidelity = auto` over the run the user asked for (issue 27), with the shipped front:
//! the bound holds over the whole run against a converged reference, an open horizon
//! reports the phase drift per second, and an unmet tolerance is refused with the best
//! achievable number.

use stickslip::auto::{
    choose, choose_over, describe, paper_front, window_deviation, AutoError, Horizon, Reach,
};
use stickslip::scene::{Scene, Scheme};
use stickslip::study::{measure, Configuration, Resolution};

/// The verification's reference: 40 modes of the 0.005 m mesh at 1e-5 s. Over the
/// 1.2 s of the two scenes below it is 0.013 um (paper) and 0.11 um (2.5 m beam) from
/// its finer run, 80 modes at 5e-6 s (`stickslip study --verify-auto`,
/// docs/speed-accuracy.md): converged far below the 10 um it judges.
fn reference() -> Configuration {
    Configuration {
        resolution: Resolution::PlaneStressModal {
            element_size: 0.005,
            modes: 40,
        },
        dt: 1e-5,
        scheme: Scheme::GeneralizedAlpha,
        inference: None,
    }
}

/// On the paper scene and the 2.5 m beam, to 1.2 s (three and two slips: the later
/// slips' drift is inside the run, where the first-cycle bound of issue 24 let the
/// deviation reach 2 to 80 times the tolerance), the choice at 10 um meets 10 um over
/// the whole run against the reference, and its estimate is not below its true error:
/// the bound is measured over the whole run, so no allowance is needed beyond the
/// reference's 0.1 um.
#[test]
fn the_bound_holds_over_the_whole_run() {
    let front = paper_front().unwrap();
    let tolerance = 1e-5;
    let mut long_beam = Scene::default();
    long_beam.geometry.length = 2.5;
    for scene in [Scene::default(), long_beam] {
        let law = stickslip_tests::law_of(&scene);
        let choice = choose(&scene, &law, tolerance, &front, &mut |_| {}).unwrap();
        assert_eq!(choice.reach, Reach::Whole);
        assert_eq!(choice.window, scene.time.end);
        let truth = |configuration| {
            let run = measure(&scene, &law, configuration).unwrap();
            let reference = measure(&scene, &law, reference()).unwrap();
            window_deviation(&run.tip, &reference.tip)
        };
        let true_error = truth(choice.configuration);
        println!(
            "{} m: {} estimated {:.3e}, true {true_error:.3e}",
            scene.geometry.length, choice.configuration, choice.estimated_error
        );
        assert!(true_error <= tolerance, "{true_error} {choice:?}");
        assert!(
            true_error <= choice.estimated_error + 1e-7,
            "{true_error} {choice:?}"
        );
        assert!(describe(&choice, tolerance).contains("over the whole run, 0 to 1.200 s"));
    }
}

/// An open horizon (an FMU without a stop time) and a run longer than the direct limit
/// bound the calibration window of the first three slips and report the drift per
/// second of simulated time.
#[test]
fn an_open_or_long_horizon_bounds_the_window_and_reports_the_drift() {
    let front = paper_front().unwrap();
    let scene = Scene::default();
    let law = stickslip_tests::law_of(&scene);
    for (horizon, words) in [
        (Horizon::Open, "the horizon is open"),
        (Horizon::Until(100.0), "the run's 100 s is beyond"),
    ] {
        let choice = choose_over(&scene, &law, 1e-4, horizon, &front, &mut |_| {}).unwrap();
        assert!(matches!(choice.reach, Reach::Window { .. }), "{choice:?}");
        // The window holds three slips (the paper scene's third is at 0.94 s) with margin.
        assert!(
            choice.window > 0.94 && choice.window < 2.0,
            "{}",
            choice.window
        );
        let rate = choice.drift_rate.expect("the runs' slips match");
        assert!(rate.is_finite() && rate >= 0.0, "{rate}");
        let text = describe(&choice, 1e-4);
        println!("{text}");
        assert!(text.contains(words), "{text}");
        assert!(text.contains("ms per s of simulated time"), "{text}");
    }
}

/// A tolerance that no point meets is refused with the best estimate, and that number
/// is achievable: asked for it, auto chooses.
#[test]
fn an_unmet_tolerance_is_refused_with_the_best_achievable_number() {
    let front = paper_front().unwrap();
    let mut scene = Scene::default();
    scene.time.end = 0.6;
    let law = stickslip_tests::law_of(&scene);
    // 1e-11 m: below what the front's finest pair resolves (their runs differ by
    // 6e-10 m over 0.6 s on the paper scene).
    let error = choose(&scene, &law, 1e-11, &front, &mut |_| {}).unwrap_err();
    let AutoError::Unmet {
        best,
        ref over,
        ref among,
        ..
    } = error
    else {
        panic!("{error}");
    };
    assert!(best.is_finite() && best > 1e-11, "{best}");
    // The paper front is the shipped one of the exponential law: the message names its file.
    assert_eq!(among, "of the front data/pareto_front.json");
    assert!(over.contains("the whole run, 0 to 0.600 s"), "{over}");
    assert!(
        error.to_string().contains(&format!("{best:.3e}")),
        "{error}"
    );
    let choice = choose(&scene, &law, best * 1.000001, &front, &mut |_| {}).unwrap();
    assert!(choice.estimated_error <= best * 1.000001);
}
