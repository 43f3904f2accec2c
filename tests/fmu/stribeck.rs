//! The registry's example law, Stribeck with viscous friction, in both FMUs with no code
//! of their own for it: NeuralFriction's `law = stribeck` gives the law's force, slope
//! and Jacobian at its inputs, with its parameters set through the variables the
//! registry declares; StickSlipBeam's `friction.law = stribeck` runs the library's
//! simulation bit for bit.

use crate::friction_laws::{initialised, real, set_velocity};
use stickslip::choice::Choice;
use stickslip::friction::registry::Coefficients;
use stickslip::friction::stribeck::{self, StribeckLaw};
use stickslip::friction::{FrictionLaw, FrictionLawKind};
use stickslip::law_source::LawSource;
use stickslip::scene::{CheckedScene, FidelityLevel};
use stickslip::simulation::Simulator;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::{NeuralFriction, NeuralFrictionLaw};
use stickslip_fmi::instance::{FmiVersion, Instance};
use stickslip_tests::vr;

/// NeuralFriction's `law = stribeck` (its code from the registry).
fn law() -> NeuralFrictionLaw {
    NeuralFrictionLaw::of(FrictionLawKind::Stribeck).expect("NeuralFriction evaluates it")
}

#[test]
fn neural_friction_evaluates_the_law_with_its_parameters_and_jacobian() {
    for version in [FmiVersion::V2, FmiVersion::V3] {
        let reals = [
            ("static_coefficient", 0.6),
            ("kinetic_coefficient", 0.25),
            ("friction.stribeck.stribeck_velocity", 0.05),
            ("friction.stribeck.viscous_coefficient", 30.0),
        ];
        let (f, _) = initialised(version, law(), &[], &reals);
        let mut f = f.unwrap();
        let coefficients = Coefficients {
            static_coefficient: 0.6,
            kinetic_coefficient: 0.25,
            decay: 5.0,
        };
        let mut law = StribeckLaw::new(&coefficients, &[0.05, 30.0]);
        let normal = real(&mut f, "normal_force");
        for v in [-0.2, -0.03, 1e-4, 0.035, 0.3] {
            set_velocity(&mut f, v);
            let j = law.jacobian(v, normal).unwrap();
            assert_eq!(real(&mut f, "friction_force"), j.force, "v {v}");
            assert_eq!(real(&mut f, "friction_force_slope"), j.slope, "v {v}");
            // d(friction_force)/d(sliding_velocity, normal_force) and
            // d(friction_force_slope)/d(sliding_velocity): the law's Jacobian.
            let force = [vr::<NeuralFriction>("friction_force")];
            let slope = [vr::<NeuralFriction>("friction_force_slope")];
            let velocity = [vr::<NeuralFriction>("sliding_velocity")];
            let normal_force = [vr::<NeuralFriction>("normal_force")];
            let mut d = [0.0];
            f.get_directional_derivative(&force, &velocity, &[1.0], &mut d)
                .unwrap();
            assert_eq!(d[0], j.force_gradient[0]);
            f.get_directional_derivative(&force, &normal_force, &[1.0], &mut d)
                .unwrap();
            assert_eq!(d[0], j.force_gradient[1]);
            f.get_directional_derivative(&slope, &velocity, &[1.0], &mut d)
                .unwrap();
            assert_eq!(d[0], j.slope_gradient[0]);
        }
        // The static limit is mu_s F_n: the law has no presliding of its own.
        assert_eq!(real(&mut f, "static_limit"), 0.6 * normal);
    }
}

#[test]
fn a_parameter_out_of_range_is_refused_by_its_name() {
    let (f, log) = initialised(
        FmiVersion::V2,
        law(),
        &[],
        &[("friction.stribeck.stribeck_velocity", 0.0)],
    );
    assert!(f.is_err());
    let said = log.lock().unwrap().join("\n");
    assert!(
        said.contains("friction.stribeck.stribeck_velocity") && said.contains("> 0 (m/s)"),
        "{said}"
    );
}

#[test]
fn the_beam_fmu_runs_the_law_as_the_library_does() {
    let logger = Box::new(|_, _: &str, _: &str| {});
    let mut b: Instance<StickSlipBeam> =
        Instance::new("beam", Some(&stickslip_tests::weights_dir()), false, logger).unwrap();
    b.setup_experiment(0.0, Some(1.2)).unwrap();
    b.set_integer(
        &[
            vr::<StickSlipBeam>("fidelity.level"),
            vr::<StickSlipBeam>("friction.law"),
        ],
        &[FidelityLevel::Beam.code(), FrictionLawKind::Stribeck.code()],
    )
    .unwrap();
    b.set_real(
        &[vr::<StickSlipBeam>("friction.stribeck.viscous_coefficient")],
        &[15.0],
    )
    .unwrap();
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    let mut scene = CheckedScene::paper().into_scene();
    scene.fidelity.level = FidelityLevel::Beam;
    scene.time.end = 1.2;
    scene.friction.law = FrictionLawKind::Stribeck;
    scene
        .friction
        .laws
        .set(&stribeck::VISCOUS_COEFFICIENT, 15.0);
    let scene = scene.check().unwrap();
    let mut sim = Simulator::new(
        scene.clone(),
        LawSource::resolve(&scene).unwrap().law().unwrap(),
    )
    .unwrap();
    let tip = [vr::<StickSlipBeam>("tip_deflection")];
    let mut last = 0.0;
    for k in 0..800 {
        let t = k as f64 * 1e-3;
        b.do_step(t, 1e-3).unwrap();
        let mut out = [0.0];
        b.get_real(&tip, &mut out).unwrap();
        sim.advance_to(t + 1e-3).unwrap();
        assert_eq!(out[0], sim.sample().tip_deflection, "at step {k}");
        last = out[0];
    }
    // It slipped: the tip left the belt's line u = v_b t.
    assert!((last - 0.02 * 0.8).abs() > 1e-4, "{last}");
}
