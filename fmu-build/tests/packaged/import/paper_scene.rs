//! a. The paper scene through the FMU equals the library's simulation bit for bit, also
//! from a later start time and at communication steps off the internal grid.

use super::*;

// a. The paper scene through the FMU equals the library's simulation bit for bit.

/// `level` set in the FMU and in the library's scene; None: both keep their default,
/// plane stress.
fn paper_scene_equals_library(level: Option<FidelityLevel>, tag: &str) {
    let import = import(FmuKind::StickSlipBeam);
    let name = format!("paper-{tag}");
    let vrs = BeamVrs::of(&import);
    let parameters: Vec<(u32, i32)> = level
        .map(|l| (vrs.fidelity, l.code()))
        .into_iter()
        .collect();
    let mut beam = Beam::start(&import, &name, &parameters);
    let expected_level = level.unwrap_or(FidelityLevel::PlaneStress);
    assert_eq!(beam.integer(vrs.fidelity), expected_level.code());
    Common::set_debug_logging(&mut beam.inst, true, &["logEvents"]).expect("logEvents on");

    let started = std::time::Instant::now();
    let fmu = beam.run_from_start(STEPS);
    let fmu_time = started.elapsed();
    let (advanced, sim) = direct_advance_to(level);
    let stepped = direct_steps(level);

    assert_bitwise(&format!("{tag}: FMU vs advance_to"), &fmu, &advanced);
    assert_bitwise(&format!("{tag}: step() vs advance_to"), &stepped, &advanced);

    // The run is not trivial: the beam deflects to ~8.4 mm and slips several times.
    let peak = fmu.iter().map(|o| o.tip_deflection).fold(0.0, f64::max);
    assert!(
        (8.0e-3..9.0e-3).contains(&peak),
        "{tag}: peak tip deflection {peak} m"
    );
    assert!(
        fmu[STEPS].transitions >= 10,
        "{tag}: only {} transitions",
        fmu[STEPS].transitions
    );

    // Breakaway: the library's first transition is stick -> slip at 0.4000 s, and the
    // FMU's first communication point in slip is the first one at or after it.
    let first = sim.transitions()[0];
    assert_eq!(first.to, ContactState::Slip);
    assert!(
        (first.time - BREAKAWAY).abs() < 0.5e-4,
        "{tag}: library breakaway at {} s",
        first.time
    );
    let points = communication_points(STEPS);
    let k = first_slip(&fmu);
    assert!(
        points[k - 1] < first.time && first.time <= points[k] + 1e-12,
        "{tag}: first slip at communication point {} s, transition at {} s",
        points[k],
        first.time
    );
    assert!(
        (points[k] - BREAKAWAY).abs() <= H * (1.0 + 1e-9),
        "{tag}: FMU breakaway at {} s",
        points[k]
    );

    // logEvents reports every transition, with the library's times.
    let events: Vec<String> = messages_of(&name)
        .into_iter()
        .filter(|(level, _)| *level == log::Level::Info)
        .map(|(_, text)| text)
        .collect();
    let expected: Vec<String> = sim
        .transitions()
        .iter()
        .map(|t| {
            let to = match t.to {
                ContactState::Stick => "stick",
                ContactState::Slip => "slip",
            };
            format!("t = {:.6} s: {to}", t.time)
        })
        .collect();
    assert_eq!(events, expected, "{tag}: logEvents messages");

    Common::terminate(&mut beam.inst).expect("fmi2Terminate");
    println!(
        "{tag}: {} points bitwise equal (advance_to and step()); FMU breakaway at {:.3} s, library transition at {:.6} s; peak {:.4} mm; {} transitions; FMU run {:.3} s",
        fmu.len(),
        points[k],
        first.time,
        peak * 1e3,
        fmu[STEPS].transitions,
        fmu_time.as_secs_f64()
    );
}

#[test]
fn a_paper_scene_beam_fidelity_equals_library_bit_for_bit() {
    paper_scene_equals_library(Some(FidelityLevel::Beam), "beam");
}

#[test]
fn a_paper_scene_modal_fidelity_equals_library_bit_for_bit() {
    paper_scene_equals_library(Some(FidelityLevel::Modal), "modal");
}

#[test]
fn a_paper_scene_default_plane_stress_equals_library_bit_for_bit() {
    paper_scene_equals_library(None, "plane-stress");
}

/// The FMU's time is absolute, the simulation's relative to the start time: a start at
/// 10 s changes no output. A communication step off the internal grid (2.5e-4 s = 2.5
/// internal steps) ends with a shorter landing step, as `advance_to` does.
#[test]
fn a_start_time_and_off_grid_communication_steps_equal_library() {
    let import = import(FmuKind::StickSlipBeam);
    let vrs = BeamVrs::of(&import);
    let (direct, _) = direct_advance_to(Some(FidelityLevel::Beam));

    let mut inst = import
        .instantiate_cs("start-at-10", false, false)
        .expect("fmi2Instantiate");
    inst.setup_experiment(None, 10.0, Some(10.0 + STOP))
        .expect("fmi2SetupExperiment");
    Common::enter_initialization_mode(&mut inst).expect("fmi2EnterInitializationMode");
    inst.set_integer(&[vrs.fidelity], &[FidelityLevel::Beam.code()])
        .expect("fmi2SetInteger");
    Common::exit_initialization_mode(&mut inst).expect("fmi2ExitInitializationMode");
    let mut shifted = Beam {
        inst,
        vr: vrs,
        t: 10.0,
    };
    let run = shifted.run_from_start(STEPS);
    assert_bitwise("start time 10 s vs library from 0", &run, &direct);

    let h = 2.5e-4;
    let mut beam = Beam::start(
        &import,
        "off-grid",
        &[(vrs.fidelity, FidelityLevel::Beam.code())],
    );
    let mut sim = direct_simulator(Some(FidelityLevel::Beam));
    let mut t = 0.0;
    let (mut fmu, mut library) = (Vec::new(), Vec::new());
    for _ in 0..(STOP / h).round() as usize {
        beam.inst.do_step(t, h, true).expect("fmi2DoStep");
        t += h;
        sim.advance_to(t).expect("advance_to");
        fmu.push(beam.outputs());
        library.push(Outputs::of_simulator(&sim));
    }
    assert_bitwise("h = 2.5e-4 s vs library advance_to", &fmu, &library);
    // Landing steps change the discretisation, so this is a different (close) run.
    let last = fmu.last().expect("points").tip_deflection;
    assert_ne!(last.to_bits(), direct[STEPS].tip_deflection.to_bits());
    assert!(first_slip(&fmu) > 0);
}
