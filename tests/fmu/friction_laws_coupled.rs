//! StickSlipBeam with `friction.law = external` (signed coupling) driven by
//! NeuralFriction with a law with state, Gauss-Seidel, against StickSlipBeam with the
//! same law embedded.

use crate::friction_laws::initialised;
use stickslip::choice::Choice;
use stickslip::friction::rate_and_state::StateEvolution;
use stickslip::friction::tabulated::TABLE_VELOCITIES;
use stickslip::friction::FrictionLawKind;
use stickslip::scene::FidelityLevel;
use stickslip::simulation::ExternalCoupling;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::instance::{FmiVersion, Instance};
use stickslip_tests::vr;

const END: f64 = 1.2;

/// How a beam (embedded or external law) and its friction model are set up.
#[derive(Clone, Copy)]
struct Setup {
    law: FrictionLawKind,
    /// None: the FMU's default fidelity (the SSP systems').
    fidelity: Option<FidelityLevel>,
    coupling: ExternalCoupling,
    /// The rate-and-state evolution (both FMUs).
    evolution: Option<StateEvolution>,
    /// The learned law with memory (both FMUs' weights).
    learned: bool,
}

impl Setup {
    fn modal(law: FrictionLawKind, coupling: ExternalCoupling) -> Self {
        Setup {
            law,
            fidelity: Some(FidelityLevel::Modal),
            coupling,
            evolution: None,
            learned: false,
        }
    }
}

const LEARNED: &str = "rate-and-state-learned.json";

fn beam_with(setup: &Setup) -> Instance<StickSlipBeam> {
    let logger = Box::new(|_, _: &str, _: &str| {});
    let dir = stickslip_tests::weights_dir();
    let mut b = Instance::<StickSlipBeam>::new("b", Some(&dir), false, logger).unwrap();
    b.setup_experiment(0.0, Some(END)).unwrap();
    let mut integers = vec![
        (vr::<StickSlipBeam>("friction.law"), setup.law.code()),
        (
            vr::<StickSlipBeam>("external.coupling"),
            setup.coupling.code(),
        ),
    ];
    if let Some(level) = setup.fidelity {
        integers.push((vr::<StickSlipBeam>("fidelity.level"), level.code()));
    }
    if let Some(evolution) = setup.evolution {
        integers.push((
            vr::<StickSlipBeam>("friction.rate_and_state.state_evolution"),
            evolution.code(),
        ));
    }
    let (vrs, values): (Vec<u32>, Vec<i32>) = integers.into_iter().unzip();
    b.set_integer(&vrs, &values).unwrap();
    if setup.learned && setup.law != FrictionLawKind::External {
        b.set_string(&[vr::<StickSlipBeam>("friction.weights")], &[LEARNED])
            .unwrap();
    }
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
    alone_with(&Setup::modal(law, ExternalCoupling::Signed), h)
}

fn alone_with(setup: &Setup, h: f64) -> Vec<f64> {
    let mut b = beam_with(setup);
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
    let setup = Setup::modal(FrictionLawKind::External, ExternalCoupling::Signed);
    coupled_with(law, &setup, h, Scheme::GaussSeidel)
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scheme {
    GaussSeidel,
    Jacobi,
    /// Jacobi, NeuralFriction re-committing (emulated in the loop with its FMU state):
    /// at t_k it restores its state at t_k-1, commits [t_k-1, t_k] as Gauss-Seidel does
    /// (v_rel(t_k), the mean over [t_k-1, t_k]), saves that, and predicts one step with
    /// the velocity of `Predict` for its outputs.
    JacobiRecommit(Predict),
}

/// The velocity NeuralFriction's predicted step (Jacobi re-commit) holds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Predict {
    /// v_rel(t_k).
    End,
    /// The law's own commit velocity (`state_velocity`): the mean over [t_k-1, t_k]
    /// where it chooses the mean, else v_rel(t_k).
    Rule,
    /// Predicted and evaluated at v_rel extrapolated linearly to t_k+1,
    /// 2 v_rel(t_k) - v_rel(t_k-1) (NeuralFriction could keep the previous input).
    Extrapolated,
    /// `End`, and then a diagnosis no master can run: NeuralFriction's outputs are
    /// evaluated at v_rel(t_k+1), the beam's velocity after its step, as in
    /// Gauss-Seidel, so that only the predicted state differs from Gauss-Seidel.
    Oracle,
}

