//! `StatefulLaw::force_at_state` of the three laws with state: its gradients against
//! central differences of itself, and its force against the step force as dt -> 0.

use super::{LawStep, StatefulLaw};
use crate::friction::exponential::ExponentialLaw;
use crate::friction::learned_state::{LearnedStateFriction, LearnedStateLaw, StateLawParameters};
use crate::friction::lugre::{LuGreLaw, LuGreParameters};
use crate::friction::rate_and_state::{RateStateLaw, RateStateParameters, StateEvolution};
use std::sync::Arc;

/// One law of each kind with its defaults (the paper's exponential law as LuGre's g),
/// in the order of `STATE_VARIABLES`.
pub(super) fn example_laws() -> [Box<dyn StatefulLaw>; 3] {
    [
        Box::new(LuGreLaw::new(
            LuGreParameters::default(),
            ExponentialLaw {
                static_coefficient: 0.5,
                kinetic_coefficient: 0.2,
                decay: 5.0,
            },
        )),
        Box::new(RateStateLaw::new(RateStateParameters::default())),
        Box::new(LearnedStateFriction::new(Arc::new(LearnedStateLaw {
            parameters: StateLawParameters {
                reference_coefficient: 0.5,
                reference_velocity: 1e-3,
                direct_effect: 0.01,
                evolution_effect: 0.015,
                characteristic_slip: 1e-5,
                state_evolution: crate::friction::rate_and_state::StateEvolution::Aging,
            },
            correction: None,
        }))),
    ]
}

/// States away from steady sliding at the test velocities, so that the step force
/// moves with dt: LuGre half its steady deflection at 0.01 m/s under 100 N
/// (g / sigma0 ~ 4.8e-6 m), theta 3 x D_c / V_0, psi = 0.7.
const STATES: [f64; 3] = [2.4e-6, 3e-2, 0.7];

/// (v, F_n): both signs, the rate-and-state regularisation's core (|w| ~ 1 near
/// v ~ 1e-25 m/s for the defaults) and ordinary sliding.
const POINTS: [(f64, f64); 5] = [
    (0.01, 100.0),
    (-0.02, 80.0),
    (0.3, 120.0),
    (3e-25, 100.0),
    (-1e-3, 50.0),
];

/// The central difference of `f` at `x` with the step `h`.
fn central(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
    (f(x + h) - f(x - h)) / (2.0 * h)
}

/// Central differences with a relative step 1e-6 of each input: truncation ~1e-12 of
/// the derivative's scale for these smooth functions (their scale lengths are |v| and
/// F_n), rounding ~eps |F| / (1e-6 |x|) ~ 1e-10 relative. 1e-6 of the larger of the two
/// (and an absolute 1e-9 for derivatives that are zero) bounds both with room.
#[test]
fn the_force_at_state_has_the_gradients_of_its_central_differences() {
    for (mut law, state) in example_laws().into_iter().zip(STATES) {
        law.set_state(&[state]).unwrap();
        for (v, normal) in POINTS {
            // LuGre's force there is sigma0 z plus ~1e-22 N: a difference at that v is
            // all rounding of sigma0 z (eps |F| / h >> dF/dv). Only the regularised
            // laws, whose force ~ v there, are tested in the core.
            if v.abs() < 1e-20 && law.state_variables()[0].name == "bristle_deflection" {
                continue;
            }
            let at = law.force_at_state(v, normal);
            assert_eq!(at.slope, at.force_gradient[0]);
            let (hv, hn) = (1e-6 * v.abs(), 1e-6 * normal);
            let expected = [
                central(|x| law.force_at_state(x, normal).force, v, hv),
                central(|x| law.force_at_state(v, x).force, normal, hn),
                central(|x| law.force_at_state(x, normal).slope, v, hv),
                central(|x| law.force_at_state(v, x).slope, normal, hn),
            ];
            let exact = [
                at.force_gradient[0],
                at.force_gradient[1],
                at.slope_gradient[0],
                at.slope_gradient[1],
            ];
            for (k, (e, x)) in expected.iter().zip(exact).enumerate() {
                assert!(
                    (e - x).abs() <= 1e-6 * e.abs().max(x.abs()) + 1e-9,
                    "{:?} law, state {state}, v {v}, F_n {normal}: derivative {k} is {x}, central difference {e}",
                    law.state_variables()[0].name
                );
            }
        }
    }
}

/// The step force at a fixed velocity tends to the force at the committed state as
/// dt -> 0, at first order (the state moves by dt times its rate): ten times smaller a
/// step gives about ten times smaller a difference (asserted below 0.2, first order
/// giving 0.1 plus O(dt) corrections), and the committed state is unchanged.
#[test]
fn the_step_force_tends_to_the_force_at_state_as_the_step_shrinks() {
    for (mut law, state) in example_laws().into_iter().zip(STATES) {
        law.set_state(&[state]).unwrap();
        for (v, normal) in [(0.01, 100.0), (-0.02, 80.0)] {
            let at = law.force_at_state(v, normal).force;
            let mut gap = |dt: f64| {
                let step = LawStep {
                    dt,
                    sliding_velocity: v,
                    normal_force: normal,
                };
                (law.step_force_and_slope(step).0 - at).abs()
            };
            let (coarse, fine) = (gap(1e-8), gap(1e-9));
            let name = law.state_variables()[0].name;
            assert!(
                coarse > 0.0 && fine < 0.2 * coarse,
                "{name}, v {v}: gaps {coarse:e}, {fine:e}"
            );
            assert_eq!(law.state(), &[state]);
        }
    }
}

/// The slip-law variant of rate-and-state shares the force (the state only enters
/// through theta), so its force at state equals the aging variant's bit for bit.
#[test]
fn the_force_at_state_does_not_depend_on_the_evolution_law() {
    let aging = RateStateLaw::new(RateStateParameters::default());
    let slip = RateStateLaw::new(RateStateParameters {
        state_evolution: StateEvolution::Slip,
        ..RateStateParameters::default()
    });
    for (v, normal) in POINTS {
        assert_eq!(
            aging.force_at_state(v, normal),
            slip.force_at_state(v, normal)
        );
    }
}
