//! NeuralFriction with `law = lugre` and `law = rate-and-state`, FMI 2.0 and 3.0: the
//! steady state at constant velocity, rate-and-state's direct effect at a velocity
//! step, the state outputs, the law state in the FMU state (bit for bit, and version-4
//! states written before these laws existed), and bad parameters refused with the
//! reason. The coupled run with StickSlipBeam is in `friction_laws_coupled`.

use std::sync::{Arc, Mutex};
use stickslip::choice::Choice;
use stickslip::friction::exponential::ExponentialLaw;
use stickslip::friction::rate_and_state;
use stickslip::friction::rate_and_state::{RateStateParameters, StateEvolution};
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::instance::{FmiVersion, Instance, SavedState};
use stickslip_tests::vr;

pub(crate) type Log = Arc<Mutex<Vec<String>>>;

/// An initialised NeuralFriction of `version` with `law`, the Integer and Real
/// parameters `integers` and `reals` (name, value) set before initialisation, and its
/// log; the error of fmi2ExitInitializationMode / fmi3ExitInitializationMode if it
/// refuses.
pub(crate) fn initialised(
    version: FmiVersion,
    law: NeuralFrictionLaw,
    integers: &[(&str, i32)],
    reals: &[(&str, f64)],
) -> (Result<Instance<NeuralFriction>, String>, Log) {
    let log: Log = Arc::default();
    let sink = log.clone();
    let logger = Box::new(move |_, _: &str, message: &str| {
        sink.lock().unwrap().push(message.to_string());
    });
    let dir = stickslip_tests::weights_dir();
    let mut f =
        Instance::<NeuralFriction>::instantiate(version, "f", Some(&dir), false, logger).unwrap();
    f.set_integer(&[vr::<NeuralFriction>("law")], &[law.code()])
        .unwrap();
    for (name, value) in integers {
        f.set_integer(&[vr::<NeuralFriction>(name)], &[*value])
            .unwrap();
    }
    for (name, value) in reals {
        // A value no parameter may have (NaN, infinite) is refused here already.
        if let Err(e) = f.set_real(&[vr::<NeuralFriction>(name)], &[*value]) {
            return (Err(format!("{e:?}")), log);
        }
    }
    f.setup_experiment(0.0, None).unwrap();
    f.enter_initialization_mode().unwrap();
    let result = match f.exit_initialization_mode() {
        Ok(()) => Ok(f),
        Err(e) => Err(format!("{e:?}")),
    };
    (result, log)
}

pub(crate) fn set_velocity(f: &mut Instance<NeuralFriction>, v: f64) {
    f.set_real(&[vr::<NeuralFriction>("sliding_velocity")], &[v])
        .unwrap();
}

pub(crate) fn real(f: &mut Instance<NeuralFriction>, name: &str) -> f64 {
    let mut out = [0.0];
    f.get_real(&[vr::<NeuralFriction>(name)], &mut out).unwrap();
    out[0]
}

/// `n` steps of `h` from `t` in the version's way; returns the end time.
pub(crate) fn steps(
    f: &mut Instance<NeuralFriction>,
    version: FmiVersion,
    t: f64,
    h: f64,
    n: usize,
) -> f64 {
    let mut t = t;
    for _ in 0..n {
        match version {
            FmiVersion::V2 => f.do_step(t, h).unwrap(),
            FmiVersion::V3 => {
                f.do_step3(t, h).unwrap();
            }
        }
        t += h;
    }
    t
}

const VERSIONS: [FmiVersion; 2] = [FmiVersion::V2, FmiVersion::V3];

/// NeuralFriction's default exponential law, LuGre's g(v).
fn exponential() -> ExponentialLaw {
    let scene = stickslip::scene::Scene::default();
    scene.friction.exponential_law()
}

