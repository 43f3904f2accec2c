//! f. Coupled: StickSlipBeam (friction.law = external) + NeuralFriction (exponential)
//! against the monolithic run.

use super::*;

// f. Coupled: StickSlipBeam (friction.law = external) + NeuralFriction (exponential).

/// How far the coupled tip deflection may stray from the monolithic run (m), up to the
/// second major slip (0.7051 s). The coupling holds the kinetic force of t_k over
/// [t_k, t_k + h] (zero-order hold), a first-order error: measured 45.6, 22.9, 9.3 and
/// 4.9 um at h = 1e-3, 5e-4, 2e-4 and 1e-4 s over the first major slip. 0.1 mm is twice
/// the h = 1e-3 s value. A coupling that passes a 5 % wrong kinetic force or static
/// limit is off by 1.34 mm or 0.71 mm here (measured), so both fail.
const COUPLED_TOLERANCE_FIRST_SLIP: f64 = 0.1e-3;

/// The same over the whole run to 1.2 s. Measured 0.222 mm (at 1.033 s). After the first
/// slip the deviation is no longer first order in h (0.25 mm at h = 5e-4 s, 0.09 mm at
/// 1e-4 s): the slip ends in bursts of re-stick and slip whose count and timing are
/// sensitive to any perturbation (35 transitions coupled, 33 monolithic), and each
/// moved burst shifts the following sawtooth a little. 0.5 mm (6 % of the 8.4 mm peak)
/// holds the measurement with a factor two and still fails a 5 % wrong kinetic force
/// or static limit (both 1.62 mm off over the run, measured).
const COUPLED_TOLERANCE: f64 = 0.5e-3;

/// Communication points up to (excluding) the second major slip at 0.7051 s.
const FIRST_SLIP_END: usize = 700;

#[test]
fn f_coupled_with_neural_friction_fmu_matches_the_monolithic_run() {
    let beam_import = import(FmuKind::StickSlipBeam);
    let friction_import = import(FmuKind::NeuralFriction);
    let vrs = BeamVrs::of(&beam_import);
    let fvrs = FrictionVrs::of(&friction_import);
    let mut beam = Beam::start(
        &beam_import,
        "coupled-beam",
        &[
            (vrs.fidelity, FidelityLevel::Beam.code()),
            (vrs.friction_law, FrictionLawKind::External.code()),
        ],
    );
    let mut friction = start_friction(
        &friction_import,
        "coupled-friction",
        Some(NeuralFrictionLaw::EXPONENTIAL),
    );
    let friction_outputs = [fvrs.outputs[1], fvrs.outputs[3]];

    // Gauss-Seidel at each point t_k: the beam's v_rel(t_k) goes through NeuralFriction
    // (direct feedthrough, no state) and its force back into the beam, then both step
    // to t_k + h. (python-checks/stickslip_checks/cosim_convergence.py compares this
    // with one-pass Jacobi, where the beam gets the force of v_rel(t_{k-1}).)
    let mut coupled = vec![beam.outputs()];
    let mut t = 0.0;
    for _ in 0..STEPS {
        let v_rel = coupled.last().map(|o| o.relative_velocity).unwrap_or(0.0);
        friction
            .set_real(&[fvrs.sliding_velocity], &[v_rel])
            .expect("friction input");
        let mut f = [0.0; 2];
        friction
            .get_real(&friction_outputs, &mut f)
            .expect("friction outputs");
        beam.inst
            .set_real(&[vrs.kinetic_force, vrs.static_limit], &[f[0], f[1]])
            .expect("beam inputs");
        beam.step();
        friction.do_step(t, H, true).expect("friction do_step");
        t += H;
        coupled.push(beam.outputs());
    }

    // Monolithic: the same beam with friction.law = exponential, i.e. the library.
    let monolithic_fmu = {
        let mut mono = Beam::start(
            &beam_import,
            "coupled-monolithic",
            &[
                (vrs.fidelity, FidelityLevel::Beam.code()),
                (vrs.friction_law, FrictionLawKind::Exponential.code()),
            ],
        );
        mono.run_from_start(STEPS)
    };
    let (monolithic, _) = direct_advance_to(Some(FidelityLevel::Beam));
    assert_bitwise("monolithic FMU vs library", &monolithic_fmu, &monolithic);

    let points = communication_points(STEPS);
    let k = first_slip(&coupled);
    assert!(
        (points[k] - BREAKAWAY).abs() <= H * (1.0 + 1e-9),
        "coupled breakaway at {} s",
        points[k]
    );
    assert_eq!(
        k,
        first_slip(&monolithic),
        "same breakaway point as monolithic"
    );
    // Until breakaway the static limit is the only coupled quantity: identical.
    assert_bitwise(
        "coupled vs monolithic before breakaway",
        &coupled[..k],
        &monolithic[..k],
    );

    let deviation = |range: std::ops::Range<usize>| {
        range
            .map(|j| {
                (
                    (coupled[j].tip_deflection - monolithic[j].tip_deflection).abs(),
                    j,
                )
            })
            .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
    };
    let (first_worst, first_at) = deviation(0..FIRST_SLIP_END);
    let (worst, at) = deviation(0..STEPS + 1);
    let peak = monolithic
        .iter()
        .map(|o| o.tip_deflection)
        .fold(0.0, f64::max);
    println!(
        "coupled: breakaway at {:.3} s; max |tip deflection - monolithic| = {:.4} mm to 0.7 s (at {:.3} s), {:.4} mm to 1.2 s (at {:.3} s); peak {:.3} mm; {} vs {} transitions",
        points[k],
        first_worst * 1e3,
        points[first_at],
        worst * 1e3,
        points[at],
        peak * 1e3,
        coupled[STEPS].transitions,
        monolithic[STEPS].transitions
    );
    assert!(
        worst > 0.0,
        "the coupled run holds the force over h: not identical"
    );
    assert!(
        first_worst <= COUPLED_TOLERANCE_FIRST_SLIP,
        "coupled tip deflection {:.4} mm off the monolithic run at t = {:.3} s",
        first_worst * 1e3,
        points[first_at]
    );
    assert!(
        worst <= COUPLED_TOLERANCE,
        "coupled tip deflection {:.4} mm off the monolithic run at t = {:.3} s",
        worst * 1e3,
        points[at]
    );
}
