//! Oracle experiments on the step coupling of a law with state (issue 36): the
//! coupled loop of `friction_laws_coupled` replayed on the physics crate's `Simulator`,
//! internal step by internal step, so that single pieces of the coupling can be made
//! exact (the force curve the beam solves within a communication step, the state the
//! friction side commits, the set-valued stick) and the piece that carries the coupling
//! error found. Printed, not asserted (`measure_coupling_oracles`, #[ignore]d).

use crate::friction_laws_coupled::{coupling_error, major_falls};
use stickslip::choice::Choice;
use stickslip::friction::rate_and_state::{StateEvolution, STATE_EVOLUTION};
use stickslip::friction::state::{LawStep, StatefulLaw};
use stickslip::friction::{FrictionLaw, FrictionLawKind};
use stickslip::law_source::LawSource;
use stickslip::scene::{CheckedScene, Scene};
use stickslip::simulation::{ExternalFriction, ExternalKinetic, Simulator};

const END: f64 = 1.2;
const NORMAL_FORCE: f64 = 100.0;
const STATIC_LIMIT: f64 = 50.0;

/// The law of a run: rate-and-state (`Some(evolution)`) or the learned law (`None`).
fn scene_of(evolution: Option<StateEvolution>) -> CheckedScene {
    raw_scene(evolution).check().unwrap()
}

fn raw_scene(evolution: Option<StateEvolution>) -> Scene {
    let mut scene = Scene::default();
    scene.time.end = END;
    match evolution {
        Some(e) => {
            scene.friction.law = FrictionLawKind::RateAndState;
            scene.friction.laws.set(&STATE_EVOLUTION, e.code() as f64);
        }
        None => {
            scene.friction.law = FrictionLawKind::Neural;
            let path = stickslip_tests::weights_dir().join("rate-and-state-learned.json");
            scene.friction.weights = Some(path.to_string_lossy().into_owned());
        }
    }
    scene
}

fn law_of(scene: &CheckedScene) -> Box<dyn FrictionLaw> {
    LawSource::resolve(scene).unwrap().law().unwrap()
}

fn stateful(law: &mut Box<dyn FrictionLaw>) -> &mut dyn StatefulLaw {
    law.as_stateful_mut().unwrap()
}

/// The embedded run's tip every `h`.
fn embedded(scene: &CheckedScene, h: f64) -> Vec<f64> {
    let mut sim = Simulator::new(scene.clone(), law_of(scene)).unwrap();
    let n = (END / h).round() as usize;
    (0..n)
        .map(|k| {
            sim.advance_to((k + 1) as f64 * h).unwrap();
            sim.sample().tip_deflection
        })
        .collect()
}

/// What the beam solves within a communication step from t_k (state s_k, v_k).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Force {
    /// As shipped: (1 - theta) [F_0 + S_0 (x - v_k)] + theta [F_h + S_h (x - v_k)].
    BlendTangent,
    /// (1 - theta) F(s_k, x) + theta F_h(s_k, x), exact in x.
    BlendExact,
    /// F after theta h from s_k at x held, exact in x.
    RelaxExact,
    /// The embedded law's own step from the state committed along the path.
    Path,
    /// F_h(s_k, x) exact in x over the whole step.
    StepExact,
}

/// With what the friction side commits its state over the step.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Commit {
    /// One step of h at v_rel(t_k+1).
    End,
    /// One step of h at the step's mean v_rel.
    Mean,
    /// Every internal step at its law-level velocity (the embedded commit).
    Path,
}

#[derive(Clone, Copy, Debug)]
struct Variant {
    force: Force,
    commit: Commit,
    static_limit: f64,
}

/// The law-level velocity x of the step just taken from v_rel `before`.
fn law_level(alpha_f: f64, before: f64, after: f64) -> f64 {
    (1.0 - alpha_f) * after + alpha_f * before
}

