//! The packaged FMI 3.0 FMUs (`target/fmu/3.0/*.fmu`) imported with the `fmi` crate
//! (feature `fmi3`): their descriptions parse and carry the instantiation token of this
//! source tree, and StickSlipBeam's outputs equal the FMI 2.0 FMU's bit for bit at the
//! same settings (the same library and tables behind both interfaces; without event
//! mode or early return an FMI 3.0 step is an FMI 2.0 step).
//!
//! A child of `import`, so it reuses its helpers (`Beam`, `Outputs`, `assert_bitwise`).

use super::*;
use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::instance::InstanceCS as InstanceCS3;
use fmi::fmi3::{CoSimulation as _, Common as _, Fmi3Model, GetSet};

/// The packaged FMI 3.0 FMU of `kind`, imported; fails (does not skip) when missing.
fn import3(kind: FmuKind) -> Fmi3Import {
    install_logger();
    let path = fmu_build::fmu3_path(kind);
    assert!(
        path.is_file(),
        "{} is missing: run `cargo run --release -p fmu-build` first",
        path.display()
    );
    let import: Fmi3Import = fmi::import::from_path(&path)
        .unwrap_or_else(|e| panic!("cannot import {}: {e}", path.display()));
    let md = import.model_description();
    assert_eq!(
        md.instantiation_token,
        kind.guid(),
        "{} is stale: run `cargo run --release -p fmu-build` first",
        path.display()
    );
    assert_eq!(md.fmi_version, "3.0");
    assert_eq!(
        md.co_simulation
            .as_ref()
            .map(|cs| cs.model_identifier.as_str()),
        Some(kind.model_identifier())
    );
    import
}

/// An FMI 3.0 StickSlipBeam instance, initialised for [0, STOP], stepped by `H`.
struct Beam3 {
    inst: InstanceCS3,
    vr: BeamVrs,
    t: f64,
}

impl Beam3 {
    fn start(import: &Fmi3Import, name: &str, vr: BeamVrs, integers: &[(u32, i32)]) -> Self {
        let mut inst = import
            .instantiate_cs(name, false, false, false, false, &[])
            .unwrap_or_else(|e| panic!("{name}: fmi3InstantiateCoSimulation failed: {e}"));
        inst.enter_initialization_mode(None, 0.0, Some(STOP))
            .expect("fmi3EnterInitializationMode");
        for &(vr, value) in integers {
            inst.set_int32(&[vr], &[value])
                .unwrap_or_else(|e| panic!("fmi3SetInt32({vr}, {value}): {e}"));
        }
        inst.exit_initialization_mode()
            .expect("fmi3ExitInitializationMode");
        Self { inst, vr, t: 0.0 }
    }

    fn outputs(&mut self) -> Outputs {
        let mut r = [0.0; 5];
        self.inst
            .get_float64(&self.vr.reals, &mut r)
            .expect("fmi3GetFloat64");
        let mut stick = [false; 1];
        self.inst
            .get_boolean(&[self.vr.stick], &mut stick)
            .expect("fmi3GetBoolean");
        let mut transitions = [0i32; 1];
        self.inst
            .get_int32(&[self.vr.transitions], &mut transitions)
            .expect("fmi3GetInt32");
        Outputs {
            tip_deflection: r[0],
            tip_velocity: r[1],
            relative_velocity: r[2],
            friction_force: r[3],
            holding_force: r[4],
            stick: stick[0],
            transitions: transitions[0],
        }
    }

