//! Oracle experiments on the step coupling of a law with state (issue 36): the
//! coupled loop of `friction_laws_coupled` replayed on the physics crate's `Simulator`,
//! internal step by internal step, so that single pieces of the coupling can be made
//! exact (the force curve the beam solves within a communication step, the state the
//! friction side commits, the set-valued stick) and the piece that carries the coupling
//! error found. Printed, not asserted (`measure_coupling_oracles`, #[ignore]d; the
//! numbers and what they decided: docs/cosimulation.md, "Where the aging and learned
//! laws' coupling error comes from").
//!
//! Each internal step of a variant other than the shipped tangent is solved here, not by
//! the beam: x(F), the law-level v_rel at the step's end under a tip force F, is affine
//! in the slip branch, so two probe steps (F = 0 and 50 N, no static limit, the state
//! restored after each) give it, F = F_model(x(F)) is solved by bisection, and the beam
//! takes the step with the tangent of the model at that root (its own Newton then ends
//! there in one pass). The shipped variant (`blend-tangent`, the law's own static limit
//! and commit) reproduces `measure_step_consistent_coupling`'s numbers through the FMUs
//! (LuGre 0.0069 mm, slip law 0.0664 mm, aging 0.1378 mm, learned 0.1684 mm at 1e-3 s),
//! and `path/path/0` (the embedded law's own step from the state committed at every
//! internal step, no set-valued stick) the embedded run to 0.6 um (aging, learned) and
//! 0.9 um (slip law): the harness adds no error of its own.

use crate::friction_laws_coupled::{coupling_error, major_falls};
use std::sync::{Arc, Mutex};
use stickslip::choice::Choice;
use stickslip::friction::rate_and_state::{StateEvolution, STATE_EVOLUTION};
use stickslip::friction::state::{LawStep, StatefulLaw};
use stickslip::friction::{FrictionLaw, FrictionLawKind};
use stickslip::law_source::LawSource;
use stickslip::scene::{CheckedScene, Scene};
use stickslip::simulation::{ExternalFriction, ExternalKinetic, Simulator};

const END: f64 = 1.2;
const NORMAL_FORCE: f64 = 100.0;

/// The law of a run: rate-and-state (`Some(evolution)`) or the learned law (`None`).
fn scene_of(evolution: Option<StateEvolution>) -> CheckedScene {
    raw_scene(evolution).check().unwrap()
}

fn raw_scene(evolution: Option<StateEvolution>) -> Scene {
    let mut scene = base_scene();
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

/// The paper's scene to `END`, its belt speed from LAB_BELT_SPEED (m/s) if set.
fn base_scene() -> Scene {
    let mut scene = Scene::default();
    scene.time.end = END;
    if let Ok(v) = std::env::var("LAB_BELT_SPEED") {
        scene.loading.belt_speed = v.parse().unwrap();
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
    /// The blend of `BlendExact` known only at nodes v_k and v_k +- d (d from
    /// LAB_NODES; with LAB_NODES_AT_ZERO at v_k, 0 and +- d), with its slopes there, interpolated piecewise linearly (`hermite`
    /// false) or by monotone cubic Hermite (Fritsch-Carlson) and extrapolated along the
    /// end nodes' tangents: what NeuralFriction could hand over as a table. With
    /// `step_only` the instantaneous curve is the tangent at v_k as now, and only F_h is
    /// tabulated (half the values).
    Table {
        hermite: bool,
        step_only: bool,
        /// The beam's own slip solve (`contact::newton`, with its bracket and the
        /// jump rule) solves the interpolant, handed to it as a memoryless law, with
        /// no static limit; not the lab's bisection.
        beam_solves: bool,
    },
}

/// The interpolant of `Force::Table` of the current internal step.
#[derive(Clone, Default)]
struct TableCurve {
    xs: Vec<f64>,
    ys: Vec<f64>,
    ms: Vec<f64>,
    hermite: bool,
}

/// The interpolant as a memoryless law for the beam's own solve (`beam_solves`).
struct TableLaw(Arc<Mutex<TableCurve>>);

impl FrictionLaw for TableLaw {
    fn name(&self) -> &str {
        "tabulated step curves"
    }

    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        self.sliding_force_and_slope(sliding_velocity, normal_force)
            .0
    }

    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, _normal_force: f64) -> (f64, f64) {
        let c = self.0.lock().unwrap();
        interpolate(&c.xs, &c.ys, &c.ms, c.hermite, sliding_velocity)
    }
}

/// The node offsets (m/s) of `Force::Table` around v_k.
fn node_offsets() -> Vec<f64> {
    std::env::var("LAB_NODES")
        .unwrap_or_else(|_| "1e-6,1e-5,1e-4,1e-3,1e-2".into())
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect()
}