fn step_kinetic(force: f64, slope: f64, velocity: f64) -> ExternalKinetic {
    ExternalKinetic::Step {
        force,
        slope,
        step_force: force,
        step_slope: slope,
        velocity,
    }
}

/// The coupled run, Gauss-Seidel, communication step `h`, the beam's internal steps
/// taken one by one.
fn coupled(scene: &CheckedScene, h: f64, variant: Variant) -> Vec<f64> {
    let beam_scene = beam_scene_law(scene);
    let mut sim = Simulator::new(beam_scene.clone(), law_of(&beam_scene)).unwrap();
    let rho = scene.integrator.rho_inf;
    let alpha_f = rho / (rho + 1.0);
    let dt = scene.time.step;
    let n = (h / dt).round() as usize;
    let mut law_k = law_of(scene);
    let mut law_path = law_of(scene);
    let mut probe = law_of(scene);
    stateful(&mut law_k).reset();
    stateful(&mut law_path).reset();
    let steps = (END / h).round() as usize;
    let mut tips = Vec::with_capacity(steps);
    let fnormal = NORMAL_FORCE;
    let mut first = true;
    for _ in 0..steps {
        let v_k = sim.sample().relative_velocity;
        let s_k: Vec<f64> = stateful(&mut law_k).state().to_vec();
        let inst = stateful(&mut law_k).force_at_state(v_k, fnormal);
        let (f_h, s_h) = if first {
            (inst.force, inst.slope)
        } else {
            stateful(&mut law_k).step_force_and_slope(LawStep {
                dt: h,
                sliding_velocity: v_k,
                normal_force: fnormal,
            })
        };
        let u_k = sim.sample().tip_deflection;
        let mut v_before = v_k;
        for j in 1..=n {
            let theta = j as f64 / n as f64;
            let kinetic = if variant.force == Force::BlendTangent {
                step_kinetic(
                    (1.0 - theta) * inst.force + theta * f_h,
                    (1.0 - theta) * inst.slope + theta * s_h,
                    v_k,
                )
            } else {
                // The slip branch's x(F) is affine: two probes with a constant force and
                // no static limit give it; then F = F_model(x(F)) is solved here.
                let saved = sim.state().clone();
                let mut probe_x = |force: f64| {
                    sim.set_external_friction(Some(ExternalFriction {
                        kinetic: step_kinetic(force, 0.0, 0.0),
                        static_limit: 0.0,
                    }));
                    sim.step().unwrap();
                    let x = law_level(alpha_f, v_before, sim.sample().relative_velocity);
                    sim.restore(saved.clone()).unwrap();
                    x
                };
                let (fa, fb) = (0.0, 50.0);
                let xa = probe_x(fa);
                let xb = probe_x(fb);
                let dxdf = (xb - xa) / (fb - fa);
                let mut model = |x: f64| {
                    exact(
                        variant.force,
                        &mut probe,
                        &s_k,
                        &mut law_path,
                        x,
                        theta,
                        h,
                        dt,
                        first,
                    )
                };
                // r(F) = F - F_model(x(F)) rises with F (dx/dF < 0, the model's slope
                // >= 0 over a step here): bisection to the last bits.
                let (mut lo, mut hi) = (-1e3, 1e3);
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    let (fm, _) = model(xa + dxdf * (mid - fa));
                    if mid - fm < 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let force = 0.5 * (lo + hi);
                let x = xa + dxdf * (force - fa);
                let (_, slope) = model(x);
                step_kinetic(force, slope, x)
            };
            sim.set_external_friction(Some(ExternalFriction {
                kinetic,
                static_limit: variant.static_limit,
            }));
            sim.step().unwrap();
            let after = sim.sample().relative_velocity;
            if std::env::var("LAB_TRACE").is_ok() && sim.sample().time > 0.4315 && sim.sample().time < 0.4335 {
                println!("  step t {:.5} kinetic {kinetic:?} x {:.6e} F {:.6} stick {}", sim.sample().time, law_level(alpha_f, v_before, after), sim.sample().friction_force, sim.sample().stick);
            }
            stateful(&mut law_path).commit(LawStep {
                dt,
                sliding_velocity: law_level(alpha_f, v_before, after),
                normal_force: fnormal,
            });
            v_before = after;
        }
        let v_end = sim.sample().relative_velocity;
        let mean = scene.loading.belt_speed - (sim.sample().tip_deflection - u_k) / h;
        match variant.commit {
            Commit::End | Commit::Mean => {
                let v = if variant.commit == Commit::End { v_end } else { mean };
                stateful(&mut law_k).commit(LawStep {
                    dt: h,
                    sliding_velocity: v,
                    normal_force: fnormal,
                });
            }
            Commit::Path => {
                let s = stateful(&mut law_path).state().to_vec();
                stateful(&mut law_k).set_state(&s).unwrap();
            }
        }
        if variant.force != Force::Path && variant.commit != Commit::Path {
            // The path law follows the committed state where it is not the path.
            let s = stateful(&mut law_k).state().to_vec();
            stateful(&mut law_path).set_state(&s).unwrap();
        }
        first = false;
        tips.push(sim.sample().tip_deflection);
        if std::env::var("LAB_TRACE").is_ok() {
            let smp = sim.sample();
            println!(
                "coupled t {:.3} u {:.9e} v_rel {:.3e} F {:.4} state {:?}",
                smp.time,
                smp.tip_deflection,
                smp.relative_velocity,
                smp.friction_force,
                stateful(&mut law_k).state()
            );
        }
    }
    tips
}