/// Sliding at constant v for 0.1 s (1e-3 s steps), LuGre's force is g(v) sgn v + sigma2 v
/// and its deflection sgn(v) g(v) / sigma0. The bristle relaxation time g / (sigma0 |v|)
/// is 2.3e-4 s at 0.02 m/s and 4.5e-5 s at 0.1 m/s (g ~ 45 N, sigma0 = 1e7 N/m): after
/// 0.1 s the initial state's memory is below e^-400, and the exact step keeps the fixed
/// point to rounding. What is left is the rounding of sigma0 z and of the rate v - c z
/// (a few ulp of 45 N, times sigma1 = 1e3 N s/m for the rate's ~1e-18 m/s): 1e-9 N
/// bounds it with room and is 1e-11 of the force.
#[test]
fn lugre_at_constant_velocity_converges_to_its_steady_force() {
    let sigma2 = 5.0;
    for version in VERSIONS {
        let (f, _) = initialised(
            version,
            NeuralFrictionLaw::LUGRE,
            &[],
            &[("friction.lugre.viscous_damping", sigma2)],
        );
        let mut f = f.unwrap();
        let mut t = 0.0;
        for v in [0.02, -0.1] {
            set_velocity(&mut f, v);
            t = steps(&mut f, version, t, 1e-3, 100);
            let g = exponential().coefficient(v) * 100.0;
            let expected = g * v.signum() + sigma2 * v;
            let force = real(&mut f, "friction_force");
            assert!(
                (force - expected).abs() < 1e-9,
                "{version:?} v {v}: {force} vs {expected}"
            );
            // z to 1e-12 relative (its rounding is ulps); the other laws' outputs are 0.
            let z = real(&mut f, "bristle_deflection");
            let z_steady = v.signum() * g / 1e7;
            assert!((z - z_steady).abs() < 1e-12 * z_steady.abs(), "{z}");
            assert_eq!(real(&mut f, "state_theta"), 0.0);
            assert_eq!(real(&mut f, "state_psi"), 0.0);
        }
    }
}

/// Sliding at constant V for 0.1 s, rate-and-state's force is F_n (mu_0 + (a - b)
/// ln(V / V_0)) and theta = D_c / V, for both evolution laws. The state relaxes over the
/// slip D_c = 1e-5 m: e^-200 of the initial state remains at 0.02 m/s after 0.1 s, and
/// the regularised law equals the classical one to a / (4 w^2) with w > e^40. Left is
/// the rounding of ln and asinh (ulps of 48 N): 1e-9 N.
#[test]
fn rate_and_state_at_constant_velocity_converges_to_its_steady_force() {
    for version in VERSIONS {
        for &evolution in StateEvolution::ALL {
            let (f, _) = initialised(
                version,
                NeuralFrictionLaw::RATE_AND_STATE,
                &[("friction.rate_and_state.state_evolution", evolution.code())],
                &[],
            );
            let mut f = f.unwrap();
            let p = RateStateParameters::default();
            let mut t = 0.0;
            for v in [0.02, -0.005] {
                set_velocity(&mut f, v);
                t = steps(&mut f, version, t, 1e-3, 100);
                let expected = v.signum() * 100.0 * p.steady_coefficient(v.abs());
                let force = real(&mut f, "friction_force");
                assert!(
                    (force - expected).abs() < 1e-9,
                    "{version:?} {evolution:?} v {v}: {force} vs {expected}"
                );
                let theta = real(&mut f, "state_theta");
                let steady = p.characteristic_slip / v.abs();
                assert!((theta - steady).abs() < 1e-12 * steady, "{theta}");
                assert_eq!(real(&mut f, "bristle_deflection"), 0.0);
            }
        }
    }
}

/// Steady at V_1 = 1 mm/s, then V_2 = 10 mm/s set between steps: the force jumps at
/// once by a ln(V_2 / V_1) F_n (the state has not moved; the same formula at the same
/// theta, so to rounding: 1e-9 N), then relaxes to the steady force at V_2 (1e-9 N as
/// above, after 200 D_c of slip).
#[test]
fn a_velocity_step_gives_the_direct_effect_at_once_then_the_new_steady_force() {
    let p = RateStateParameters::default();
    for version in VERSIONS {
        let (f, _) = initialised(version, NeuralFrictionLaw::RATE_AND_STATE, &[], &[]);
        let mut f = f.unwrap();
        set_velocity(&mut f, 1e-3);
        let t = steps(&mut f, version, 0.0, 1e-2, 20);
        let before = real(&mut f, "friction_force");
        set_velocity(&mut f, 1e-2);
        let jump = real(&mut f, "friction_force") - before;
        let expected = p.direct_effect * stickslip::elementary::ln(10.0) * 100.0;
        assert!(
            (jump - expected).abs() < 1e-9,
            "{version:?}: {jump} vs {expected}"
        );
        steps(&mut f, version, t, 1e-3, 200);
        let after = real(&mut f, "friction_force");
        let steady = 100.0 * p.steady_coefficient(1e-2);
        assert!((after - steady).abs() < 1e-9, "{after} vs {steady}");
        // b > a: velocity weakening, the new steady force is below the old one.
        assert!(after < before);
    }
}

