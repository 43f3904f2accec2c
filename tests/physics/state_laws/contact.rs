//! Laws with state in the time loop: the stick output, the stiff-bristle limit of
//! LuGre, stability for bristles far stiffer than the beam, the stick-slip threshold of
//! rate-and-state against its closed-form critical slip, saved states, and the scene's
//! checks. Runs are on the paper beam at modal fidelity (4 modes, a few ms each) unless
//! a test says otherwise.

use stickslip::choice::Choice;
use stickslip::friction::lugre;
use stickslip::friction::rate_and_state;
use stickslip::friction::rate_and_state::RateStateParameters;
use stickslip::friction::rate_and_state::StateEvolution;
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::LawSource;
use stickslip::run::{run_scene, Run};
use stickslip::scene::{FidelityLevel, Scene, Scheme, SlidingVelocity};
use stickslip::simulation::{Sample, Simulator};
use stickslip::stability::cantilever_omega;

pub(super) fn scene(law: FrictionLawKind) -> Scene {
    let mut s = Scene::default();
    s.friction.law = law;
    s.fidelity.level = FidelityLevel::Modal;
    s.fidelity.modes = 4;
    s
}

pub(super) fn run(s: Scene) -> Run {
    let checked = s.check().unwrap();
    let source = LawSource::resolve(&checked).unwrap();
    run_scene(checked, &source, 1).unwrap()
}

/// The sawtooth read off the tip deflection alone, the same way for every law (the
/// stick flag of a law with state is a velocity threshold, not the memoryless switch):
/// the times (s) at which the deflection falls through 80 % of its largest value, on
/// the steep flank of each drop (interpolated between samples; the flat tops make the
/// times of the maxima themselves ill-conditioned), and the largest deflection (m).
struct Sawtooth {
    drops: Vec<f64>,
    highest: f64,
}

impl Sawtooth {
    fn of(samples: &[Sample]) -> Self {
        let highest = samples
            .iter()
            .map(|s| s.tip_deflection)
            .fold(f64::MIN, f64::max);
        let level = 0.8 * highest;
        let drops = samples
            .windows(2)
            .filter(|w| w[0].tip_deflection >= level && w[1].tip_deflection < level)
            .map(|w| {
                let fraction =
                    (w[0].tip_deflection - level) / (w[0].tip_deflection - w[1].tip_deflection);
                w[0].time + fraction * (w[1].time - w[0].time)
            })
            .collect();
        Sawtooth { drops, highest }
    }

    fn period(&self) -> f64 {
        let n = self.drops.len();
        (self.drops[n - 1] - self.drops[0]) / (n - 1) as f64
    }
}

/// `stick` means |v_rel| < friction.stick_threshold for a law with state, at every
/// sample, and the paper scene with either law has both phases.
#[test]
fn the_stick_output_of_a_law_with_state_is_the_velocity_threshold() {
    for law in [FrictionLawKind::Lugre, FrictionLawKind::RateAndState] {
        let result = run(scene(law));
        let eps = Scene::default().friction.stick_threshold;
        for s in &result.samples[1..] {
            assert_eq!(
                s.stick,
                s.relative_velocity.abs() < eps,
                "{law:?} at {}",
                s.time
            );
        }
        assert!(result.samples.iter().any(|s| s.stick));
        assert!(result.samples.iter().any(|s| !s.stick));
        assert!(
            result.summary.slip_phases >= 3,
            "{law:?}: {:?}",
            result.summary
        );
    }
}

