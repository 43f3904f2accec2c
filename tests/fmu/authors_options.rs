//! The paper authors' scene options as StickSlipBeam parameters: set through the FMU,
//! they give the library's `paper-authors` run bit for bit, and the preload's
//! breakaway is the analytical one.

use std::path::PathBuf;
use stickslip::choice::Choice;
use stickslip::law_source::LawSource;
use stickslip::scene::{FidelityLevel, Scene};
use stickslip::scene_preset::ScenePreset;
use stickslip::simulation::Simulator;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::instance::Instance;
use stickslip_tests::vr;

fn resources() -> PathBuf {
    stickslip_tests::weights_dir()
}

/// The preset's options, each set through its own parameter.
fn authors_beam(preset: &Scene) -> Instance<StickSlipBeam> {
    let mut b: Instance<StickSlipBeam> =
        Instance::new("beam", Some(&resources()), false, Box::new(|_, _, _| {})).unwrap();
    b.setup_experiment(0.0, Some(1.2)).unwrap();
    let c = &preset.contact;
    let choices = [
        ("fidelity.level", FidelityLevel::Beam.code()),
        ("contact.initial_state", c.initial_state.code()),
        ("contact.holding_force", c.holding_force.code()),
        ("contact.tip_velocity", c.tip_velocity.code()),
        ("contact.damping_phase", c.damping_phase.code()),
        ("contact.first_slip_step", c.first_slip_step.code()),
        ("contact.slip_force", c.slip_force.code()),
    ];
    for (name, code) in choices {
        b.set_integer(&[vr::<StickSlipBeam>(name)], &[code])
            .unwrap();
    }
    let reals = [
        ("contact.preload", c.preload),
        (
            "damping.mass_proportional",
            preset.damping.mass_proportional,
        ),
        (
            "damping.stiffness_proportional",
            preset.damping.stiffness_proportional,
        ),
    ];
    for (name, value) in reals {
        b.set_real(&[vr::<StickSlipBeam>(name)], &[value]).unwrap();
    }
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    b
}

#[test]
fn the_authors_options_set_through_the_fmu_are_the_presets_run_bit_for_bit() {
    let mut preset = ScenePreset::PaperAuthors.scene();
    let mut b = authors_beam(&preset);
    preset.fidelity.level = FidelityLevel::Beam;
    let scene = preset.check().unwrap();
    let law = LawSource::resolve(&scene).unwrap().law().unwrap();
    let mut sim = Simulator::new(scene, law).unwrap();
    let tip = vr::<StickSlipBeam>("tip_deflection");
    let h = 1e-3;
    let mut first_slip = None;
    for k in 0..600 {
        b.do_step(k as f64 * h, h).unwrap();
        for _ in 0..10 {
            sim.step().unwrap();
        }
        let mut out = [0.0];
        b.get_real(&[tip], &mut out).unwrap();
        assert_eq!(
            out[0],
            sim.sample().tip_deflection,
            "communication point {k}"
        );
        if first_slip.is_none() && !sim.sample().stick {
            first_slip = Some((k + 1) as f64 * h);
        }
    }
    // Breakaway (mu_s F_n - P) / (k v_b) = 0.396 s, seen at the first communication
    // point after it: within one communication step h after it, give or take the one
    // internal step dt = 1e-4 s in which the switch is detected.
    let t_b = 0.396;
    let t = first_slip.expect("the beam breaks away");
    assert!(
        t >= t_b - 1e-4 && t <= t_b + h + 1e-4,
        "first slip seen at {t} s"
    );
}