/// The outputs read after `n` steps of 1e-3 s from `t` at each of a few velocities, as
/// bits: force, slope and the three state outputs.
fn run_bits(f: &mut Instance<NeuralFriction>, version: FmiVersion, t: f64) -> Vec<u64> {
    let mut out = Vec::new();
    let mut t = t;
    for v in [3e-2, -1e-2, 0.0, 5e-3] {
        set_velocity(f, v);
        t = steps(f, version, t, 1e-3, 3);
        for name in [
            "friction_force",
            "friction_force_slope",
            "bristle_deflection",
            "state_theta",
            "state_psi",
        ] {
            out.push(real(f, name).to_bits());
        }
    }
    out
}

/// The law state is in the FMU state: restored in the same instance after it went on
/// (get/set), and serialised and restored in a fresh one, the run that follows is the
/// uninterrupted run's, bit for bit. A law state outside the law's domain is refused.
#[test]
fn the_state_round_trips_bit_for_bit_for_both_laws() {
    for version in VERSIONS {
        for law in [NeuralFrictionLaw::LUGRE, NeuralFrictionLaw::RATE_AND_STATE] {
            let (f, _) = initialised(version, law, &[], &[]);
            let mut f = f.unwrap();
            set_velocity(&mut f, 2e-2);
            let t = steps(&mut f, version, 0.0, 1e-4, 7);
            let saved = f.get_state().unwrap();
            let bytes = f.serialize_state(&saved).unwrap();
            let uninterrupted = run_bits(&mut f, version, t);
            f.set_state(&saved).unwrap();
            assert_eq!(
                run_bits(&mut f, version, t),
                uninterrupted,
                "{law:?} get/set"
            );
            let (other, _) = initialised(version, law, &[], &[]);
            let mut other = other.unwrap();
            let restored = other.deserialize_state(&bytes).unwrap();
            other.set_state(&restored).unwrap();
            assert_eq!(
                run_bits(&mut other, version, t),
                uninterrupted,
                "{law:?} serialised"
            );
            // A state that does not fit the law is refused when set (theta must be > 0;
            // LuGre's z may be any finite value), and the instance runs on unchanged.
            if law == NeuralFrictionLaw::RATE_AND_STATE {
                let mut bad = saved.clone();
                bad.model["law_state"] = serde_json::json!([-1.0]);
                assert!(other.set_state(&bad).is_err());
                other.set_state(&saved).unwrap();
                assert_eq!(
                    run_bits(&mut other, version, t),
                    uninterrupted,
                    "after refusal"
                );
            }
        }
    }
}

/// A version-4 state as NeuralFriction wrote it before `lugre` and `rate-and-state`
/// existed: its settings have no `lugre` and `rate_and_state` tables (and its law is
/// neural or exponential). Built here by removing them from a state of today's code
/// (the rest of the format is unchanged); it restores, and the learned law with memory
/// runs on from it bit for bit.
#[test]
fn a_version_4_state_from_before_these_laws_still_restores() {
    let dir = stickslip_tests::weights_dir();
    for version in VERSIONS {
        let learned = || {
            let logger = Box::new(|_, _: &str, _: &str| {});
            let mut f =
                Instance::<NeuralFriction>::instantiate(version, "f", Some(&dir), false, logger)
                    .unwrap();
            f.set_string(
                &[vr::<NeuralFriction>("weights")],
                &["rate-and-state-learned.json"],
            )
            .unwrap();
            f.setup_experiment(0.0, None).unwrap();
            f.enter_initialization_mode().unwrap();
            f.exit_initialization_mode().unwrap();
            f
        };
        let mut f = learned();
        set_velocity(&mut f, 3e-3);
        let t = steps(&mut f, version, 0.0, 1e-3, 5);
        let mut old: SavedState = f.get_state().unwrap();
        // The JSON of version 4 is that of today's version 5; version 4 has no checksum.
        old.version = 4;
        let settings = old.model["settings"].as_object_mut().unwrap();
        assert!(settings.remove("lugre").is_some());
        assert!(settings.remove("rate_and_state").is_some());
        let bytes = old.to_bytes();
        let uninterrupted = run_bits(&mut f, version, t);
        let mut fresh = learned();
        fresh
            .set_state(&SavedState::from_bytes(&bytes).unwrap())
            .unwrap();
        assert_eq!(run_bits(&mut fresh, version, t), uninterrupted);
    }
}

