//! StickSlipBeam with `friction.law = external` (signed coupling) driven by
//! NeuralFriction with a law with state, Gauss-Seidel, against StickSlipBeam with the
//! same law embedded.

use crate::friction_laws::initialised;
use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;
use stickslip::scene::FidelityLevel;
use stickslip::simulation::ExternalCoupling;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::instance::{FmiVersion, Instance};
use stickslip_tests::vr;

const END: f64 = 1.2;

fn beam(law: FrictionLawKind) -> Instance<StickSlipBeam> {
    let logger = Box::new(|_, _: &str, _: &str| {});
    let dir = stickslip_tests::weights_dir();
    let mut b = Instance::<StickSlipBeam>::new("b", Some(&dir), false, logger).unwrap();
    b.setup_experiment(0.0, Some(END)).unwrap();
    b.set_integer(
        &[
            vr::<StickSlipBeam>("fidelity.level"),
            vr::<StickSlipBeam>("friction.law"),
            vr::<StickSlipBeam>("external.coupling"),
        ],
        &[
            FidelityLevel::Modal.code(),
            law.code(),
            ExternalCoupling::Signed.code(),
        ],
    )
    .unwrap();
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    b
}

fn beam_real(b: &mut Instance<StickSlipBeam>, name: &str) -> f64 {
    let mut out = [0.0];
    b.get_real(&[vr::<StickSlipBeam>(name)], &mut out).unwrap();
    out[0]
}

/// The embedded run's tip deflection at the communication points of `h`.
fn alone(law: FrictionLawKind, h: f64) -> Vec<f64> {
    let mut b = beam(law);
    let n = (END / h).round() as usize;
    (0..n)
        .map(|k| {
            b.do_step(k as f64 * h, h).unwrap();
            beam_real(&mut b, "tip_deflection")
        })
        .collect()
}

/// The coupled run, Gauss-Seidel with the beam first: at t_k NeuralFriction holds
/// v_rel(t_k) and its outputs (force, slope, evaluated velocity, static limit) go to the
/// beam, which steps; NeuralFriction then gets v_rel(t_k+1) and steps its state with it
/// held, as the embedded law's implicit step holds the step's end velocity.
fn coupled(law: NeuralFrictionLaw, h: f64) -> Vec<f64> {
    let mut b = beam(FrictionLawKind::External);
    let (f, _) = initialised(FmiVersion::V2, law, &[], &[]);
    let mut f = f.unwrap();
    let links = [
        ("friction_force_magnitude", "external.kinetic_force"),
        ("static_limit", "external.static_limit"),
        ("friction_force", "external.friction_force"),
        ("friction_force_slope", "external.friction_slope"),
        ("evaluated_velocity", "external.sliding_velocity"),
    ];
    let outputs: Vec<u32> = links.iter().map(|(o, _)| vr::<NeuralFriction>(o)).collect();
    let inputs: Vec<u32> = links.iter().map(|(_, i)| vr::<StickSlipBeam>(i)).collect();
    let v_rel = |b: &mut Instance<StickSlipBeam>| beam_real(b, "relative_velocity");
    let n = (END / h).round() as usize;
    let sliding = [vr::<NeuralFriction>("sliding_velocity")];
    f.set_real(&sliding, &[v_rel(&mut b)]).unwrap();
    (0..n)
        .map(|k| {
            let t = k as f64 * h;
            let mut values = vec![0.0; links.len()];
            f.get_real(&outputs, &mut values).unwrap();
            b.set_real(&inputs, &values).unwrap();
            b.do_step(t, h).unwrap();
            f.set_real(&sliding, &[v_rel(&mut b)]).unwrap();
            f.do_step(t, h).unwrap();
            beam_real(&mut b, "tip_deflection")
        })
        .collect()
}

/// The times (s) at which `tip` (sampled every `h` from h on) falls through `level`
/// (m), linearly interpolated.
fn drops(tip: &[f64], h: f64, level: f64) -> Vec<f64> {
    tip.windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] >= level && w[1] < level)
        .map(|(k, w)| (k + 1) as f64 * h + h * (w[0] - level) / (w[0] - w[1]))
        .collect()
}

/// Breakaway (the first drop through the middle of the reference's corridor, s) and
/// the mean period between drops (s).
fn breakaway_and_period(tip: &[f64], h: f64, level: f64) -> (f64, f64) {
    let d = drops(tip, h, level);
    assert!(d.len() >= 3, "{d:?}");
    (d[0], (d[d.len() - 1] - d[0]) / (d.len() - 1) as f64)
}

/// The middle of the embedded run's corridor over its second half (m): the level its
/// drops are timed at.
fn mid_corridor(tip: &[f64]) -> f64 {
    let late = &tip[tip.len() / 2..];
    let (lo, hi) = late
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    0.5 * (lo + hi)
}