/// The velocity NeuralFriction commits its law's state with over its step
/// (Gauss-Seidel), NeuralFriction's `state_velocity`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum StateVelocity {
    /// v_rel(t_k+1), the beam's at the step's end (`state_velocity = end`).
    End,
    /// The step's mean v_rel, its slip distance over h: the beam's output
    /// `mean_relative_velocity` into NeuralFriction's `mean_sliding_velocity`
    /// (`state_velocity = mean`). NeuralFriction's outputs, the step pair included, stay
    /// at `sliding_velocity` = v_rel(t_k+1) as with `End`.
    Mean,
    /// The law's own choice (`state_velocity = auto`, the FMU's default) with the link,
    /// as the SSP systems run: the mean for every law with state.
    Auto,
}

impl StateVelocity {
    fn fmu(self) -> stickslip_fmi::friction::StateVelocity {
        use stickslip_fmi::friction::StateVelocity as Fmu;
        match self {
            StateVelocity::End => Fmu::End,
            StateVelocity::Mean => Fmu::Mean,
            StateVelocity::Auto => Fmu::Auto,
        }
    }
}

/// The coupled run of `law` in NeuralFriction with the beam of `setup` (its law
/// `external`), by `scheme` as `stickslip_checks.master` runs it: Gauss-Seidel beam
/// first (above); Jacobi reads every output at t_k (NeuralFriction's at the v_rel(t_k-1)
/// it held), then sets the inputs and steps both.
fn coupled_with(law: NeuralFrictionLaw, setup: &Setup, h: f64, scheme: Scheme) -> Vec<f64> {
    coupled_holding(law, setup, h, scheme, StateVelocity::End)
}

/// `coupled_with` as the SSP systems run it: `state_velocity` at its default (`auto`)
/// with `mean_relative_velocity` linked to `mean_sliding_velocity`.
fn coupled_as_shipped(law: NeuralFrictionLaw, setup: &Setup, h: f64, scheme: Scheme) -> Vec<f64> {
    coupled_holding(law, setup, h, scheme, StateVelocity::Auto)
}