/// The scene whose law the coupled beam is built with (any memoryless law: its
/// friction comes from outside).
fn beam_scene_law(scene: &CheckedScene) -> CheckedScene {
    let mut s = scene.scene().clone();
    s.friction.law = FrictionLawKind::Exponential;
    s.friction.weights = None;
    s.check().unwrap()
}

/// The exact force and slope at x of `force`'s model.
#[allow(clippy::too_many_arguments)]
fn exact(
    force: Force,
    probe: &mut Box<dyn FrictionLaw>,
    s_k: &[f64],
    law_path: &mut Box<dyn FrictionLaw>,
    x: f64,
    theta: f64,
    h: f64,
    dt: f64,
    first: bool,
) -> (f64, f64) {
    let p = stateful(probe);
    p.set_state(s_k).unwrap();
    let at = |p: &mut dyn StatefulLaw, span: f64| {
        if first || span <= 0.0 {
            let a = p.force_at_state(x, NORMAL_FORCE);
            (a.force, a.slope)
        } else {
            p.step_force_and_slope(LawStep {
                dt: span,
                sliding_velocity: x,
                normal_force: NORMAL_FORCE,
            })
        }
    };
    match force {
        Force::BlendExact => {
            let a = p.force_at_state(x, NORMAL_FORCE);
            let (fh, sh) = at(p, h);
            (
                (1.0 - theta) * a.force + theta * fh,
                (1.0 - theta) * a.slope + theta * sh,
            )
        }
        Force::RelaxExact => at(p, theta * h),
        Force::StepExact => at(p, h),
        Force::Path => stateful(law_path).step_force_and_slope(LawStep {
            dt,
            sliding_velocity: x,
            normal_force: NORMAL_FORCE,
        }),
        Force::BlendTangent => unreachable!(),
    }
}