/// With sigma1 = sigma2 = 0 and sigma0 -> infinity LuGre becomes the set-valued law
/// with the static limit g(0) = mu_s F_n and the kinetic law g(v): the memoryless run.
/// Measured on the sawtooth (1.2 s, three drops): the largest deflection differs by
/// 3.8e-5, 7.7e-6, 1.5e-6, 2.7e-7 m at sigma0 = 1e7 ... 1e10 N/m, a factor 5 to 6 per
/// decade (order ~0.74 in sigma0); asserted: at least 3 per decade, and below 5e-7 m at
/// 1e10. The first drop (breakaway) agrees to 1.6e-5 s from sigma0 = 1e9 on (asserted
/// 1e-4 s, the step). The period differs by 2.2 ms, 0.24 ms, 0.049 ms and 0.0072 ms
/// at 1e7 ... 1e10; asserted: below the step from 1e9 on. (Before issue 37 the
/// memoryless run's re-stick took either side's force where the slip equation had no
/// solution, its period moved by 2.9 ms with the stick threshold, and that was the
/// tolerance here; now it re-sticks at the reversal force, the same period at eps =
/// 1e-3 and 1e-4 m/s.)
#[test]
fn lugre_with_stiff_bristles_approaches_the_memoryless_run() {
    let reference = Sawtooth::of(&run(scene(FrictionLawKind::Exponential)).samples);
    let mut last = f64::INFINITY;
    for sigma0 in [1e7, 1e8, 1e9, 1e10] {
        let mut s = scene(FrictionLawKind::Lugre);
        s.friction.laws.set(&lugre::BRISTLE_STIFFNESS, sigma0);
        s.friction.laws.set(&lugre::BRISTLE_DAMPING, 0.0);
        s.friction.laws.set(&lugre::VISCOUS_DAMPING, 0.0);
        let saw = Sawtooth::of(&run(s).samples);
        let difference = (saw.highest - reference.highest).abs();
        assert!(
            difference < last / 3.0,
            "sigma0 {sigma0:e}: {difference:e} after {last:e}"
        );
        last = difference;
        if sigma0 >= 1e9 {
            assert!(
                (saw.drops[0] - reference.drops[0]).abs() < 1e-4,
                "{sigma0:e}: {:?} vs {:?}",
                saw.drops,
                reference.drops
            );
            assert!(
                (saw.period() - reference.period()).abs() < 1e-4,
                "{sigma0:e}: {:?} vs {:?}",
                saw.drops,
                reference.drops
            );
        }
    }
    assert!(last < 5e-7, "{last:e}");
}

/// Bristles 1.6e8 times stiffer than the tip (sigma0 = 1e12 N/m against 3 EI / L^3 =
/// 6.25e3 N/m) step stably at beam and modal fidelity with both schemes: the exact
/// bristle step is L-stable. The first peak is the memoryless run's to 1e-7 m (the
/// stiff-bristle limit above, at 1e10 already 2.7e-7 m) and at its time to the sample.
#[test]
fn stiff_bristles_are_stable_at_every_fidelity_with_both_schemes() {
    for level in [FidelityLevel::Modal, FidelityLevel::Beam] {
        for scheme in [Scheme::GeneralizedAlpha, Scheme::MoreauJean] {
            let configure = |law| {
                let mut s = scene(law);
                s.fidelity.level = level;
                s.fidelity.beam_elements = 10;
                s.integrator.scheme = scheme;
                s.time.end = 0.6;
                s
            };
            let reference = Sawtooth::of(&run(configure(FrictionLawKind::Exponential)).samples);
            let mut s = configure(FrictionLawKind::Lugre);
            s.friction.laws.set(&lugre::BRISTLE_STIFFNESS, 1e12);
            let result = run(s);
            assert!(result.samples.iter().all(|s| s.friction_force.is_finite()));
            let saw = Sawtooth::of(&result.samples);
            assert!(
                (saw.highest - reference.highest).abs() < 1e-7,
                "{level:?} {scheme:?}: {} vs {}",
                saw.highest,
                reference.highest
            );
            assert!((saw.drops[0] - reference.drops[0]).abs() < 1.5e-4);
        }
    }
}

/// The critical slip of the paper beam's first mode as a spring-block (tip modal mass
/// m = M / 4, since phi_1(L)^2 = 4 / M for the mass-normalised cantilever modes, and
/// k = omega_1^2 m): steady sliding at V is linearly stable when
/// k > (b - a) F_n / D_c [1 + m V^2 / (a F_n D_c)] (Rice & Ruina 1983; derived in
/// docs/friction-with-memory.md), so D_c* is the positive root of
/// k D^2 - (b - a) F_n D - (b - a) m V^2 / a = 0: 4.35e-4 m for the defaults. The beam's
/// damping (b_R omega_1^2 m = 0.32 N s/m) moves it by 1 %, left out.
fn critical_slip(s: &Scene) -> f64 {
    let checked = s.clone().check().unwrap();
    let mass = checked.mass_per_length() * checked.geometry.length / 4.0;
    let k = cantilever_omega(&checked, 1).unwrap().powi(2) * mass;
    let p = RateStateParameters::of(&s.friction.laws);
    let (a, weakening) = (p.direct_effect, p.evolution_effect - p.direct_effect);
    let (f_n, v) = (s.loading.normal_force, s.loading.belt_speed);
    let linear = weakening * f_n;
    (linear + (linear * linear + 4.0 * k * weakening * mass * v * v / a).sqrt()) / (2.0 * k)
}

