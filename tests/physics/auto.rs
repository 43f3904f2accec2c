//! `fidelity = auto` end to end on three scenes, with a small front measured here (the
//! shipped front needs the full study; `stickslip study --verify-auto` checks that one).
//!
//! The front: five beam/modal configurations, their largest deviations measured on the
//! paper scene to 0.6 s (breakaway and the first slip) against a 100-element beam at
//! dt = 1e-5 s. Since issue 27 the tolerance bounds the whole run (here 0.6 s), so the
//! errors are the largest over the whole run, no longer over the first cycle.
//! On each scene the tolerance is put halfway (geometrically) between the true errors
//! of two consecutive front points k-1 and k that differ by at least 3x: auto must
//! choose the first point that meets it, or (where the front is not monotone on the
//! scene over the whole run) the next.

use stickslip::auto::{check_front, choose, window_deviation};
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
    measure(scene, &stickslip_tests::law_of(scene), finest).unwrap()
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
            let run = measure(&paper, &stickslip_tests::law_of(&paper), c).unwrap();
            FrontPoint {
                configuration: c,
                seconds: run.dofs as f64 / c.dt,
                rms_error: window_deviation(&run.tip, &paper_reference.tip),
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
                let run =
                    measure(&scene, &stickslip_tests::law_of(&scene), p.configuration).unwrap();
                window_deviation(&run.tip, &reference.tip)
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
        let choice = choose(
            &scene,
            &stickslip_tests::law_of(&scene),
            tolerance,
            &front,
            &mut |_| {},
        )
        .unwrap();
        println!(
            "{name}: errors {errors:?} m, tolerance {tolerance:.3e} m, chose point {} (estimated {:.3e} m)",
            choice.index, choice.estimated_error
        );
        // Over the whole run the front need not be monotone on another scene: on the
        // 1.6 m beam the 10-element beam at 5e-5 s is 63 um off over 0.6 s while the
        // cheaper 5 modes at 1e-4 s are 6.6 um off (a slip a step late), and as the
        // partner of the 2e-4 s beam it makes auto cautious by one point. More than one
        // would be a fault.
        assert!(
            choice.index >= first_meeting && choice.index <= first_meeting + 1,
            "{name}: chose {}, errors {errors:?}",
            choice.index
        );
        assert!(errors[choice.index] <= tolerance, "{name}");
        checked += 1;
    }
    assert_eq!(checked, 3);
}

/// The calibration window (for an open or long horizon) stops at 1.5x the pilot's third
/// major-slip onset, whatever the scene's end: a scene that runs for 100 s calibrates
/// over the same window as one that runs for 20 s, and a scene shorter than that over
/// its whole run. (Until issue 27 the window ended at 1.5x the second onset; it now
/// holds two intervals between slips, from which the phase drift is measured.)
#[test]
fn the_calibration_window_follows_the_first_slips_not_the_end_time() {
    let pilot = configuration(
        Resolution::Modal { modes: 1 },
        1e-3,
        Scheme::GeneralizedAlpha,
    );
    let mut lines = Vec::new();
    let mut horizon_at = |end: f64| {
        let mut scene = Scene::default();
        scene.time.end = end;
        stickslip::auto::calibration_horizon(
            &scene,
            &stickslip_tests::law_of(&scene),
            pilot,
            &mut |l| lines.push(l.to_string()),
        )
        .unwrap()
    };
    let twenty = horizon_at(20.0);
    let long = horizon_at(100.0);
    let short = horizon_at(0.5);
    // The pilot's third onset on the paper scene, over 2 s of run.
    let mut scene = Scene::default();
    scene.time.end = 2.0;
    let run = measure(&scene, &stickslip_tests::law_of(&scene), pilot).unwrap();
    let third = stickslip::auto::drift::distinct_onsets(&run)[2];
    let expected = (1.5 * third / 1e-3).ceil() * 1e-3;
    assert!((twenty - expected).abs() < 1e-12, "{twenty} {expected}");
    assert_eq!(long, twenty);
    assert!(
        twenty < 2.0,
        "three slips fit in the first 2 s of the paper scene: {twenty}"
    );
    assert_eq!(short, 0.5);
    // One progress line per pilot run, each naming its horizon.
    assert!(lines.iter().all(|l| l.contains("the pilot")), "{lines:?}");
}