/// `coupled_with`, with NeuralFriction's state committed at `held`. With the mean (or
/// `auto`) the link `mean_relative_velocity` -> `mean_sliding_velocity` is made as the
/// other links are: Gauss-Seidel hands over the step's own mean, Jacobi the previous
/// step's (read at t_k, before either steps).
fn coupled_holding(
    law: NeuralFrictionLaw,
    setup: &Setup,
    h: f64,
    scheme: Scheme,
    held: StateVelocity,
) -> Vec<f64> {
    let beam_setup = Setup {
        law: FrictionLawKind::External,
        ..*setup
    };
    let mut b = beam_with(&beam_setup);
    let state_velocity = ("state_velocity", held.fmu().code());
    let integers: Vec<(&str, i32)> = setup
        .evolution
        .map(|e| ("friction.rate_and_state.state_evolution", e.code()))
        .into_iter()
        .chain([state_velocity])
        .collect();
    let mut f = if setup.learned {
        let logger = Box::new(|_, _: &str, _: &str| {});
        let dir = stickslip_tests::weights_dir();
        let mut f = Instance::<NeuralFriction>::instantiate(
            stickslip_fmi::instance::FmiVersion::V2,
            "f",
            Some(&dir),
            false,
            logger,
        )
        .unwrap();
        f.set_string(&[vr::<NeuralFriction>("weights")], &[LEARNED])
            .unwrap();
        f.set_integer(
            &[vr::<NeuralFriction>(state_velocity.0)],
            &[state_velocity.1],
        )
        .unwrap();
        f.setup_experiment(0.0, None).unwrap();
        f.enter_initialization_mode().unwrap();
        f.exit_initialization_mode().unwrap();
        f
    } else {
        initialised(FmiVersion::V2, law, &integers, &[]).0.unwrap()
    };
    let links = [
        ("friction_force_magnitude", "external.kinetic_force"),
        ("static_limit", "external.static_limit"),
        ("friction_force", "external.friction_force"),
        ("friction_force_slope", "external.friction_slope"),
        ("evaluated_velocity", "external.sliding_velocity"),
        ("step_friction_force", "external.step_force"),
        ("step_friction_slope", "external.step_slope"),
    ];
    let mut outputs: Vec<u32> = links.iter().map(|(o, _)| vr::<NeuralFriction>(o)).collect();
    let mut inputs: Vec<u32> = links.iter().map(|(_, i)| vr::<StickSlipBeam>(i)).collect();
    // The table coupling's 22 links, as the SSP systems make them.
    for i in 0..TABLE_VELOCITIES.len() {
        outputs.push(vr::<NeuralFriction>(&format!("table_friction_force_{i}")));
        inputs.push(vr::<StickSlipBeam>(&format!("external.table_force_{i}")));
        outputs.push(vr::<NeuralFriction>(&format!(
            "table_step_friction_force_{i}"
        )));
        inputs.push(vr::<StickSlipBeam>(&format!(
            "external.table_step_force_{i}"
        )));
    }
    let v_rel = |b: &mut Instance<StickSlipBeam>| beam_real(b, "relative_velocity");
    let n = (END / h).round() as usize;
    let sliding = [vr::<NeuralFriction>("sliding_velocity")];
    // The link of the step's mean (not made with `End`: a master without it).
    let mean_link = held != StateVelocity::End;
    let mean = |b: &mut Instance<StickSlipBeam>, f: &mut Instance<NeuralFriction>| {
        let m = beam_real(b, "mean_relative_velocity");
        f.set_real(&[vr::<NeuralFriction>("mean_sliding_velocity")], &[m])
            .unwrap();
    };
    f.set_real(&sliding, &[v_rel(&mut b)]).unwrap();
    let mean_vr = [vr::<NeuralFriction>("mean_sliding_velocity")];
    // Jacobi re-commit: NeuralFriction's committed state at t_k-1.
    let mut committed = None;
    let mut previous: Option<f64> = None;
    (0..n)
        .map(|k| {
            let t = k as f64 * h;
            let mut values = vec![0.0; outputs.len()];
            f.get_real(&outputs, &mut values).unwrap();
            b.set_real(&inputs, &values).unwrap();
            if let Scheme::JacobiRecommit(predict) = scheme {
                let v = v_rel(&mut b);
                let m = beam_real(&mut b, "mean_relative_velocity");
                if let Some(saved) = &committed {
                    f.set_state(saved).unwrap();
                    f.set_real(&sliding, &[v]).unwrap();
                    if mean_link {
                        f.set_real(&mean_vr, &[m]).unwrap();
                    }
                    f.do_step((k - 1) as f64 * h, h).unwrap();
                }
                committed = Some(f.get_state().unwrap());
                let v_prev = previous.replace(v).unwrap_or(v);
                let v = if predict == Predict::Extrapolated {
                    2.0 * v - v_prev
                } else {
                    v
                };
                f.set_real(&sliding, &[v]).unwrap();
                if mean_link {
                    let held = if predict == Predict::Rule { m } else { v };
                    f.set_real(&mean_vr, &[held]).unwrap();
                }
            }
            if scheme == Scheme::Jacobi {
                f.set_real(&sliding, &[v_rel(&mut b)]).unwrap();
                if mean_link {
                    mean(&mut b, &mut f);
                }
            }
            b.do_step(t, h).unwrap();
            if scheme == Scheme::GaussSeidel {
                f.set_real(&sliding, &[v_rel(&mut b)]).unwrap();
                if mean_link {
                    mean(&mut b, &mut f);
                }
            }
            f.do_step(t, h).unwrap();
            if scheme == Scheme::JacobiRecommit(Predict::Oracle) {
                f.set_real(&sliding, &[v_rel(&mut b)]).unwrap();
            }
            beam_real(&mut b, "tip_deflection")
        })
        .collect()
}

