use stickslip::law_source::LawSource;
use stickslip::run::run_scene;
use stickslip::scene::{FidelityLevel, FrictionLawKind, Scene};

fn scene(law: FrictionLawKind, level: FidelityLevel) -> Scene {
    let mut s = Scene::default();
    s.friction.law = law;
    s.fidelity.level = level;
    s.fidelity.beam_elements = 10;
    s.fidelity.modes = 4;
    s.time.end = 1.2;
    s
}

#[test]
#[ignore]
fn explore_dc() {
    for evolution in [
        stickslip::memory::rate_state::StateEvolution::Aging,
        stickslip::memory::rate_state::StateEvolution::Slip,
    ] {
        for dc in [1e-5, 3e-5, 6e-5, 1e-4, 1.3e-4, 2e-4, 4e-4, 1e-3] {
            let mut s = scene(FrictionLawKind::RateAndState, FidelityLevel::Modal);
            s.friction.rate_and_state.characteristic_slip = dc;
            s.friction.rate_and_state.state_evolution = evolution;
            s.time.end = 3.0;
            let checked = s.check().unwrap();
            let source = LawSource::resolve(&checked).unwrap();
            let run = run_scene(checked, &source, 1).unwrap();
            let late: Vec<_> = run.samples.iter().filter(|x| x.time > 2.0).collect();
            let vmin = late
                .iter()
                .map(|x| x.relative_velocity)
                .fold(f64::MAX, f64::min);
            let vmax = late
                .iter()
                .map(|x| x.relative_velocity)
                .fold(f64::MIN, f64::max);
            let sticks = late.iter().filter(|x| x.stick).count();
            println!("{evolution:?} dc {dc:e}: {:.3}s slips {} vrel late [{vmin:.3e}, {vmax:.3e}] stick samples late {sticks}",
            run.seconds, run.summary.slip_phases);
        }
    }
}

#[test]
#[ignore]
fn explore_sigma() {
    for eps in [1e-4, 1e-5, 1e-6] {
        let reference = {
            let mut s = scene(FrictionLawKind::Exponential, FidelityLevel::Modal);
            s.friction.stick_threshold = eps;
            let checked = s.check().unwrap();
            let source = LawSource::resolve(&checked).unwrap();
            run_scene(checked, &source, 1).unwrap().summary
        };
        println!("ref {:?} {:?}", reference.breakaway, reference.period);
        for sigma0 in [1e7, 1e8, 1e9, 1e10, 1e11] {
            for sigma1 in [0.0] {
                let mut s = scene(FrictionLawKind::Lugre, FidelityLevel::Modal);
                s.friction.lugre.bristle_stiffness = sigma0;
                s.friction.lugre.bristle_damping = sigma1;
                s.friction.lugre.viscous_damping = 0.0;
                s.friction.stick_threshold = eps;
                let checked = s.check().unwrap();
                let source = LawSource::resolve(&checked).unwrap();
                let run = run_scene(checked, &source, 1).unwrap();
                println!("sigma0 {sigma0:e} s1 {sigma1}: {:.3}s breakaway {:?} period {:?} slips {} corridor {:?}", run.seconds, run.summary.breakaway, run.summary.period, run.summary.slip_phases, run.summary.corridor);
            }
        }
    }
}

fn peaks(samples: &[stickslip::simulation::Sample]) -> Vec<f64> {
    let u: Vec<f64> = samples.iter().map(|s| s.tip_deflection).collect();
    let hi = u.iter().cloned().fold(f64::MIN, f64::max);
    let mut out: Vec<f64> = Vec::new();
    for i in 1..u.len() - 1 {
        if u[i] > u[i - 1] && u[i] >= u[i + 1] && u[i] > 0.8 * hi {
            if out.last().map_or(true, |&t| samples[i].time - t > 0.05) {
                out.push(samples[i].time);
            }
        }
    }
    out
}