/// Out-of-range parameters of the laws with state are refused with fmi2Error / fmi3Error
/// and the parameter's name in the log, and no panic: non-finite values when set
/// (fmi2SetReal / fmi3SetFloat64), finite ones out of range when initialisation ends.
#[test]
fn bad_parameters_are_refused_with_the_reason() {
    let cases = [
        (
            NeuralFrictionLaw::LUGRE,
            "friction.lugre.bristle_stiffness",
            -1e7,
        ),
        (
            NeuralFrictionLaw::LUGRE,
            "friction.lugre.bristle_stiffness",
            f64::NAN,
        ),
        (
            NeuralFrictionLaw::LUGRE,
            "friction.lugre.bristle_damping",
            -1.0,
        ),
        (
            NeuralFrictionLaw::RATE_AND_STATE,
            "friction.rate_and_state.direct_effect",
            0.0,
        ),
        (
            NeuralFrictionLaw::RATE_AND_STATE,
            "friction.rate_and_state.direct_effect",
            -0.01,
        ),
        (
            NeuralFrictionLaw::RATE_AND_STATE,
            "friction.rate_and_state.characteristic_slip",
            0.0,
        ),
        (
            NeuralFrictionLaw::RATE_AND_STATE,
            "friction.rate_and_state.characteristic_slip",
            -1e-5,
        ),
        (
            NeuralFrictionLaw::RATE_AND_STATE,
            "friction.rate_and_state.reference_velocity",
            f64::NAN,
        ),
        (
            NeuralFrictionLaw::RATE_AND_STATE,
            "friction.rate_and_state.evolution_effect",
            f64::INFINITY,
        ),
        // Finite, but E = exp(mu_0 / a) / (2 V_0) overflows: no finite slope at rest.
        (
            NeuralFrictionLaw::RATE_AND_STATE,
            "friction.rate_and_state.direct_effect",
            1e-6,
        ),
    ];
    for version in VERSIONS {
        for (law, name, value) in cases {
            let (result, log) = initialised(version, law, &[], &[(name, value)]);
            assert!(result.is_err(), "{version:?} {name} = {value} accepted");
            let log = log.lock().unwrap();
            assert!(
                log.iter().any(|m| m.contains(name)),
                "{version:?} {name} = {value}: {log:?}"
            );
        }
    }
}

/// rate-and-state with a = 1e-6 (its slope at rest F_n a exp(mu_0 / a) / (2 V_0)
/// overflows) is refused at initialisation in both versions with the words of the
/// scene check, which the command line and StickSlipBeam give (`memory_laws`), the
/// parameter named; before, NeuralFriction said "the outputs are not finite at
/// sliding_velocity = 0 ... slope inf" and StickSlipBeam ran it.
#[test]
fn a_rate_and_state_law_without_a_finite_slope_at_rest_is_refused_as_by_the_scene() {
    let mut scene = stickslip::scene::Scene::default();
    scene
        .friction
        .laws
        .set(&rate_and_state::DIRECT_EFFECT, 1e-6);
    let reason = scene.check().unwrap_err().to_string();
    assert!(reason.starts_with("invalid scene: friction.rate_and_state.direct_effect = 1e-6; it must be >= 7.206847e-4"), "{reason}");
    for version in VERSIONS {
        let (result, log) = initialised(
            version,
            NeuralFrictionLaw::RATE_AND_STATE,
            &[],
            &[("friction.rate_and_state.direct_effect", 1e-6)],
        );
        assert!(result.is_err());
        let log = log.lock().unwrap();
        assert!(
            log.iter().any(|m| m.contains(&reason)),
            "{version:?}: {log:?}"
        );
    }
}