/// The starts (s) of the major falls of `tip` (sampled every `h` from h on): the
/// peaks from which the tip falls by more than `FALL` (0.5 mm, the measure)
/// before it rises again by as much, so that neither a re-stick's stall of a few um
/// within a fall nor a wiggle at the top counts as a fall of its own.
pub(crate) fn major_falls(tip: &[f64], h: f64) -> Vec<f64> {
    const FALL: f64 = 5e-4;
    let mut starts = Vec::new();
    let (mut peak, mut peak_at) = (f64::MIN, 0);
    let mut trough = f64::MAX;
    let mut falling = false;
    for (k, &x) in tip.iter().enumerate() {
        if falling {
            trough = trough.min(x);
            if x > trough + FALL {
                falling = false;
                (peak, peak_at) = (x, k);
            }
        } else {
            if x > peak {
                (peak, peak_at) = (x, k);
            }
            if x < peak - FALL {
                starts.push((peak_at + 1) as f64 * h);
                falling = true;
                trough = x;
            }
        }
    }
    starts
}

/// The mean period (s) between the major falls of `tip` up to `END`.
fn fall_period(tip: &[f64], h: f64) -> f64 {
    let d = major_falls(tip, h);
    if d.len() < 2 {
        return f64::NAN;
    }
    (d[d.len() - 1] - d[0]) / (d.len() - 1) as f64
}