/// Peak-to-peak v_rel (m/s) of a run between t0 and t1 (s).
fn swing(samples: &[Sample], t0: f64, t1: f64) -> f64 {
    let window = samples.iter().filter(|s| s.time >= t0 && s.time < t1);
    let (lo, hi) = window.fold((f64::MAX, f64::MIN), |(lo, hi), s| {
        (lo.min(s.relative_velocity), hi.max(s.relative_velocity))
    });
    hi - lo
}

/// Rate-and-state with b > a on the paper beam at belt speed 0.02 m/s, both evolution
/// laws, against the closed-form critical slip D_c* (4.35e-4 m):
/// - D_c = 0.1 D_c*: stick-slip (the tip sticks in the last second, the swing of v_rel
///   repeats);
/// - 0.7 D_c*: steady sliding is unstable: the oscillation does not decay (measured
///   swing ratio 1.000 between the 5th and 6th second);
/// - 1.5 D_c*: it decays (measured ratio 0.27 per second), and at 3 D_c* the beam
///   slides steadily (swing below 1e-4 m/s = 0.5 % of v_b after 3 s; measured 2.3e-6
///   and 3.6e-6).
///
/// The threshold sits between 0.9 and 1.1 D_c* in the measurements (ratio 0.98 and
/// 0.71), the closed form's 1 % damping shift inside that.
#[test]
fn rate_and_state_stick_slips_below_the_critical_slip_and_slides_steadily_above() {
    for evolution in [StateEvolution::Aging, StateEvolution::Slip] {
        let with = |factor: f64, end: f64| {
            let mut s = scene(FrictionLawKind::RateAndState);
            s.friction.laws.set(
                &rate_and_state::STATE_EVOLUTION,
                f64::from(evolution.code()),
            );
            let critical = critical_slip(&s);
            assert!((critical - 4.35e-4).abs() < 0.01e-4, "{critical:e}");
            s.friction
                .laws
                .set(&rate_and_state::CHARACTERISTIC_SLIP, factor * critical);
            s.time.end = end;
            run(s).samples
        };
        let stick_slip = with(0.1, 3.0);
        assert!(
            stick_slip
                .iter()
                .filter(|s| s.time > 2.0 && s.stick)
                .count()
                > 100
        );
        let ratio = swing(&stick_slip, 2.0, 3.0) / swing(&stick_slip, 1.0, 2.0);
        assert!((ratio - 1.0).abs() < 0.02, "{evolution:?}: {ratio}");

        let unstable = with(0.7, 6.0);
        let ratio = swing(&unstable, 5.0, 6.0) / swing(&unstable, 4.0, 5.0);
        assert!(ratio > 0.98, "{evolution:?} 0.7 D_c*: {ratio}");
        let stable = with(1.5, 6.0);
        let ratio = swing(&stable, 5.0, 6.0) / swing(&stable, 4.0, 5.0);
        assert!(ratio < 0.5, "{evolution:?} 1.5 D_c*: {ratio}");

        let steady = with(3.0, 4.0);
        assert!(swing(&steady, 3.0, 4.0) < 1e-4, "{evolution:?}");
        assert!(steady.iter().all(|s| s.time < 3.0 || !s.stick));
    }
}

/// The law's state travels with the simulation state: a run restored from a state
/// saved at 0.45 s (in the first slip) goes on bit for bit; a state without the law's
/// state, or with one for a memoryless law, is refused with the reason.
#[test]
fn saved_states_carry_the_law_state() {
    for law in [FrictionLawKind::Lugre, FrictionLawKind::RateAndState] {
        let checked = scene(law).check().unwrap();
        let source = LawSource::resolve(&checked).unwrap();
        let mut first = Simulator::new(checked.clone(), source.law().unwrap()).unwrap();
        first.advance_to(0.45).unwrap();
        let saved = first.state().clone();
        assert_eq!(saved.law_state.len(), 1);
        first.advance_to(0.6).unwrap();
        let mut second = Simulator::new(checked.clone(), source.law().unwrap()).unwrap();
        second.restore(saved.clone()).unwrap();
        second.advance_to(0.6).unwrap();
        assert_eq!(first.state(), second.state());
        assert_eq!(
            format!("{:?}", first.sample()),
            format!("{:?}", second.sample())
        );

        let mut old = saved.clone();
        old.law_state.clear();
        let error = second.restore(old).unwrap_err().to_string();
        assert!(error.contains("0 values for a state of 1"), "{error}");
        let exponential = scene(FrictionLawKind::Exponential).check().unwrap();
        let mut memoryless = Simulator::new(
            exponential.clone(),
            LawSource::resolve(&exponential).unwrap().law().unwrap(),
        )
        .unwrap();
        let error = memoryless.restore(saved).unwrap_err().to_string();
        assert!(error.contains("has no state"), "{error}");
    }
}

