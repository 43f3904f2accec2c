//! The slip solve (`stickslip::contact`): Newton with the law's exact slope against the
//! fixed-point iteration of earlier versions over the paper scene, and the law
//! evaluations each takes per slip step.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use stickslip::contact::{SlipSolver, SLIP_TOLERANCE};
use stickslip::friction::FrictionLaw;
use stickslip::friction::FrictionLawKind;
use stickslip::integrator::{Coefficients, Integrator, Kinematics};
use stickslip::law_source::LawSource;
use stickslip::scene::{CheckedScene, FidelityLevel, Scene, Scheme};
use stickslip::simulation::Simulator;
use stickslip::structure::StructuralModel;

/// A law that counts its evaluations (value, or value and slope).
struct Counting {
    inner: Box<dyn FrictionLaw>,
    calls: Arc<AtomicUsize>,
}

impl FrictionLaw for Counting {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn sliding_force(&mut self, v: f64, f_n: f64) -> f64 {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.inner.sliding_force(v, f_n)
    }
    fn sliding_force_and_slope(&mut self, v: f64, f_n: f64) -> (f64, f64) {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.inner.sliding_force_and_slope(v, f_n)
    }
}

/// The paper scene at `level` with `law` (the shipped signed network for `signed`) under
/// `scheme`.
fn scene(level: FidelityLevel, law: FrictionLawKind, signed: bool, scheme: Scheme) -> CheckedScene {
    let mut scene = Scene::default();
    scene.fidelity.level = level;
    scene.friction.law = law;
    if signed {
        scene.friction.weights =
            Some(concat!(env!("CARGO_MANIFEST_DIR"), "/../weights/paper-signed.json").to_string());
    }
    scene.integrator.scheme = scheme;
    scene.check().unwrap()
}

/// One step of a run: contact state, tip deflection (m), and the slip solve's law
/// evaluations as counted by the law and as the simulator reports them, and whether it
/// solved.
struct Step {
    stick: bool,
    tip: f64,
    counted: usize,
    slip: Option<(usize, bool)>,
}

fn run(scene: &CheckedScene, solver: SlipSolver) -> Vec<Step> {
    let calls = Arc::new(AtomicUsize::new(0));
    let law = Counting {
        inner: LawSource::resolve(scene).unwrap().law().unwrap(),
        calls: calls.clone(),
    };
    let mut sim = Simulator::new(scene.clone(), Box::new(law)).unwrap();
    sim.set_slip_solver(solver);
    let steps = (scene.time.end / scene.time.step).round() as usize;
    (0..steps)
        .map(|_| {
            let before = calls.load(Ordering::Relaxed);
            sim.step().unwrap();
            let sample = sim.sample();
            Step {
                stick: sample.stick,
                tip: sample.tip_deflection,
                counted: calls.load(Ordering::Relaxed) - before,
                slip: sim.last_slip_solve().map(|s| (s.evaluations, s.solved)),
            }
        })
        .collect()
}

/// d(tip velocity)/dF and d(tip displacement)/dF of one step of the scene's model.
fn tip_response(scene: &CheckedScene) -> (f64, f64) {
    let model = StructuralModel::build(scene).unwrap();
    let mut integrator = Integrator::new(
        &model,
        Coefficients::from_scene(scene),
        scene.time.step,
        scene.damping.mass_proportional,
        scene.damping.stiffness_proportional,
    )
    .unwrap();
    let trial = integrator.trial(&model, &Kinematics::at_rest(model.dofs()));
    (trial.velocity_per_force, trial.displacement_per_force)
}

