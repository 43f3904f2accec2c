//! Where the friction force of the paper scene reverses within a slip step (issue 37):
//! for each fidelity at the paper's step and at a reference step, the slip steps in which
//! v_rel changes sign, the steps whose slip equation has no solution (zero inside the
//! law's jump at v = 0), what the switch made of them, and the samples after breakaway
//! whose friction force is negative (the converged run has none); then the modes of the
//! model with their damping under generalised-alpha. Run with
//! `cargo run --release -p stickslip --example reversals [END_S] [REFERENCE_DT_S]`
//! (default 3 s and 2e-6 s; the plane-stress reference takes about two minutes).
//!
//! Measured (3 s, paper scene, exponential law, generalised-alpha), before the fix of
//! issue 37 -> after, at dt = 1e-4 s: steps without solution 210 -> 63 (modal), 487 ->
//! 63 (beam), 68 -> 60 (plane stress), of which re-stuck 45 -> 57, 56 -> 57, 61 -> 58;
//! samples below -1 N 21 -> 0, 58 -> 0, 3 -> 0. At dt = 2e-6 s the same steps occur
//! (67 -> 71, 65 -> 63, 56 with the fix) and left 5 (modal) and 2 (beam) such samples
//! before the fix, none after: the steps are the tip reaching the belt's speed within
//! a step, at every step size, and only the force taken there was wrong. The modes:
//! generalised-alpha's numerical damping is below 1.2e-4 in the eight lowest (omega dt
//! <= 0.57 at 1e-4 s); the law's negative damping at v -> 0 (-0.42 in mode 1, -0.024 in
//! mode 3) exceeds the Rayleigh damping (0.0009, 0.016) in modes 1 to 3 only, the
//! physical stick-slip instability, not a high mode.
//!
//! Per mode (omega from the model's eigenpairs, phi mass-normalised):
//! - numerical damping of generalised-alpha at rho_inf and dt: zeta = -ln|lambda| /
//!   arg(lambda), lambda the complex eigenvalue of the undamped one-mode step (Chung and
//!   Hulbert, J. Appl. Mech. 60 (1993) 371);
//! - physical (Rayleigh) damping zeta = a / (2 omega) + b omega / 2;
//! - the law's negative damping at v -> 0: a tip dashpot of -dF/dv = (mu_s - mu_k) alpha
//!   F_n (N s/m) gives the mode zeta = dF/dv phi_tip^2 / (2 omega) (negative).

use std::env;
use stickslip::elementary::{atan2, ln};
use stickslip::integrator::Coefficients;
use stickslip::law_source::LawSource;
use stickslip::modal::modes_of;
use stickslip::scene::{CheckedScene, FidelityLevel, Scene};
use stickslip::simulation::Simulator;
use stickslip::structure::StructuralModel;

/// What one run's slip steps did.
#[derive(Default)]
struct Counts {
    slip_steps: usize,
    /// Slip steps in which v_rel changed sign.
    crossings: usize,
    /// ... of which the step ended in stick.
    crossings_restuck: usize,
    /// Slip steps whose equation had no solution.
    unsolved: usize,
    /// ... of which the step ended in stick.
    unsolved_restuck: usize,
    /// Slip steps that ended in slip with F v_rel,n+1 < 0 (the force along the tip's
    /// motion relative to the belt).
    against: usize,
    /// Samples after breakaway with F < -1 N, and the first of them (s).
    negative: usize,
    first_negative: Vec<f64>,
}

fn scene(level: FidelityLevel, dt: f64, end: f64) -> CheckedScene {
    let mut scene = Scene::default();
    scene.fidelity.level = level;
    scene.time.step = dt;
    scene.time.end = end;
    scene.check().expect("the paper scene")
}

fn count(scene: &CheckedScene) -> Counts {
    let law = LawSource::resolve(scene).unwrap().law().unwrap();
    let mut sim = Simulator::new(scene.clone(), law).unwrap();
    let steps = (scene.time.end / scene.time.step).round() as u64;
    let mut counts = Counts::default();
    let mut broken_away = false;
    for _ in 0..steps {
        let before = sim.sample();
        sim.step().unwrap();
        let after = sim.sample();
        broken_away |= !after.stick;
        if broken_away && after.friction_force < -1.0 {
            counts.negative += 1;
            if counts.first_negative.len() < 5 {
                counts.first_negative.push(after.time);
            }
        }
        let Some(solve) = sim.last_slip_solve() else {
            continue;
        };
        if before.stick {
            continue;
        }
        counts.slip_steps += 1;
        let crossed = before.relative_velocity * after.relative_velocity < 0.0;
        if crossed {
            counts.crossings += 1;
            counts.crossings_restuck += usize::from(after.stick);
        }
        if !solve.solved {
            counts.unsolved += 1;
            counts.unsolved_restuck += usize::from(after.stick);
        }
        if !after.stick && after.friction_force * after.relative_velocity < 0.0 {
            counts.against += 1;
        }
    }
    counts
}