/// The oracle table: LAB_LAWS (aging, slip, learned), LAB_STEPS (default 1e-3),
/// LAB_VARIANTS (force/commit/limit, e.g. "blend-tangent/end/50").
#[test]
#[ignore = "measurement"]
fn measure_coupling_oracles() {
    let laws = std::env::var("LAB_LAWS").unwrap_or_else(|_| "aging".into());
    let steps = std::env::var("LAB_STEPS").unwrap_or_else(|_| "1e-3".into());
    let variants = std::env::var("LAB_VARIANTS")
        .unwrap_or_else(|_| "blend-tangent/end/50,blend-exact/end/50,relax-exact/end/50,blend-tangent/path/50,path/path/50,path/path/0".into());
    for law in laws.split(',') {
        let evolution = match law {
            "aging" => Some(StateEvolution::Aging),
            "slip" => Some(StateEvolution::Slip),
            _ => None,
        };
        let scene = scene_of(evolution);
        for h in steps.split(',').map(|x| x.parse::<f64>().unwrap()) {
            let reference = embedded(&scene, h);
            for v in variants.split(',') {
                let parts: Vec<&str> = v.split('/').collect();
                let force = match parts[0] {
                    "blend-tangent" => Force::BlendTangent,
                    "blend-exact" => Force::BlendExact,
                    "relax-exact" => Force::RelaxExact,
                    "step-exact" => Force::StepExact,
                    "path" => Force::Path,
                    other => panic!("{other}"),
                };
                let commit = match parts[1] {
                    "end" => Commit::End,
                    "mean" => Commit::Mean,
                    "path" => Commit::Path,
                    other => panic!("{other}"),
                };
                let static_limit: f64 = parts[2].parse().unwrap();
                let variant = Variant {
                    force,
                    commit,
                    static_limit,
                };
                let run = coupled(&scene, h, variant);
                let (d, p) = coupling_error(&reference, &run, h);
                println!(
                    "{law:8} h {h:e} {v:24}: {:.4} mm, period {:+.2} %, falls {:.4?} (embedded {:.4?})",
                    d * 1e3,
                    p * 100.0,
                    &major_falls(&run, h)[..],
                    &major_falls(&reference, h)[..],
                );
            }
        }
    }
    let _ = STATIC_LIMIT;
}

#[test]
#[ignore = "measurement"]
fn lab_debug_path() {
    let scene = scene_of(Some(StateEvolution::Aging));
    {
        let mut sim = Simulator::new(scene.clone(), law_of(&scene)).unwrap();
        for k in 0..460 {
            sim.advance_to((k + 1) as f64 * 1e-3).unwrap();
            if k % 20 == 0 || (k > 425 && k < 445) {
                let s = sim.sample();
                println!("t {:.3} u {:.9e} v_rel {:.3e} F {:.4} state {:?}", s.time, s.tip_deflection, s.relative_velocity, s.friction_force, &s.law_state[..]);
            }
        }
    }
    let h = 1e-3;
    let reference = embedded(&scene, h);
    let run = coupled(
        &scene,
        h,
        Variant {
            force: Force::Path,
            commit: Commit::Path,
            static_limit: 0.0,
        },
    );
    for (k, (a, b)) in reference.iter().zip(&run).enumerate() {
        if (a - b).abs() > 1e-9 {
            println!("first difference at step {k}: {a} {b}");
            for j in (k..(k + 120).min(run.len())).step_by(6) {
                println!("{j} {:.9e} {:.9e} {:.3e}", reference[j], run[j], run[j] - reference[j]);
            }
            break;
        }
    }
}

/// The reference's own sensitivity: the embedded run against itself with the belt
/// speed moved by a relative 1e-12 and 1e-9, and with the fixed-point slip solver.
#[test]
#[ignore = "measurement"]
fn lab_reference_sensitivity() {
    let h = 1e-3;
    for law in ["aging", "slip", "learned"] {
        let evolution = match law {
            "aging" => Some(StateEvolution::Aging),
            "slip" => Some(StateEvolution::Slip),
            _ => None,
        };
        let scene = scene_of(evolution);
        let reference = embedded(&scene, h);
        for eps in [1e-12, 1e-9, 1e-6] {
            let mut raw = scene.scene().clone();
            raw.loading.belt_speed *= 1.0 + eps;
            let run = embedded(&raw.check().unwrap(), h);
            let (d, p) = coupling_error(&reference, &run, h);
            println!("{law:8} belt x (1 + {eps:e}): {:.4} mm, period {:+.2} %", d * 1e3, p * 100.0);
        }
    }
}