/// At v = 0 LuGre's `friction_force_slope` and its directional derivatives are those of
/// v > 0, as the other laws' (docs/fmu-reference.md): with z the committed deflection,
/// g(0) = mu_s F_n and g'(0+) = -alpha (mu_s - mu_k) F_n, S = sigma1 (1 - sigma0 z /
/// g(0)) + sigma2, dS/dv = 2 sigma1 sigma0 z g'(0+) / g(0)^2, dS/dF_n = sigma1 sigma0 z
/// / (g(0) F_n), dF/dF_n = 0. The FMU evaluates the same operations in another order:
/// 1e-12 relative. Before, S was sigma1 + sigma2 (the mean of the two sides) and dS/dv 0.
#[test]
fn lugre_slope_and_derivatives_at_rest_are_those_of_positive_velocity() {
    let sigma2 = 5.0;
    let (sigma0, sigma1, normal) = (1e7, 1e3, 100.0);
    let g = exponential();
    let g0 = g.static_coefficient * normal;
    let g0_slope = -g.decay * (g.static_coefficient - g.kinetic_coefficient) * normal;
    for version in VERSIONS {
        let (f, _) = initialised(
            version,
            NeuralFrictionLaw::LUGRE,
            &[],
            &[("friction.lugre.viscous_damping", sigma2)],
        );
        let mut f = f.unwrap();
        set_velocity(&mut f, 0.02);
        steps(&mut f, version, 0.0, 1e-4, 3);
        set_velocity(&mut f, 0.0);
        let z = real(&mut f, "bristle_deflection");
        let expected_slope = sigma1 * (1.0 - sigma0 * z / g0) + sigma2;
        let slope = real(&mut f, "friction_force_slope");
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * y.abs();
        assert!(
            close(slope, expected_slope),
            "{version:?}: {slope} vs {expected_slope}"
        );
        let unknowns = [
            vr::<NeuralFriction>("friction_force"),
            vr::<NeuralFriction>("friction_force_slope"),
        ];
        let derivative = |f: &mut Instance<NeuralFriction>, input: &str| {
            let mut out = [0.0; 2];
            f.get_directional_derivative(
                &unknowns,
                &[vr::<NeuralFriction>(input)],
                &[1.0],
                &mut out,
            )
            .unwrap();
            out
        };
        let along_v = derivative(&mut f, "sliding_velocity");
        let along_normal = derivative(&mut f, "normal_force");
        assert!(
            close(along_v[0], expected_slope),
            "{version:?}: {along_v:?}"
        );
        let expected_curvature = 2.0 * sigma1 * sigma0 * z * g0_slope / (g0 * g0);
        assert!(
            close(along_v[1], expected_curvature),
            "{version:?}: {along_v:?} vs {expected_curvature}"
        );
        assert_eq!(along_normal[0], 0.0);
        let expected_slope_normal = sigma1 * sigma0 * z / (g0 * normal);
        assert!(
            close(along_normal[1], expected_slope_normal),
            "{version:?}: {along_normal:?}"
        );
    }
}

/// The directional derivatives at a committed state away from the initial one (3 steps
/// of 1e-4 s at 0.02 m/s: the state mid-transient) against central differences of the
/// outputs read with no step between. Relative steps 1e-6 of each input: truncation
/// ~1e-12 and rounding ~eps |F| / (1e-6 x) ~1e-10 of the derivative's scale for these
/// smooth laws (away from v = 0), so 1e-6 relative (plus 1e-9 absolute, for zeros)
/// bounds both with room.
#[test]
fn directional_derivatives_at_the_committed_state_match_central_differences() {
    let outputs = [
        "friction_force",
        "friction_force_slope",
        "friction_coefficient",
    ];
    let inputs = ["sliding_velocity", "normal_force"];
    for version in VERSIONS {
        for law in [NeuralFrictionLaw::LUGRE, NeuralFrictionLaw::RATE_AND_STATE] {
            let (f, _) = initialised(version, law, &[], &[]);
            let mut f = f.unwrap();
            set_velocity(&mut f, 2e-2);
            steps(&mut f, version, 0.0, 1e-4, 3);
            for (v, normal) in [(0.01, 100.0), (0.03, 80.0), (-0.02, 120.0)] {
                let x: [f64; 2] = [v, normal];
                let set = |f: &mut Instance<NeuralFriction>, x: [f64; 2]| {
                    f.set_real(
                        &[
                            vr::<NeuralFriction>("sliding_velocity"),
                            vr::<NeuralFriction>("normal_force"),
                        ],
                        &x,
                    )
                    .unwrap();
                };
                for (j, input) in inputs.iter().enumerate() {
                    let h = 1e-6 * x[j].abs();
                    let mut read = |t: f64| -> Vec<f64> {
                        let mut p = x;
                        p[j] += t * h;
                        set(&mut f, p);
                        outputs.iter().map(|o| real(&mut f, o)).collect()
                    };
                    let (up, down) = (read(1.0), read(-1.0));
                    set(&mut f, x);
                    let unknowns: Vec<u32> =
                        outputs.iter().map(|o| vr::<NeuralFriction>(o)).collect();
                    let mut exact = vec![0.0; outputs.len()];
                    f.get_directional_derivative(
                        &unknowns,
                        &[vr::<NeuralFriction>(input)],
                        &[1.0],
                        &mut exact,
                    )
                    .unwrap();
                    for (o, name) in outputs.iter().enumerate() {
                        let central = (up[o] - down[o]) / (2.0 * h);
                        assert!(
                            (exact[o] - central).abs()
                                <= 1e-6 * exact[o].abs().max(central.abs()) + 1e-9,
                            "{version:?} {law:?} d {name} / d {input} at {x:?}: {} vs {central}",
                            exact[o]
                        );
                    }
                }
            }
        }
    }
}