/// The coupling error of `run` against `reference` (both every `h`): the largest tip
/// difference (m) to 0.7 s and the relative period error by major falls to 1.2 s.
pub(crate) fn coupling_error(reference: &[f64], run: &[f64], h: f64) -> (f64, f64) {
    let m = (0.7 / h).round() as usize;
    let deviation = largest_difference(&reference[..m], &run[..m]);
    let period = fall_period(reference, h);
    (deviation, fall_period(run, h) / period - 1.0)
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

/// The laws with state of the SSP systems: (name, NeuralFriction's law, the embedded
/// law, the rate-and-state evolution, the learned law's weights).
fn state_law_setups(coupling: ExternalCoupling) -> Vec<(&'static str, NeuralFrictionLaw, Setup)> {
    let base = |law| Setup {
        law,
        fidelity: None,
        coupling,
        evolution: None,
        learned: false,
    };
    vec![
        (
            "lugre",
            NeuralFrictionLaw::LUGRE,
            base(FrictionLawKind::Lugre),
        ),
        (
            "rate-and-state aging",
            NeuralFrictionLaw::RATE_AND_STATE,
            Setup {
                evolution: Some(StateEvolution::Aging),
                ..base(FrictionLawKind::RateAndState)
            },
        ),
        (
            "rate-and-state slip",
            NeuralFrictionLaw::RATE_AND_STATE,
            Setup {
                evolution: Some(StateEvolution::Slip),
                ..base(FrictionLawKind::RateAndState)
            },
        ),
        (
            "learned",
            NeuralFrictionLaw::NEURAL,
            Setup {
                learned: true,
                ..base(FrictionLawKind::Neural)
            },
        ),
    ]
}

/// The coupling-error table of docs/cosimulation.md: every law with state of the SSP
/// systems at the FMU's default fidelity, signed and step couplings, Gauss-Seidel and
/// Jacobi, h from the environment's COUPLING_STEPS (default 1e-3): printed.
#[test]
#[ignore = "measurement"]
fn measure_step_consistent_coupling() {
    let steps: Vec<f64> = std::env::var("COUPLING_STEPS")
        .unwrap_or_else(|_| "1e-3".into())
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let only = std::env::var("COUPLING_LAWS").unwrap_or_default();
    // COUPLING_STATE_VELOCITY=mean or auto: NeuralFriction's `state_velocity`, with
    // the beam's `mean_relative_velocity` linked (`StateVelocity`); default end.
    let held = match std::env::var("COUPLING_STATE_VELOCITY").as_deref() {
        Ok("mean") => StateVelocity::Mean,
        Ok("auto") => StateVelocity::Auto,
        _ => StateVelocity::End,
    };
    for h in steps {
        for (name, law, setup) in state_law_setups(ExternalCoupling::Step) {
            if !only.is_empty() && !only.split(',').any(|o| o == name) {
                continue;
            }
            let reference = alone_with(&setup, h);
            // COUPLING_COUPLINGS (signed,step,table) and COUPLING_SCHEMES
            // (GaussSeidel,Jacobi) narrow the runs: at h = 1e-5 s each is 120,000 exchanges.
            let listed = |var: &str, name: &str| {
                std::env::var(var).map_or(true, |v| v.split(',').any(|o| o == name))
            };
            for coupling in [
                ExternalCoupling::Signed,
                ExternalCoupling::Step,
                ExternalCoupling::Table,
            ] {
                if !listed("COUPLING_COUPLINGS", coupling.name()) {
                    continue;
                }
                for scheme in [Scheme::GaussSeidel, Scheme::Jacobi] {
                    if !listed("COUPLING_SCHEMES", &format!("{scheme:?}")) {
                        continue;
                    }
                    let run = coupled_holding(law, &Setup { coupling, ..setup }, h, scheme, held);
                    let (deviation, period) = coupling_error(&reference, &run, h);
                    println!(
                        "h {h:e} {name:22} {:7} {scheme:?} {held:?}: {:.4} mm, period {:+.2} %, falls {:.4?} (embedded {:.4?})",
                        coupling.name(),
                        deviation * 1e3,
                        period * 100.0,
                        major_falls(&run, h),
                        major_falls(&reference, h),
                    );
                }
            }
        }
    }
}

/// Jacobi with NeuralFriction re-committing its state one step back (issue 36):
/// every law with state of the SSP systems, step coupling, `state_velocity = auto`
/// linked, against Gauss-Seidel and plain Jacobi; and the exponential law's Jacobi and
/// Gauss-Seidel errors (the bound), h from COUPLING_STEPS (default 1e-3): printed.
#[test]
#[ignore = "measurement"]
fn measure_jacobi_recommit() {
    let steps: Vec<f64> = std::env::var("COUPLING_STEPS")
        .unwrap_or_else(|_| "1e-3".into())
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let only = std::env::var("COUPLING_LAWS").unwrap_or_default();
    let wanted = |name: &str| only.is_empty() || only.split(',').any(|o| o == name);
    let report = |h: f64, name: &str, what: String, reference: &[f64], run: &[f64]| {
        let (deviation, period) = coupling_error(reference, run, h);
        println!(
            "h {h:e} {name:22} {what:40}: {:.4} mm, period {:+.2} %, falls {:.4?} (embedded {:.4?})",
            deviation * 1e3,
            period * 100.0,
            major_falls(run, h),
            major_falls(reference, h),
        );
    };
    for h in steps {
        if wanted("exponential") {
            for coupling in [ExternalCoupling::Magnitude, ExternalCoupling::Signed] {
                let setup = Setup {
                    law: FrictionLawKind::Exponential,
                    fidelity: None,
                    coupling,
                    evolution: None,
                    learned: false,
                };
                let reference = alone_with(&setup, h);
                for scheme in [Scheme::GaussSeidel, Scheme::Jacobi] {
                    let run = coupled_with(NeuralFrictionLaw::EXPONENTIAL, &setup, h, scheme);
                    let what = format!("{} {scheme:?}", coupling.name());
                    report(h, "exponential", what, &reference, &run);
                }
            }
        }
        for (name, law, setup) in state_law_setups(ExternalCoupling::Step) {
            if !wanted(name) {
                continue;
            }
            let reference = alone_with(&setup, h);
            for scheme in [
                Scheme::GaussSeidel,
                Scheme::Jacobi,
                Scheme::JacobiRecommit(Predict::End),
                Scheme::JacobiRecommit(Predict::Rule),
                Scheme::JacobiRecommit(Predict::Oracle),
                Scheme::JacobiRecommit(Predict::Extrapolated),
            ] {
                let run = coupled_as_shipped(law, &setup, h, scheme);
                report(h, name, format!("{scheme:?}"), &reference, &run);
            }
        }
    }
}

/// The couplings of a law with state at the SSP systems' step, h = 1e-3 s,
/// Gauss-Seidel, default fidelity, as the systems run them (`state_velocity = auto`, the
/// step's mean for every law with state, with the beam's `mean_relative_velocity`
/// linked), against each law embedded: largest tip difference to 0.7 s and period error
/// by major falls to 1.2 s. Measured (`COUPLING_STATE_VELOCITY=auto
/// measure_step_consistent_coupling`, docs/cosimulation.md):
///
/// | law | table (the systems') | step |
/// | --- | --- | --- |
/// | LuGre | 0.0074 mm, 0.00 % | 0.0069 mm, +0.19 % |
/// | rate-and-state, slip | 0.0038 mm, 0.00 % | 0.066 mm, -0.18 % |
/// | rate-and-state, aging | 0.0201 mm, 0.00 % | 0.197 mm, +3.69 % |
/// | learned law with memory | 0.0206 mm, 0.00 % | 0.230 mm, +4.03 % |
///
/// The `table` coupling meets the bounds (0.092 mm to 0.7 s, 1 % of period to
/// 1.2 s) for all four laws, asserted: the largest deviation is 4.5x below the bound;
/// the falls are timed to a sample, 1 ms, and the period is their mean over about
/// 0.6 s, so timing costs at most about 0.25 %. The `step` coupling (kept for masters
/// without the 22 links) meets them for LuGre and the slip law, asserted as well; its
/// numbers for the aging and the learned law, which now commit at the mean as well,
/// are those `the_state_committed_at_the_steps_mean_velocity` asserts (not run twice:
/// this test stays near 4 s).
#[test]
fn the_step_coupling_at_the_systems_step() {
    let h = 1e-3;
    for (name, law, setup) in state_law_setups(ExternalCoupling::Table) {
        let reference = alone_with(&setup, h);
        let run = coupled_as_shipped(law, &setup, h, Scheme::GaussSeidel);
        let (d, p) = coupling_error(&reference, &run, h);
        assert!(d < 0.092e-3, "{name}, table: {d} m");
        assert!(p.abs() < 0.01, "{name}, table: period error {p}");
        if name == "lugre" || name == "rate-and-state slip" {
            let step = Setup {
                coupling: ExternalCoupling::Step,
                ..setup
            };
            let run = coupled_as_shipped(law, &step, h, Scheme::GaussSeidel);
            let (d, p) = coupling_error(&reference, &run, h);
            assert!(d < 0.092e-3, "{name}, step: {d} m");
            assert!(p.abs() < 0.01, "{name}, step: period error {p}");
        }
    }
}

/// The step coupling converges to the embedded law with h, Gauss-Seidel: at h = 2e-4 s
/// LuGre, rate-and-state with the aging law and the learned law are within the issue's
/// bounds (0.092 mm to 0.7 s, 1 % of period to 1.2 s). Measured at 2e-4 s: LuGre
/// 0.0024 mm, 0.00 %; aging 0.0078 mm, +0.37 %; learned 0.0082 mm, +0.37 %. Not
/// rate-and-state with the slip law, whose coupling error does not fall with h from
/// 1e-3 s (0.092, then 0.145 mm at 2e-4 s, -1.3 %: docs/cosimulation.md), signed
/// coupling alike (0.131 mm at 2e-4 s).
#[test]
fn the_step_coupling_meets_the_bounds_at_a_smaller_step() {
    let h = 2e-4;
    for (name, law, setup) in state_law_setups(ExternalCoupling::Step) {
        if name == "rate-and-state slip" {
            continue;
        }
        let reference = alone_with(&setup, h);
        let run = coupled_with(law, &setup, h, Scheme::GaussSeidel);
        let (d, p) = coupling_error(&reference, &run, h);
        assert!(d < 0.092e-3, "{name}: {d} m");
        assert!(p.abs() < 0.01, "{name}: period error {p}");
    }
}

/// The `step` coupling of the aging and the learned law with the state committed at
/// the step's mean (`state_velocity = mean`, or `auto` since the `table` coupling, the
/// beam's `mean_relative_velocity` linked) is worse than at the step's end (which
/// `state_velocity = end` still gives), h = 1e-3 s, Gauss-Seidel, default fidelity.
/// Measured (`COUPLING_STATE_VELOCITY=mean`, docs/cosimulation.md), against the end
/// velocity:
///
/// | law | mean | end |
/// | --- | --- | --- |
/// | rate-and-state, aging | 0.197 mm, +3.69 % | 0.138 mm, +3.36 % |
/// | learned law with memory | 0.230 mm, +4.03 % | 0.168 mm, +2.68 % |
///
/// (LuGre and the slip law gain: `the_step_coupling_at_the_systems_step`.) Asserted:
/// the measured, within 1.25 times the deviation and 1 percentage point of period, and
/// that the mean stays worse than the end velocity for `step` (the `table` coupling
/// needs the mean: `the_step_coupling_at_the_systems_step`).
#[test]
fn the_state_committed_at_the_steps_mean_velocity() {
    let h = 1e-3;
    let worse = [
        ("rate-and-state aging", 0.197e-3, 0.0369_f64),
        ("learned", 0.230e-3, 0.0403),
    ];
    for (name, law, setup) in state_law_setups(ExternalCoupling::Step) {
        let Some((_, deviation, period)) = worse.iter().find(|m| m.0 == name) else {
            continue;
        };
        let reference = alone_with(&setup, h);
        let mean = coupled_holding(law, &setup, h, Scheme::GaussSeidel, StateVelocity::Mean);
        let (d, p) = coupling_error(&reference, &mean, h);
        assert!(
            d < 1.25 * deviation,
            "{name}: {d} m, measured {deviation} m"
        );
        assert!(
            p.abs() < period.abs() + 0.01,
            "{name}: period error {p}, measured {period}"
        );
        let end = coupled_with(law, &setup, h, Scheme::GaussSeidel);
        let (d_end, _) = coupling_error(&reference, &end, h);
        assert!(d > d_end, "{name}: mean {d} m, end {d_end} m");
    }
}

/// `mean_relative_velocity` is part of the beam's FMU state (version 7). A version-6
/// state (which lacks it) after a step with `friction.law = external` is refused with
/// the reason, since a coupled law with state commits with it; with a law inside the
/// beam it restores, the mean read as v_rel at the restored point until the next step.
/// A version-7 state restores it bit for bit.
#[test]
fn the_steps_mean_velocity_is_in_the_beams_state() {
    for (law, refused) in [
        (FrictionLawKind::External, true),
        (FrictionLawKind::Lugre, false),
    ] {
        let mut b = beam_with(&Setup::modal(law, ExternalCoupling::Step));
        for k in 0..450 {
            b.do_step(k as f64 * 1e-3, 1e-3).unwrap();
        }
        let mean = beam_real(&mut b, "mean_relative_velocity");
        assert!(mean.is_finite());
        let saved = b.get_state().unwrap();
        let bytes = saved.to_bytes();
        let restored = b.deserialize_state(&bytes).unwrap();
        b.set_state(&restored).unwrap();
        assert_eq!(
            beam_real(&mut b, "mean_relative_velocity").to_bits(),
            mean.to_bits()
        );
        let mut old = saved.clone();
        old.version = 6;
        old.model["running"]
            .as_object_mut()
            .unwrap()
            .remove("mean_relative_velocity");
        let old = b.deserialize_state(&old.to_bytes());
        assert_eq!(old.is_err(), refused, "{law:?}");
        if let Ok(old) = old {
            b.set_state(&old).unwrap();
            let v_rel = beam_real(&mut b, "relative_velocity");
            assert_eq!(beam_real(&mut b, "mean_relative_velocity"), v_rel);
        }
    }
}