/// The chain of partners catches a partner that is itself wrong on the scene. On the
/// stubby beam (0.2 m x 0.02 m, E = 40 MPa) the 1-mode model and the 5-element beam, both
/// at dt = 1e-3 s, agree closely with each other and far less with an accurate run: the
/// old estimate, 1.25 x their deviation, fell below the true error. The chain goes on to
/// the partner's partner (5 modes at 1e-4 s), finds that the first partner is not 5x more
/// accurate there, and bounds the error by the deviation from the deepest partner.
#[test]
fn the_chain_bounds_the_error_where_the_first_partner_is_as_wrong() {
    let mut stubby = short(Scene::default());
    stubby.geometry.length = 0.2;
    stubby.geometry.height = 0.02;
    stubby.material.youngs_modulus = 40e6;
    // The run ends at the reference's second major-slip onset: since issue 27 the bound
    // covers the whole run, and this keeps it to the first cycle the test was made for
    // (over 0.6 s the single link is no longer an underestimate here: 4.2e-4 against a
    // true 2.8e-4 m).
    let onsets = stickslip::auto::drift::distinct_onsets(&reference(&stubby));
    stubby.time.end = (onsets[1] / 1e-3).floor() * 1e-3 + 1e-3;
    let coarse = configuration(Resolution::Modal { modes: 1 }, 1e-3, Scheme::MoreauJean);
    let partner = configuration(Resolution::Beam { elements: 5 }, 1e-3, Scheme::MoreauJean);
    let fine = configuration(
        Resolution::Modal { modes: 5 },
        1e-4,
        Scheme::GeneralizedAlpha,
    );
    // Paper-scene errors that make `partner` the partner of `coarse`, and `fine` that of
    // `partner` (each at least 5x smaller); costs rising.
    let front = [
        FrontPoint {
            configuration: coarse,
            seconds: 1e-4,
            rms_error: 2e-4,
        },
        FrontPoint {
            configuration: partner,
            seconds: 2e-4,
            rms_error: 3e-5,
        },
        FrontPoint {
            configuration: fine,
            seconds: 3e-4,
            rms_error: 5e-7,
        },
    ];
    let choice = choose(
        &stubby,
        &stickslip_tests::law_of(&stubby),
        1.0,
        &front,
        &mut |_| {},
    )
    .unwrap();
    let tried = &choice.tried[0];
    assert_eq!(tried.configuration, coarse);
    assert_eq!(tried.chain.len(), 2, "{tried:?}");
    let first_link = tried.chain[0].1;
    let truth = {
        let reference = reference(&stubby);
        let run = measure(&stubby, &stickslip_tests::law_of(&stubby), coarse).unwrap();
        window_deviation(&run.tip, &reference.tip)
    };
    println!(
        "stubby: single-link {:.3e} m, chain {:.3e} m, true {truth:.3e} m",
        1.25 * first_link,
        tried.estimated_error
    );
    // The single link would have underestimated; the chain does not.
    assert!(1.25 * first_link < truth, "{first_link} {truth}");
    assert!(tried.estimated_error >= truth, "{tried:?} {truth}");
}

/// The paper authors' contact options (free first slip step, lagged slip force, damping
/// only in slip) belong to generalised-alpha's switch, so the scene's rules refuse every
/// Moreau-Jean point: `auto` chooses among the others (its first calibration run, on a
/// Moreau-Jean point, failed before), and refuses with the scene's reason only when
/// nothing is left.
#[test]
fn auto_leaves_out_the_points_the_scenes_rules_refuse() {
    use stickslip::auto::{for_scene, paper_front};
    use stickslip::law_source::LawSource;
    use stickslip::scene_preset::ScenePreset;
    let mut scene = ScenePreset::PaperAuthors.scene();
    scene.time.end = 0.5;
    let front = paper_front().unwrap();
    let admitted = for_scene(&scene, &front).unwrap();
    assert!(front
        .iter()
        .any(|p| p.configuration.scheme == Scheme::MoreauJean));
    assert!(admitted
        .iter()
        .all(|p| p.configuration.scheme == Scheme::GeneralizedAlpha));
    assert!(admitted.len() >= 2, "{}", admitted.len());
    let law = LawSource::resolve(&scene.clone().check().unwrap()).unwrap();
    let choice = choose(&scene, &law, 1e-5, &front, &mut |_| {}).unwrap();
    assert_eq!(choice.configuration.scheme, Scheme::GeneralizedAlpha);
    assert!(choice.estimated_error <= 1e-5);
    // The default scene keeps the whole front.
    assert_eq!(
        for_scene(&Scene::default(), &front).unwrap().len(),
        front.len()
    );
}