/// The interpolant of `Force::Table` at x: value and slope.
fn interpolate(xs: &[f64], ys: &[f64], ms: &[f64], hermite: bool, x: f64) -> (f64, f64) {
    let n = xs.len();
    if x <= xs[0] {
        return (ys[0] + ms[0] * (x - xs[0]), ms[0]);
    }
    if x >= xs[n - 1] {
        return (ys[n - 1] + ms[n - 1] * (x - xs[n - 1]), ms[n - 1]);
    }
    let i = xs.windows(2).position(|w| x < w[1]).unwrap();
    let w = xs[i + 1] - xs[i];
    let delta = (ys[i + 1] - ys[i]) / w;
    if !hermite {
        return (ys[i] + delta * (x - xs[i]), delta);
    }
    let limit = |m: f64| {
        if delta == 0.0 || m * delta <= 0.0 {
            0.0
        } else if m / delta > 3.0 {
            3.0 * delta
        } else {
            m
        }
    };
    let (m0, m1) = (limit(ms[i]), limit(ms[i + 1]));
    let t = (x - xs[i]) / w;
    let (t2, t3) = (t * t, t * t * t);
    let value = (2.0 * t3 - 3.0 * t2 + 1.0) * ys[i]
        + (t3 - 2.0 * t2 + t) * w * m0
        + (-2.0 * t3 + 3.0 * t2) * ys[i + 1]
        + (t3 - t2) * w * m1;
    let slope = ((6.0 * t2 - 6.0 * t) * ys[i] + (6.0 * t - 6.0 * t2) * ys[i + 1]) / w
        + (3.0 * t2 - 4.0 * t + 1.0) * m0
        + (3.0 * t2 - 2.0 * t) * m1;
    (value, slope)
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
    /// Jacobi instead of Gauss-Seidel (beam first): NeuralFriction's outputs at t_k
    /// are at the v_rel(t_k-1) it was given, and it commits with v_rel(t_k) or the
    /// previous step's mean, as `friction_laws_coupled::coupled_holding` runs it.
    jacobi: bool,
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

/// The coupled run, Gauss-Seidel (or Jacobi: `Variant::jacobi`), communication step
/// `h`, the beam's internal steps taken one by one.
fn coupled(scene: &CheckedScene, h: f64, variant: Variant) -> Vec<f64> {
    let beam_solves = matches!(
        variant.force,
        Force::Table {
            beam_solves: true,
            ..
        }
    );
    let curve = Arc::new(Mutex::new(TableCurve::default()));
    let mut sim = if beam_solves {
        // The law the beam solves is the table; no set-valued stick (mu_s = 0).
        let mut raw = beam_scene_law(scene).scene().clone();
        raw.friction.static_coefficient = 0.0;
        raw.friction.kinetic_coefficient = 0.0;
        Simulator::new(raw.check().unwrap(), Box::new(TableLaw(curve.clone()))).unwrap()
    } else {
        let beam_scene = beam_scene_law(scene);
        Simulator::new(beam_scene.clone(), law_of(&beam_scene)).unwrap()
    };
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
    // NeuralFriction's inputs sliding_velocity and mean_sliding_velocity, and the beam's
    // output mean_relative_velocity (before the first step: v_rel at the start).
    let mut f_v = sim.sample().relative_velocity;
    let mut f_mean = f_v;
    let mut beam_mean = f_v;
    for _ in 0..steps {
        let v_k = f_v;
        if variant.jacobi {
            f_v = sim.sample().relative_velocity;
            f_mean = beam_mean;
        }
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
        // Force::Table: the nodes and the two curves' values and slopes there.
        let mut xs = vec![v_k];
        let mut step_only = false;
        if let Force::Table {
            step_only: only, ..
        } = variant.force
        {
            step_only = only;
            // LAB_NODES_AT_ZERO: the nodes +-d around 0 (and 0) instead of around v_k.
            let centre = if std::env::var("LAB_NODES_AT_ZERO").is_ok() {
                xs.push(0.0);
                0.0
            } else {
                v_k
            };
            for d in node_offsets() {
                xs.push(centre - d);
                xs.push(centre + d);
            }
            xs.sort_by(f64::total_cmp);
            xs.dedup();
        }
        let nodes: Vec<[f64; 4]> = xs
            .iter()
            .map(|&x| {
                let law = stateful(&mut law_k);
                let a = law.force_at_state(x, fnormal);
                let (fh, sh) = if first {
                    (a.force, a.slope)
                } else {
                    law.step_force_and_slope(LawStep {
                        dt: h,
                        sliding_velocity: x,
                        normal_force: fnormal,
                    })
                };
                if step_only {
                    [inst.force + inst.slope * (x - v_k), inst.slope, fh, sh]
                } else {
                    [a.force, a.slope, fh, sh]
                }
            })
            .collect();
        let mut v_before = v_k;
        for j in 1..=n {
            let theta = j as f64 / n as f64;
            if beam_solves {
                let mut c = curve.lock().unwrap();
                c.xs.clone_from(&xs);
                c.ys = nodes
                    .iter()
                    .map(|n| (1.0 - theta) * n[0] + theta * n[2])
                    .collect();
                c.ms = nodes
                    .iter()
                    .map(|n| (1.0 - theta) * n[1] + theta * n[3])
                    .collect();
                c.hermite = true;
            }
            let kinetic = if beam_solves {
                None
            } else if variant.force == Force::BlendTangent {
                Some(step_kinetic(
                    (1.0 - theta) * inst.force + theta * f_h,
                    (1.0 - theta) * inst.slope + theta * s_h,
                    v_k,
                ))
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
                let ys: Vec<f64> = nodes
                    .iter()
                    .map(|n| (1.0 - theta) * n[0] + theta * n[2])
                    .collect();
                let ms: Vec<f64> = nodes
                    .iter()
                    .map(|n| (1.0 - theta) * n[1] + theta * n[3])
                    .collect();
                let mut model = |x: f64| {
                    if let Force::Table { hermite, .. } = variant.force {
                        return interpolate(&xs, &ys, &ms, hermite, x);
                    }
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
                // r(F) = F - F_model(x(F)), bisected to the last bits on [-1, 1] kN
                // (|F_model| < 1 kN; a Newton iteration from F = 0 cycled at a slip's
                // start without converging).
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
                Some(step_kinetic(force, slope, x))
            };
            sim.set_external_friction(kinetic.map(|kinetic| ExternalFriction {
                kinetic,
                static_limit: variant.static_limit,
            }));
            sim.step().unwrap();
            let after = sim.sample().relative_velocity;
            stateful(&mut law_path).commit(LawStep {
                dt,
                sliding_velocity: law_level(alpha_f, v_before, after),
                normal_force: fnormal,
            });
            v_before = after;
        }
        beam_mean = scene.loading.belt_speed - (sim.sample().tip_deflection - u_k) / h;
        if !variant.jacobi {
            f_v = sim.sample().relative_velocity;
            f_mean = beam_mean;
        }
        match variant.commit {
            Commit::End | Commit::Mean => {
                let v = if variant.commit == Commit::End {
                    f_v
                } else {
                    f_mean
                };
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
        Force::BlendTangent | Force::Table { .. } => unreachable!(),
    }
}

/// The oracle table, Gauss-Seidel unless asked, default fidelity, against each law embedded:
/// LAB_LAWS (lugre, aging, slip, learned; default aging), LAB_STEPS (communication
/// steps, default 1e-3), LAB_VARIANTS (force/commit/static limit in N, e.g.
/// "blend-tangent/end/50"; forces blend-tangent, blend-exact, relax-exact, step-exact,
/// path, table-linear, table-hermite, table-hermite-beam, step-table-hermite; commits end, mean, path),
/// LAB_NODES (the table's offsets, m/s), LAB_NODES_AT_ZERO (the table's nodes at 0 and
/// +- the offsets, with v_k, instead of around v_k), LAB_DIFFERENCES (print the tip difference at
/// a few times up to the first fall), LAB_BELT_SPEED (m/s); a fourth part "/jacobi" runs Jacobi. The `step` coupling as
/// it shipped before `table`: LuGre blend-tangent/mean/0, the slip law
/// blend-tangent/mean/50, aging and learned blend-tangent/end/50. The shipped `table`
/// coupling is table-linear beam-solved with LAB_NODES_AT_ZERO, mean, 0 (measured
/// through the FMUs in `friction_laws_coupled`).
#[test]
#[ignore = "measurement"]
fn measure_coupling_oracles() {
    let laws = std::env::var("LAB_LAWS").unwrap_or_else(|_| "aging".into());
    let steps = std::env::var("LAB_STEPS").unwrap_or_else(|_| "1e-3".into());
    let variants = std::env::var("LAB_VARIANTS").unwrap_or_else(|_| {
        "blend-tangent/end/50,blend-exact/end/50,relax-exact/end/50,blend-tangent/path/50,path/path/50,path/path/0".into()
    });
    for law in laws.split(',') {
        let evolution = match law {
            "aging" => Some(StateEvolution::Aging),
            "slip" => Some(StateEvolution::Slip),
            _ => None,
        };
        let scene = if law == "lugre" {
            let mut raw = base_scene();
            raw.friction.law = FrictionLawKind::Lugre;
            raw.check().unwrap()
        } else {
            scene_of(evolution)
        };
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
                    "table-linear" => Force::Table {
                        hermite: false,
                        step_only: false,
                        beam_solves: false,
                    },
                    "table-hermite" => Force::Table {
                        hermite: true,
                        step_only: false,
                        beam_solves: false,
                    },
                    "table-hermite-beam" => Force::Table {
                        hermite: true,
                        step_only: false,
                        beam_solves: true,
                    },
                    "step-table-hermite" => Force::Table {
                        hermite: true,
                        step_only: true,
                        beam_solves: false,
                    },
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
                    jacobi: parts.get(3) == Some(&"jacobi"),
                };
                let run = coupled(&scene, h, variant);
                let (d, p) = coupling_error(&reference, &run, h);
                if std::env::var("LAB_DIFFERENCES").is_ok() {
                    for t in [0.1, 0.2, 0.3, 0.35, 0.4, 0.43, 0.45] {
                        let k = (t / h).round() as usize - 1;
                        println!(
                            "  t {t}: tip {:.6e} m, coupled - embedded {:.3e} m",
                            reference[k],
                            run[k] - reference[k]
                        );
                    }
                }
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
}