/// The parameters are checked with the scene, and the contact options a law with state
/// cannot honour are refused with the reason.
#[test]
fn the_scene_refuses_bad_parameters_and_options_with_the_reason() {
    let message = |edit: &dyn Fn(&mut Scene)| {
        let mut s = scene(FrictionLawKind::Lugre);
        edit(&mut s);
        s.check().unwrap_err().to_string()
    };
    type Edit<'a> = &'a dyn Fn(&mut Scene);
    let cases: [(Edit, &str); 5] = [
        (
            &|s| s.friction.laws.set(&lugre::BRISTLE_STIFFNESS, -1.0),
            "friction.lugre.bristle_stiffness",
        ),
        (
            &|s| s.friction.laws.set(&lugre::BRISTLE_DAMPING, f64::NAN),
            "friction.lugre.bristle_damping",
        ),
        (
            &|s| {
                s.friction
                    .laws
                    .set(&rate_and_state::CHARACTERISTIC_SLIP, 0.0)
            },
            "friction.rate_and_state.characteristic_slip",
        ),
        (
            &|s| s.friction.laws.set(&rate_and_state::EVOLUTION_EFFECT, -0.1),
            "friction.rate_and_state.evolution_effect",
        ),
        (
            &|s| s.contact.sliding_velocity = SlidingVelocity::Tip,
            "a law with state evolves with the relative slip velocity",
        ),
    ];
    for (edit, expected) in cases {
        let text = message(edit);
        assert!(text.contains(expected), "{text}");
    }
    let toml = "[friction]\nlaw = \"rate-and-state\"\n[friction.rate_and_state]\nstate_evolution = \"slip\"\ncharacteristic_slip = 2e-5\n";
    let parsed = Scene::from_toml_str(toml).unwrap();
    assert_eq!(parsed.friction.law, FrictionLawKind::RateAndState);
    assert_eq!(
        RateStateParameters::of(&parsed.friction.laws).state_evolution,
        StateEvolution::Slip
    );
    assert_eq!(
        RateStateParameters::of(&parsed.friction.laws).characteristic_slip,
        2e-5
    );
}

/// The FMI 3.0 early return stops at a switch of the stick output: for a law with state,
/// where |v_rel| crosses the stick threshold. `advance_until_switch` ends the step in
/// which the flag changed, with the transition recorded, and otherwise takes the steps
/// `advance_to` takes.
#[test]
fn the_early_return_stops_where_the_stick_output_switches() {
    for law in [FrictionLawKind::Lugre, FrictionLawKind::RateAndState] {
        let checked = scene(law).check().unwrap();
        let source = LawSource::resolve(&checked).unwrap();
        let mut stopping = Simulator::new(checked.clone(), source.law().unwrap()).unwrap();
        let mut plain = Simulator::new(checked.clone(), source.law().unwrap()).unwrap();
        let mut stops = 0;
        let mut stuck = stopping.sample().stick;
        while let Some(time) = stopping.advance_until_switch(0.8).unwrap() {
            assert_ne!(stopping.sample().stick, stuck, "{law:?} at {time}");
            stuck = stopping.sample().stick;
            assert_eq!(stopping.transitions().last().unwrap().time, time);
            plain.advance_to(time).unwrap();
            assert_eq!(plain.state(), stopping.state());
            stops += 1;
        }
        assert!(stops >= 2, "{law:?}: {stops}");
        assert_eq!(stopping.state().time, 0.8);
    }
}

/// A preloaded start (`contact.preload`, the beam held by P = preload mu_s F_n at
/// t = 0) puts LuGre's bristles at z = P / sigma0, so that the law carries P from the
/// first step: the first step's force is P to within what one step adds (the tip moves
/// with the belt, so the bristles barely deflect further: measured 4.8e-4 N, asserted
/// 0.01 N). Without the hold the force would start near 0 (z = 0).
#[test]
fn a_preloaded_start_loads_the_bristles() {
    let mut s = scene(FrictionLawKind::Lugre);
    s.contact.preload = 0.5;
    let checked = s.check().unwrap();
    let source = LawSource::resolve(&checked).unwrap();
    let mut sim = Simulator::new(checked.clone(), source.law().unwrap()).unwrap();
    let held = sim.state().holding_force;
    assert!((held - 25.0).abs() < 0.1, "{held}");
    assert!((sim.state().law_state[0] - held / 1e7).abs() < 1e-15);
    sim.step().unwrap();
    let force = sim.sample().friction_force;
    assert!((force - held).abs() < 0.01, "{force} vs {held}");
}