/// zeta of generalised-alpha's undamped step of a mode at omega dt = `omega_dt`.
fn numerical_damping(coefficients: Coefficients, omega_dt: f64) -> f64 {
    let Coefficients::GeneralizedAlpha {
        alpha_m,
        alpha_f,
        gamma,
        beta,
    } = coefficients
    else {
        return 0.0;
    };
    // One step of u'' + omega^2 u = 0 from each unit state (u, v dt, a dt^2): the
    // balance at the alpha levels with Newmark's updates, solved for a_{n+1}.
    let w2 = omega_dt * omega_dt;
    let step = |u: f64, v: f64, a: f64| {
        // u1 = u + v + (1/2 - beta) a + beta a1, v1 = v + (1 - gamma) a + gamma a1
        let u_pred = u + v + (0.5 - beta) * a;
        let a1 = -(alpha_m * a + w2 * ((1.0 - alpha_f) * u_pred + alpha_f * u))
            / ((1.0 - alpha_m) + w2 * (1.0 - alpha_f) * beta);
        [u_pred + beta * a1, v + (1.0 - gamma) * a + gamma * a1, a1]
    };
    let columns = [
        step(1.0, 0.0, 0.0),
        step(0.0, 1.0, 0.0),
        step(0.0, 0.0, 1.0),
    ];
    let matrix = nalgebra::Matrix3::from_fn(|i, j| columns[j][i]);
    let lambda = matrix
        .complex_eigenvalues()
        .iter()
        .copied()
        .max_by(|x, y| x.im.abs().total_cmp(&y.im.abs()))
        .unwrap();
    -ln(lambda.norm()) / atan2(lambda.im, lambda.re).abs()
}

fn main() {
    let args: Vec<f64> = env::args().skip(1).map(|a| a.parse().unwrap()).collect();
    let end = args.first().copied().unwrap_or(3.0);
    let reference = args.get(1).copied().unwrap_or(2e-6);
    println!("| fidelity | dt (s) | slip steps | v_rel crossings (re-stuck) | no solution (re-stuck) | slip with F v_rel < 0 | samples F < -1 N | first (s) |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    for level in [
        FidelityLevel::Modal,
        FidelityLevel::Beam,
        FidelityLevel::PlaneStress,
    ] {
        for dt in [1e-4, reference] {
            let c = count(&scene(level, dt, end));
            let first: Vec<String> = c.first_negative.iter().map(|t| format!("{t:.4}")).collect();
            println!(
                "| {level:?} | {dt:.0e} | {} | {} ({}) | {} ({}) | {} | {} | {} |",
                c.slip_steps,
                c.crossings,
                c.crossings_restuck,
                c.unsolved,
                c.unsolved_restuck,
                c.against,
                c.negative,
                first.join(", ")
            );
        }
    }
    println!();
    println!("| fidelity | mode | omega (rad/s) | omega dt | phi_tip^2 (1/kg) | zeta numerical | zeta Rayleigh | zeta law (v -> 0) |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    for level in [
        FidelityLevel::Modal,
        FidelityLevel::Beam,
        FidelityLevel::PlaneStress,
    ] {
        let scene = scene(level, 1e-4, end);
        let model = StructuralModel::build(&scene).unwrap();
        let modes = modes_of(&model, 8.min(model.dofs())).unwrap();
        let f = &scene.friction;
        let law_slope =
            (f.static_coefficient - f.kinetic_coefficient) * f.decay * scene.loading.normal_force;
        let coefficients = Coefficients::from_scene(&scene);
        for (k, (lambda, phi)) in modes.eigenvalues.iter().zip(&modes.vectors).enumerate() {
            let omega = lambda.sqrt();
            let tip = model.tip_value(phi);
            let d = &scene.damping;
            let rayleigh =
                d.mass_proportional / (2.0 * omega) + d.stiffness_proportional * omega / 2.0;
            println!(
                "| {level:?} | {} | {omega:.1} | {:.3} | {:.4} | {:.2e} | {:.2e} | {:.2e} |",
                k + 1,
                omega * scene.time.step,
                tip * tip,
                numerical_damping(coefficients, omega * scene.time.step),
                rayleigh,
                -law_slope * tip * tip / (2.0 * omega),
            );
        }
    }
}