/// Over the whole paper scene (1.2 s, 12 000 steps) the Newton solve takes the same
/// stick/slip decisions at every step as the fixed-point iteration of earlier versions,
/// and the tip stays within a bound set by the iteration tolerance.
///
/// The bound: where both converge they agree to dF = 2 SLIP_TOLERANCE (1 + mu_s F_n) per
/// slip step (contact's unit tests), and where the equation has no solution both take
/// the reversal force, bit for bit (`contact::jump`). A force error dF moves the tip by
/// du/dF dF in its step and leaves a velocity error dv/dF dF, which, kept for the rest
/// of the run, moves the tip by at most dv/dF dF t_end. Summed over the run's slip
/// steps: N_slip dF (du/dF + dv/dF t_end), 1e-10 m here. A velocity error does not stay
/// put in a vibrating beam, so the test allows ten times that; measured: 0 (Coulomb:
/// both solve exactly) to 1.4 times the sum (plane stress, 2e-10 m).
#[test]
fn newton_follows_the_fixed_point_over_the_paper_scene() {
    let signed = true;
    let cases = [
        (
            FidelityLevel::Modal,
            FrictionLawKind::Exponential,
            !signed,
            Scheme::GeneralizedAlpha,
        ),
        (
            FidelityLevel::Beam,
            FrictionLawKind::Exponential,
            !signed,
            Scheme::GeneralizedAlpha,
        ),
        (
            FidelityLevel::Beam,
            FrictionLawKind::Exponential,
            !signed,
            Scheme::MoreauJean,
        ),
        (
            FidelityLevel::Beam,
            FrictionLawKind::Neural,
            signed,
            Scheme::GeneralizedAlpha,
        ),
        (
            FidelityLevel::Beam,
            FrictionLawKind::Coulomb,
            !signed,
            Scheme::GeneralizedAlpha,
        ),
        (
            FidelityLevel::PlaneStress,
            FrictionLawKind::Exponential,
            !signed,
            Scheme::GeneralizedAlpha,
        ),
    ];
    for (level, law, signed, scheme) in cases {
        let scene = scene(level, law, signed, scheme);
        let newton = run(&scene, SlipSolver::Newton);
        let fixed = run(&scene, SlipSolver::FixedPoint);
        let case = format!("{level:?}, {law:?} (signed {signed}), {scheme:?}");
        for (k, (a, b)) in newton.iter().zip(&fixed).enumerate() {
            assert_eq!(a.stick, b.stick, "{case}: contact state at step {k}");
        }
        let deviation = newton
            .iter()
            .zip(&fixed)
            .map(|(a, b)| (a.tip - b.tip).abs())
            .fold(0.0, f64::max);
        let slip_steps = newton.iter().filter(|s| s.slip.is_some()).count();
        let force_error = 2.0
            * SLIP_TOLERANCE
            * (1.0 + scene.friction.static_coefficient * scene.loading.normal_force);
        let (dv_df, du_df) = tip_response(&scene);
        let sum = slip_steps as f64 * force_error * (du_df + dv_df * scene.time.end);
        println!(
            "{case}: {slip_steps} slip steps, max tip deviation {deviation:.2e} m, sum {sum:.2e} m"
        );
        assert!(
            deviation <= 10.0 * sum,
            "{case}: max tip deviation {deviation:e} m, bound {:e} m",
            10.0 * sum
        );
    }
}

/// Evaluations per slip step in the paper scene at beam fidelity: 1 to 3 with Newton
/// wherever the slip equation has a solution (laws with a jump at v = 0 meet a few steps
/// near re-stick without one, where the reversal force is taken), against
/// 6 to 7 on average with the fixed-point iteration. The plain network's steep zero
/// crossing makes Newton take more at some breakaways; where the fixed point did not
/// converge at all (|F_law' dx/dF| > 1 there), Newton solves every step.
#[test]
fn slip_steps_take_one_to_three_law_evaluations() {
    for scheme in [Scheme::GeneralizedAlpha, Scheme::MoreauJean] {
        for (law, signed) in [
            (FrictionLawKind::Exponential, false),
            (FrictionLawKind::Coulomb, false),
            (FrictionLawKind::Neural, true),
            (FrictionLawKind::Neural, false),
        ] {
            let scene = scene(FidelityLevel::Beam, law, signed, scheme);
            let case = format!("{law:?} (signed {signed}), {scheme:?}");
            let newton = run(&scene, SlipSolver::Newton);
            let fixed = run(&scene, SlipSolver::FixedPoint);
            for steps in [&newton, &fixed] {
                for s in steps.iter() {
                    // The simulator's count is the law's.
                    assert_eq!(s.slip.map_or(0, |(e, _)| e), s.counted, "{case}");
                }
            }
            let slips: Vec<(usize, bool)> = newton.iter().filter_map(|s| s.slip).collect();
            let unsolved = slips.iter().filter(|(_, solved)| !solved).count();
            let mean = |steps: &[Step]| {
                let slips: Vec<usize> = steps
                    .iter()
                    .filter_map(|s| s.slip.map(|(e, _)| e))
                    .collect();
                slips.iter().sum::<usize>() as f64 / slips.len() as f64
            };
            let within = slips
                .iter()
                .filter(|(e, solved)| *solved && (1..=3).contains(e))
                .count();
            let solved = slips.len() - unsolved;
            let fixed_unsolved = fixed
                .iter()
                .filter(|s| s.slip.is_some_and(|(_, solved)| !solved))
                .count();
            println!(
                "{case}: {} slip steps, Newton {:.2} evaluations per step ({within} of {solved} solved steps within 1 to 3, {unsolved} without solution), fixed point {:.2} ({fixed_unsolved} unconverged)",
                slips.len(),
                mean(&newton),
                mean(&fixed)
            );
            assert!(slips.len() > 1000, "{case}");
            assert!(
                mean(&newton) <= mean(&fixed) / 2.0 || law == FrictionLawKind::Coulomb,
                "{case}"
            );
            if signed || law != FrictionLawKind::Neural {
                assert_eq!(within, solved, "{case}");
                assert!(unsolved * 100 <= slips.len(), "{case}");
            } else {
                assert_eq!(unsolved, 0, "{case}");
                assert!(within * 10 >= solved * 9, "{case}");
                assert!(fixed_unsolved * 20 >= slips.len(), "{case}");
            }
        }
    }
}