/// Rate-and-state through the coupling follows the embedded law. The beam's own stick
/// (the external coupling's set-valued stick at `static_limit` = mu_s F_n = 50 N) does
/// not cut the law short: when it ends, the healed theta makes the law's force at small
/// v_rel exceed 50 N, so the tip creeps on as in the embedded run, and the slip that
/// follows is the law's. Measured at h = 1e-4 s (the beam's internal step), modal
/// fidelity, 1.2 s: first drop 0.50723 s against 0.50710 s, period 0.19750 s against
/// 0.19698 s (0.26 %), largest tip difference 0.061 mm; at h = 1e-3 s the differences
/// are 0.43 ms, 4.7 % and 0.82 mm: they are the coupling's (the force held as a tangent
/// at the committed state over a communication step), first order in h. Asserted: the
/// first drop within 0.5 ms (4 times the measured 0.13 ms, 5 steps) and the period
/// within 1 % (4 times the measured 0.26 %).
#[test]
fn rate_and_state_through_the_coupling_follows_the_embedded_law() {
    let h = 1e-4;
    let reference = alone(FrictionLawKind::RateAndState, h);
    let run = coupled(NeuralFrictionLaw::RATE_AND_STATE, h);
    assert_drop_and_period_agree(&reference, &run, h);
}

/// Asserts that the coupled `run`'s first drop lies within 0.5 ms of the embedded
/// `reference`'s and its period within 1 % (both sampled every `h`).
fn assert_drop_and_period_agree(reference: &[f64], run: &[f64], h: f64) {
    let level = mid_corridor(reference);
    let (drop, period) = breakaway_and_period(reference, h, level);
    let (drop_c, period_c) = breakaway_and_period(run, h, level);
    assert!(
        (drop_c - drop).abs() < 5e-4,
        "first drop {drop_c} s coupled, {drop} s embedded"
    );
    assert!(
        (period_c - period).abs() < 0.01 * period,
        "period {period_c} s coupled, {period} s embedded"
    );
}

/// The largest difference (m) of two tip series of equal sampling.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// LuGre through the coupling converges to the embedded law as h -> 0. NeuralFriction
/// hands `static_limit` = 0 for LuGre, so the beam takes no set-valued stick and every
/// step is a slip solve under the law's tangent, as the embedded contact does (with
/// mu_s F_n the beam's stick froze the bristles and the coupled run converged to
/// another model: first drop 2.8 ms early, period 3.9 % short at h = 1e-5 and 2e-6 s).
/// Measured, modal fidelity, 1.2 s, largest tip difference: 0.085 mm at h = 1e-4 s,
/// 1.1 um at 1e-5 s (first drop 0.48249 s against 0.48247 s, period 0.27151 s against
/// 0.27179 s at 1e-4). Asserted: at 1e-4 the first drop within 0.5 ms and the period
/// within 1 % (as for rate-and-state), and the difference falls by at least 10 from
/// 1e-4 to 1e-5 s (a coupling error of first order in h falls by 10; measured 75) and
/// stays below 0.34 mm at 1e-4 (4 times the measured). Below 1e-5 s it does not keep
/// falling (21 um at 2e-6 s): the signed coupling's direction rule flips the tangent
/// where the bristle force points against v_rel, which LuGre's presliding does at
/// every reversal (docs/friction-with-memory.md).
#[test]
fn lugre_through_the_coupling_converges_to_the_embedded_law() {
    let mut differences = Vec::new();
    for h in [1e-4, 1e-5] {
        let reference = alone(FrictionLawKind::Lugre, h);
        let run = coupled(NeuralFrictionLaw::LUGRE, h);
        if h == 1e-4 {
            assert_drop_and_period_agree(&reference, &run, h);
        }
        differences.push(largest_difference(&reference, &run));
    }
    assert!(differences[0] < 3.4e-4, "{differences:?}");
    assert!(differences[1] < 0.1 * differences[0], "{differences:?}");
}

/// The numbers of the docs (docs/friction-with-memory.md, NeuralFriction section), for
/// both laws with state at h = 1e-3 to 2e-6 s: printed, not asserted.
#[test]
#[ignore = "measurement"]
fn measure_coupled_against_embedded() {
    for (law, kind) in [
        (
            NeuralFrictionLaw::RATE_AND_STATE,
            FrictionLawKind::RateAndState,
        ),
        (NeuralFrictionLaw::LUGRE, FrictionLawKind::Lugre),
    ] {
        for h in [1e-3, 1e-4, 1e-5, 2e-6] {
            let reference = alone(kind, h);
            let level = mid_corridor(&reference);
            let (tb, period) = breakaway_and_period(&reference, h, level);
            let run = coupled(law, h);
            let (tb_c, period_c) = breakaway_and_period(&run, h, level);
            let max_dev = largest_difference(&reference, &run);
            println!(
                "{kind:?} h {h}: alone breakaway {tb:.5} period {period:.5} level {level:.5}; coupled {tb_c:.5} {period_c:.5}; max dev {max_dev:.2e}"
            );
        }
    }
}
