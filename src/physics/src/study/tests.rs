//! The study's own unit tests: the front, the full grid, the RMS; and the law axis.

use super::*;
use crate::metrics::Summary;
use crate::scene::{Scene, Scheme};

fn row(seconds: f64, rms: f64) -> Row {
    Row {
        law: "exponential".parse().unwrap(),
        measured: Measured {
            configuration: Configuration {
                resolution: Resolution::Beam { elements: 1 },
                dt: 1e-3,
                scheme: Scheme::GeneralizedAlpha,
                inference: None,
            },
            dofs: 2,
            seconds,
            summary: Summary::new(&[], &[]),
            tip: vec![],
        },
        errors: Errors {
            rms,
            ..Errors::default()
        },
        on_front: false,
    }
}

#[test]
fn the_front_keeps_exactly_the_undominated_points() {
    // (time, error): (1, 9) (2, 5) (3, 6) dominated by (2, 5), (4, 1), (5, 1)
    // dominated by (4, 1), and a NaN error never on the front.
    let mut rows: Vec<Row> = [(1.0, 9.0), (2.0, 5.0), (3.0, 6.0), (4.0, 1.0), (5.0, 1.0)]
        .iter()
        .map(|&(t, e)| row(t, e))
        .chain([row(0.5, f64::NAN)])
        .collect();
    mark_pareto_front(&mut rows);
    let marks: Vec<bool> = rows.iter().map(|r| r.on_front).collect();
    assert_eq!(marks, [true, true, false, true, false, false]);
    let errors: Vec<f64> = front(&rows).iter().map(|r| r.errors.rms).collect();
    assert_eq!(errors, [9.0, 5.0, 1.0]);
}

#[test]
fn the_full_grid_is_the_issues_grid_and_its_reference_is_the_finest_run() {
    let grid = Grid::full();
    assert_eq!(grid.configurations().len(), (6 + 6 + 5 + 5) * 7 * 2);
    let finest = grid.finest().unwrap();
    assert_eq!(
        finest.resolution,
        Resolution::PlaneStress {
            element_size: 0.005
        }
    );
    assert_eq!(finest.dt, 1e-5);
    // Every time step divides the comparison grid.
    for dt in grid.time_steps {
        let every = COMPARISON_INTERVAL / dt;
        assert!((every - every.round()).abs() < 1e-9, "{dt}");
    }
}

#[test]
fn rms_difference_of_a_constant_offset_is_the_offset() {
    let a = [1.0, 2.0, 3.0];
    let b = [1.5, 2.5, 3.5];
    assert!((rms_difference(&a, &b) - 0.5).abs() < 1e-15);
}

/// A row of another law is never compared with this law's rows: a slow, inaccurate
/// LuGre run stays on LuGre's front though an exponential run beats it in both.
#[test]
fn each_law_has_its_own_front() {
    let mut rows = vec![row(1.0, 1.0), row(2.0, 2.0)];
    rows[1].law = "lugre".parse().unwrap();
    mark_pareto_front(&mut rows);
    assert!(rows.iter().all(|r| r.on_front));
    let lugre: Law = "lugre".parse().unwrap();
    let front = front_of(&rows, &lugre);
    assert_eq!(front.len(), 1);
    assert_eq!(front[0].errors.rms, 2.0);
    assert_eq!(front_points(&front)[0].seconds, 2.0);
}

/// The 2-law grid of the paper scene cut to 0.45 s (loading, breakaway at 0.40 s and
/// the first slip), modal 3 modes at two steps: each law gets its own reference (the
/// finest configuration), every row is compared with it, and that comparison is far
/// tighter than one across laws would be.
#[test]
fn every_law_is_compared_with_its_own_reference() {
    let mut scene = Scene::default();
    scene.time.end = 0.45;
    let laws: Vec<Law> = ["exponential", "lugre"]
        .iter()
        .map(|l| l.parse().unwrap())
        .collect();
    let grid = Grid {
        modes: vec![3],
        beam_elements: vec![],
        element_sizes: vec![],
        plane_stress_modal: vec![],
        time_steps: vec![1e-4, 5e-5],
        schemes: vec![Scheme::GeneralizedAlpha],
        inferences: vec![],
        laws: laws.clone(),
    };
    let per_law = grid.configurations().len();
    assert_eq!(per_law, 2);
    let total: usize = laws.iter().map(|l| grid.configurations_for(l).len()).sum();
    assert_eq!(total, laws.len() * per_law);
    let mut announced = 0;
    let study = run(&scene, &grid, |p| {
        announced += matches!(p, Progress::Reference(_)) as usize
    })
    .unwrap();
    assert_eq!(announced, 2);
    assert_eq!(study.references.len(), 2);
    // The references are left out of the rows: one row per law remains (dt = 1e-4 s).
    assert_eq!(study.rows.len(), 2);
    assert!(study.failures.is_empty());
    for (law, other) in [(&laws[0], &laws[1]), (&laws[1], &laws[0])] {
        let reference = study.reference(law).unwrap();
        assert_eq!(Some(reference.measured.configuration), grid.finest_for(law));
        assert_eq!(reference.measured.configuration.dt, 5e-5);
        assert_eq!(
            Errors::between(&reference.measured, &reference.measured).rms,
            0.0
        );
        let row = study.rows.iter().find(|r| r.law == *law).unwrap();
        assert_eq!(row.measured.configuration.dt, 1e-4);
        let own = rms_difference(&row.measured.tip, &reference.measured.tip);
        assert_eq!(row.errors.rms.to_bits(), own.to_bits());
        let across = rms_difference(
            &row.measured.tip,
            &study.reference(other).unwrap().measured.tip,
        );
        // Measured: halving the step moves the tip by 0.35 nm RMS (exponential) and 50 nm
        // (LuGre, whose bristle state the step resolves), the law by 12.5 um (LuGre's
        // presliding and slip onset): ratios 36000 and 250. A factor of 50 leaves 5x
        // margin on the smaller one and still tells a cross-law comparison apart.
        assert!(
            across > 50.0 * own,
            "{law}: within {own:e} m, across {across:e} m"
        );
    }
}

#[test]
fn the_external_law_is_refused_with_the_reason() {
    let mut scene = Scene::default();
    scene.friction.law = crate::friction::FrictionLawKind::External;
    let mut grid = Grid::full();
    grid.modes = vec![1];
    grid.beam_elements.clear();
    grid.element_sizes.clear();
    grid.plane_stress_modal.clear();
    grid.time_steps = vec![1e-3];
    let Err(error) = run(&scene, &grid, |_| {}) else {
        panic!("an external scene law ran");
    };
    assert!(
        matches!(error, StudyError::Law(LawError::External(_))),
        "{error}"
    );
    assert!(error.to_string().contains("inputs"), "{error}");
}