    fn step(&mut self) {
        let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
        self.inst
            .do_step(
                self.t,
                H,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
            .unwrap_or_else(|e| panic!("fmi3DoStep at t = {} s: {e}", self.t));
        // No event mode, never terminates by itself, never returns early.
        assert!(!event && !terminate && !early);
        assert_eq!(last, self.t + H, "lastSuccessfulTime");
        self.t += H;
    }

    fn run_from_start(&mut self, n: usize) -> Vec<Outputs> {
        let mut out = vec![self.outputs()];
        for _ in 0..n {
            self.step();
            out.push(self.outputs());
        }
        out
    }
}

#[test]
fn i_fmi3_descriptions_parse_with_the_token_of_this_source() {
    for kind in FmuKind::ALL {
        import3(kind);
    }
}

/// The paper scene at modal and beam fidelity with the exponential and the neural law:
/// FMI 3.0 and FMI 2.0 give the same bits at every communication point.
#[test]
fn i_fmi3_beam_equals_the_fmi2_fmu_bit_for_bit() {
    const N: usize = 600; // 0.6 s: the breakaway at 0.4 s and the first slip
    let import2 = import(FmuKind::StickSlipBeam);
    let import3 = import3(FmuKind::StickSlipBeam);
    let vrs = BeamVrs::of(&import2);
    for level in [FidelityLevel::Modal, FidelityLevel::Beam] {
        for law in [FrictionLawKind::Exponential, FrictionLawKind::Neural] {
            let tag = format!("fmi3-{}-{}", level.name(), law.name());
            let integers = [(vrs.fidelity, level.code()), (vrs.friction_law, law.code())];
            let two = Beam::start(&import2, &format!("{tag}-2"), &integers).run_from_start(N);
            let three =
                Beam3::start(&import3, &format!("{tag}-3"), vrs, &integers).run_from_start(N);
            assert!(
                two[N].transitions >= 1,
                "{tag}: no stick/slip in the window"
            );
            assert_bitwise(&format!("{tag}: FMI 3.0 vs FMI 2.0"), &three, &two);
        }
    }
}

/// NeuralFriction's extra features: in FMI 3.0 one `Float64` input array,
/// `extra_feature` (value reference 16, `<Dimension start="4"/>`), read as such by the
/// `fmi` crate; set through it, a network of six features (the paper's with four more
/// inputs that every first-layer unit reads) gives every output bit for bit what the FMI
/// 2.0 FMU gives with the same values set through `extra_feature[1..4]`.
#[test]
fn i_fmi3_extra_features_are_one_array_and_reach_the_network() {
    use std::ffi::CString;
    let import2 = import(FmuKind::NeuralFriction);
    let import3 = import3(FmuKind::NeuralFriction);
    let array = import3
        .model_description()
        .model_variables
        .float64()
        .into_iter()
        .find(|v| v.name == "extra_feature")
        .expect("extra_feature in the FMI 3.0 description");
    assert_eq!(array.value_reference, 16);
    assert_eq!(
        array
            .dimensions
            .iter()
            .map(|d| d.as_fixed())
            .collect::<Vec<_>>(),
        [Some(4)]
    );
    assert_eq!(
        array.start.as_ref().map(|s| s.0.clone()),
        Some(vec![0.0; 4])
    );
    let weights = stickslip_tests::six_feature_weights("import3");
    let weights = CString::new(weights.to_str().unwrap()).unwrap();
    let fvrs = FrictionVrs::of(&import2);
    let weights_vr = vr(&import2, "weights");
    let elements: Vec<u32> = (1..=4)
        .map(|k| vr(&import2, &format!("extra_feature[{k}]")))
        .collect();
    let (velocity, normal) = (0.05, 100.0);
    let features = [0.3, -0.6, 0.8, -0.1];

    let mut two = import2
        .instantiate_cs("features-2", false, false)
        .expect("fmi2Instantiate");
    two.setup_experiment(None, 0.0, Some(STOP))
        .expect("fmi2SetupExperiment");
    Common::enter_initialization_mode(&mut two).expect("fmi2EnterInitializationMode");
    two.set_integer(&[fvrs.law], &[NeuralFrictionLaw::NEURAL.code()])
        .expect("law");
    two.set_string(&[weights_vr], std::slice::from_ref(&weights))
        .expect("weights");
    Common::exit_initialization_mode(&mut two).expect("fmi2ExitInitializationMode");
    two.set_real(&elements, &features)
        .expect("extra_feature[1..4]");
    let out2 = friction_at(&mut two, &fvrs, velocity, normal);

    let mut three = import3
        .instantiate_cs("features-3", false, false, false, false, &[])
        .expect("fmi3InstantiateCoSimulation");
    three
        .enter_initialization_mode(None, 0.0, Some(STOP))
        .expect("fmi3EnterInitializationMode");
    three
        .set_int32(&[fvrs.law], &[NeuralFrictionLaw::NEURAL.code()])
        .expect("law");
    three
        .set_string(&[weights_vr], std::slice::from_ref(&weights))
        .expect("weights");
    three
        .exit_initialization_mode()
        .expect("fmi3ExitInitializationMode");
    // One request of three variables and six values: velocity, the array, normal force.
    let mut values = vec![velocity];
    values.extend(features);
    values.push(normal);
    three
        .set_float64(&[fvrs.sliding_velocity, 16, fvrs.normal_force], &values)
        .expect("fmi3SetFloat64 with the array");
    let mut out3 = [0.0; 4];
    three
        .get_float64(&fvrs.outputs, &mut out3)
        .expect("fmi3GetFloat64");
    let mut read = [0.0; 4];
    three.get_float64(&[16], &mut read).expect("the array");
    assert_eq!(read, features);
    assert_eq!(
        out2.map(f64::to_bits),
        out3.map(f64::to_bits),
        "{out2:?} vs {out3:?}"
    );

    // The features reach the network: zeros give another force.
    two.set_real(&elements, &[0.0; 4]).expect("zeros");
    let zeros = friction_at(&mut two, &fvrs, velocity, normal);
    println!(
        "friction_force {} N with the features (FMI 3.0 = FMI 2.0), {} N with zeros",
        out3[0], zeros[0]
    );
    assert!((out3[0] - zeros[0]).abs() > 1e-3 * zeros[0].abs());
    let _ = std::fs::remove_file(weights.to_str().unwrap());
}

/// The event capability flags in the packaged descriptions, and StickSlipBeam instantiated
/// with eventModeUsed and earlyReturnAllowed through the `fmi` crate: Event Mode after
/// initialisation, a step of 7 ms that returns early at the breakaway, where the FMI 2.0
/// FMU stepped at 1 ms records its first transition, with the same outputs bit for bit
/// (the same internal steps up to it), then Event Mode and on through further switches.
#[test]
fn i_fmi3_beam_returns_early_at_a_switch_and_handles_event_mode() {
    for kind in FmuKind::ALL {
        let import = import3(kind);
        let cs = import.model_description().co_simulation.as_ref().unwrap();
        assert_eq!(cs.has_event_mode, Some(true), "{kind:?}");
        assert_eq!(
            cs.might_return_early_from_do_step,
            Some(kind == FmuKind::StickSlipBeam),
            "{kind:?}"
        );
        assert_eq!(cs.can_handle_variable_communication_step_size, Some(true));
    }
    let import2 = import(FmuKind::StickSlipBeam);
    let import3 = import3(FmuKind::StickSlipBeam);
    let vrs = BeamVrs::of(&import2);
    let integers = [(vrs.fidelity, FidelityLevel::Modal.code())];
    let two = Beam::start(&import2, "events-2", &integers).run_from_start(600);
    let k = two
        .iter()
        .position(|o| o.transitions >= 1)
        .expect("no transition within 0.6 s");

    let mut inst = import3
        .instantiate_cs("events-3", false, false, true, true, &[])
        .expect("fmi3InstantiateCoSimulation with eventModeUsed and earlyReturnAllowed");
    inst.enter_initialization_mode(None, 0.0, Some(STOP))
        .expect("fmi3EnterInitializationMode");
    inst.set_int32(&[vrs.fidelity], &[FidelityLevel::Modal.code()])
        .expect("fmi3SetInt32");
    inst.exit_initialization_mode()
        .expect("fmi3ExitInitializationMode");
    // In Event Mode: one update settles everything, no time event.
    let settle = |inst: &mut InstanceCS3| {
        let mut flags = fmi::EventFlags::default();
        inst.update_discrete_states(&mut flags)
            .expect("fmi3UpdateDiscreteStates");
        assert_eq!(flags, fmi::EventFlags::default());
        inst.enter_step_mode().expect("fmi3EnterStepMode");
    };
    settle(&mut inst);
    let mut beam = Beam3 {
        inst,
        vr: vrs,
        t: 0.0,
    };
    let h = 7.0 * H;
    let (mut switches, mut early_returns) = (Vec::new(), 0);
    let mut at_first_switch = None;
    while beam.t < 0.6 {
        let target = beam.t + h;
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, f64::NAN);
        beam.inst
            .do_step(
                beam.t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
            .unwrap_or_else(|e| panic!("fmi3DoStep at t = {} s: {e}", beam.t));
        assert!(!terminate);
        if early {
            assert!(event, "an early return is an event with eventModeUsed");
            assert!(
                last > beam.t && last < target,
                "{} < {last} < {target}",
                beam.t
            );
            early_returns += 1;
        } else {
            assert_eq!(last, target);
        }
        beam.t = last;
        if event {
            switches.push(last);
            if at_first_switch.is_none() {
                at_first_switch = Some(beam.outputs());
            }
            beam.inst.enter_event_mode().expect("fmi3EnterEventMode");
            settle(&mut beam.inst);
        }
    }
    let first = switches.first().copied().expect("no switch within 0.6 s");
    assert!(
        (first - k as f64 * H).abs() < 1e-9,
        "first switch at {first} s, FMI 2.0 records it at {} s",
        k as f64 * H
    );
    assert_bitwise(
        "outputs at the early return vs FMI 2.0 at the same time",
        &[at_first_switch.unwrap()],
        &two[k..=k],
    );
    assert!(early_returns >= 1 && switches.len() >= 2, "{switches:?}");
}

/// The CalculiX beam exported for FMI 3.0 (`stickslip export-fmu --fmi 3.0`) runs as the
/// library runs the scene file, bit for bit, to 0.5 s.
#[test]
fn i_fmi3_export_of_the_calculix_beam_equals_the_library() {
    use super::export::{export_as, library_run, EXPORT_STEPS};
    let scene = fmu_build::workspace_root().join("examples/calculix-beam/scene.toml");
    // The value references are the table's: read from the FMI 2.0 export.
    let import2: Fmi2Import = fmi::import::from_path(export_as(&scene, "CalculixBeamTwo", 2))
        .expect("the FMI 2.0 export imports");
    let vrs = BeamVrs::of(&import2);
    install_logger();
    let fmu = export_as(&scene, "CalculixBeamThree", 3);
    let import: Fmi3Import = fmi::import::from_path(&fmu).expect("the FMI 3.0 export imports");
    assert_eq!(import.model_description().fmi_version, "3.0");
    let three = Beam3::start(&import, "export-fmi3", vrs, &[]).run_from_start(EXPORT_STEPS);
    assert_bitwise(
        "FMI 3.0 export of the CalculiX beam against the library",
        &three,
        &library_run(&scene, EXPORT_STEPS),
    );
}

/// The sensors of the CalculiX beam exported for FMI 3.0 (full model) equal the
/// library's readings bit for bit at every communication point to 0.5 s, read with
/// fmi3GetFloat64 among the table's outputs.
#[test]
fn i_fmi3_exported_sensors_equal_the_library() {
    use super::export::{
        export_as, library_run, library_sensors, sensor_scene, sensor_vrs, EXPORT_STEPS,
    };
    let scene = sensor_scene("SensorsThree", "plane-stress");
    let import2: Fmi2Import =
        fmi::import::from_path(export_as(&scene, "SensorsThreeTwo", 2)).unwrap();
    let vrs = BeamVrs::of(&import2);
    let fmu = export_as(&scene, "SensorsThree", 3);
    let sensors = sensor_vrs(&fmu, 3);
    install_logger();
    let import: Fmi3Import = fmi::import::from_path(&fmu).expect("the FMI 3.0 export imports");
    let mut beam = Beam3::start(&import, "sensors-fmi3", vrs, &[]);
    let read = |beam: &mut Beam3| {
        let mut values = vec![0.0; sensors.len()];
        beam.inst
            .get_float64(&sensors, &mut values)
            .expect("fmi3GetFloat64");
        values
    };
    let mut outputs = vec![beam.outputs()];
    let mut readings = vec![read(&mut beam)];
    for _ in 0..EXPORT_STEPS {
        beam.step();
        outputs.push(beam.outputs());
        readings.push(read(&mut beam));
    }
    assert_bitwise(
        "FMI 3.0 sensor export against the library",
        &outputs,
        &library_run(&scene, EXPORT_STEPS),
    );
    let bits = |rows: &[Vec<f64>]| -> Vec<Vec<u64>> {
        rows.iter()
            .map(|r| r.iter().map(|v| v.to_bits()).collect())
            .collect()
    };
    assert_eq!(
        bits(&readings),
        bits(&library_sensors(&scene, EXPORT_STEPS)),
        "FMI 3.0 sensors"
    );
}
