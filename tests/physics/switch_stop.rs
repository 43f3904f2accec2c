//! `Simulator::advance_until_switch`: advancing towards a target but stopping at the end
//! of the internal step in which the contact switched (what an FMI 3.0 co-simulation FMU
//! needs for an early return), against `advance_to`.

use stickslip::contact::ContactState;
use stickslip::scene::{CheckedScene, FidelityLevel};
use stickslip::simulation::Simulator;

/// The paper's scene at modal fidelity: breakaway at 0.4 s, then stick-slip cycles.
fn simulator(end: f64) -> Simulator {
    let mut scene = CheckedScene::paper().into_scene();
    scene.fidelity.level = FidelityLevel::Modal;
    scene.time.end = end;
    let scene = scene.check().unwrap();
    let law = scene.friction.exponential_law();
    Simulator::new(scene, Box::new(law)).unwrap()
}

/// Communication points k h, with h off the internal grid (1e-3 s) so that landing
/// steps, split landings included, are exercised.
fn targets(h: f64, end: f64) -> Vec<f64> {
    let n = (end / h).round() as usize;
    (1..=n).map(|k| k as f64 * h).collect()
}

#[test]
fn without_a_switch_it_is_advance_to_bit_for_bit() {
    // Up to 0.35 s the tip sticks: no switch, so every call must reach its target with
    // the same state as advance_to.
    for h in [1e-2, 2.7e-3, 1.3e-3] {
        let mut a = simulator(0.35);
        let mut b = simulator(0.35);
        for t in targets(h, 0.35) {
            a.advance_to(t).unwrap();
            assert_eq!(b.advance_until_switch(t).unwrap(), None, "h = {h}, t = {t}");
            assert_eq!(a.state(), b.state(), "h = {h}, t = {t}");
        }
        assert_eq!(a.state().transition_count, 0);
    }
}

#[test]
fn it_stops_at_the_recorded_transition_time_and_otherwise_follows_advance_to() {
    let end = 1.0;
    for h in [1e-2, 2.7e-3, 1.3e-3] {
        let mut reference = simulator(end);
        let mut stopping = simulator(end);
        let mut switches = Vec::new();
        let on_grid = h == 1e-2;
        for t in targets(h, end) {
            reference.advance_to(t).unwrap();
            // Advance the stopping run to the same target, one switch at a time.
            loop {
                let before = stopping.state().transition_count;
                let from = stopping.state().time;
                match stopping.advance_until_switch(t).unwrap() {
                    None => {
                        assert_eq!(stopping.state().transition_count, before);
                        assert_eq!(stopping.state().time, t);
                        break;
                    }
                    Some(at) => {
                        // Exactly one switch, at the end of the step that made it.
                        assert_eq!(stopping.state().transition_count, before + 1);
                        let last = *stopping.transitions().last().unwrap();
                        assert_eq!(stopping.state().time, at);
                        let dt = stopping.scene().time.step;
                        assert!(
                            (last.time - at).abs() <= 1e-9 * dt,
                            "h = {h}: recorded {} s, returned {at} s",
                            last.time
                        );
                        assert!(at > from && at <= t + 1e-12, "{from} < {at} <= {t}");
                        assert_eq!(stopping.state().contact, last.to);
                        switches.push(at);
                        if at == t {
                            break;
                        }
                    }
                }
            }
            if on_grid {
                // Every stop is at the end of a full step: the grid is advance_to's.
                assert_eq!(reference.state(), stopping.state(), "h = {h}, t = {t}");
            }
        }
        // The stopping run makes the same switches, each within one internal step of
        // advance_to's (the step grid differs only after a stop inside a landing).
        let expected: Vec<f64> = reference.transitions().iter().map(|t| t.time).collect();
        assert!(expected.len() >= 3, "{} transitions", expected.len());
        assert_eq!(switches.len(), expected.len(), "h = {h}");
        let dt = reference.scene().time.step;
        for (a, b) in switches.iter().zip(&expected) {
            assert!((a - b).abs() <= dt, "h = {h}: {a} s against {b} s");
        }
        assert_eq!(
            stopping.transitions().first().map(|t| t.to),
            Some(ContactState::Slip)
        );
        // Stopping changes nothing but where the calls end: the tip is where advance_to
        // leaves it to a small fraction of the 1 cm amplitude.
        let (u_ref, u) = (
            reference.sample().tip_deflection,
            stopping.sample().tip_deflection,
        );
        assert!((u_ref - u).abs() < 1e-6, "h = {h}: {u_ref} m against {u} m");
    }
}