#[test]
#[ignore]
fn explore_peaks() {
    let run = |s: Scene| {
        let checked = s.check().unwrap();
        let source = LawSource::resolve(&checked).unwrap();
        let r = run_scene(checked, &source, 1).unwrap();
        let p = peaks(&r.samples);
        let period = (p[p.len() - 1] - p[0]) / (p.len() - 1) as f64;
        let hi = r
            .samples
            .iter()
            .map(|s| s.tip_deflection)
            .fold(f64::MIN, f64::max);
        (p[0], period, p.len(), hi)
    };
    let reference = run(scene(FrictionLawKind::Exponential, FidelityLevel::Modal));
    println!("ref {reference:?}");
    for sigma0 in [1e6, 1e7, 1e8, 1e9, 1e10, 1e11] {
        let mut s = scene(FrictionLawKind::Lugre, FidelityLevel::Modal);
        s.friction.lugre.bristle_stiffness = sigma0;
        s.friction.lugre.bristle_damping = 0.0;
        let r = run(s);
        println!(
            "sigma0 {sigma0:e}: {r:?} d_first {:.3e} d_period {:.3e} d_hi {:.3e}",
            r.0 - reference.0,
            r.1 - reference.1,
            r.3 - reference.3
        );
    }
}

#[test]
#[ignore]
fn explore_threshold() {
    let d_star = 4.35e-4;
    for evolution in [
        stickslip::memory::rate_state::StateEvolution::Aging,
        stickslip::memory::rate_state::StateEvolution::Slip,
    ] {
        for f in [0.1, 0.5, 0.7, 0.9, 1.1, 1.5, 3.0] {
            let mut s = scene(FrictionLawKind::RateAndState, FidelityLevel::Modal);
            s.friction.rate_and_state.characteristic_slip = f * d_star;
            s.friction.rate_and_state.state_evolution = evolution;
            s.time.end = 6.0;
            let checked = s.check().unwrap();
            let source = LawSource::resolve(&checked).unwrap();
            let run = run_scene(checked, &source, 1).unwrap();
            let amp = |t0: f64, t1: f64| {
                let w: Vec<f64> = run
                    .samples
                    .iter()
                    .filter(|x| x.time >= t0 && x.time < t1)
                    .map(|x| x.relative_velocity)
                    .collect();
                w.iter().cloned().fold(f64::MIN, f64::max)
                    - w.iter().cloned().fold(f64::MAX, f64::min)
            };
            let sticks = run
                .samples
                .iter()
                .filter(|x| x.time > 4.0 && x.stick)
                .count();
            println!(
                "{evolution:?} {f} D*: amp {:.2e} {:.2e} {:.2e} {:.2e} {:.2e} sticks late {sticks}",
                amp(1.0, 2.0),
                amp(2.0, 3.0),
                amp(3.0, 4.0),
                amp(4.0, 5.0),
                amp(5.0, 6.0)
            );
        }
    }
}

#[test]
#[ignore]
fn explore_drops() {
    for eps in [1e-3, 1e-4, 1e-5] {
        let mut r = scene(FrictionLawKind::Exponential, FidelityLevel::Modal);
        r.fidelity.beam_elements = 100;
        r.friction.stick_threshold = eps;
        let checked = r.check().unwrap();
        let source = LawSource::resolve(&checked).unwrap();
        let s = run_scene(checked, &source, 1).unwrap().samples;
        let hi = s.iter().map(|x| x.tip_deflection).fold(f64::MIN, f64::max);
        let drops: Vec<f64> = s
            .windows(2)
            .filter(|w| w[0].tip_deflection >= 0.8 * hi && w[1].tip_deflection < 0.8 * hi)
            .map(|w| w[0].time)
            .collect();
        println!("ref eps {eps:e}: {drops:?} {hi}");
    }
    for sigma0 in [1e9, 1e10, 1e11, 1e12, 1e13] {
        let mut r = scene(FrictionLawKind::Lugre, FidelityLevel::Modal);
        r.fidelity.beam_elements = 100;
        r.friction.lugre.bristle_stiffness = sigma0;
        r.friction.lugre.bristle_damping = 0.0;
        let checked = r.check().unwrap();
        let source = LawSource::resolve(&checked).unwrap();
        let s = run_scene(checked, &source, 1).unwrap().samples;
        let hi = s.iter().map(|x| x.tip_deflection).fold(f64::MIN, f64::max);
        let drops: Vec<f64> = s
            .windows(2)
            .filter(|w| w[0].tip_deflection >= 0.8 * hi && w[1].tip_deflection < 0.8 * hi)
            .map(|w| w[0].time)
            .collect();
        println!("lugre {sigma0:e}: {drops:?} {hi}");
    }
}
