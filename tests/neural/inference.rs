//! Inference of the shipped networks as the beam's friction law: the force's exact slope
//! (forward mode through the network) that the slip solve's Newton iteration uses.

use stickslip::friction::FrictionLaw;
use stickslip::neural::NeuralLaw;

fn shipped() -> [(&'static str, NeuralLaw); 2] {
    [
        ("plain", NeuralLaw::paper_default().unwrap()),
        ("signed", NeuralLaw::paper_signed().unwrap()),
    ]
}

/// dF/dv by forward mode against a central difference (F(v + h) - F(v - h)) / 2h at
/// h = 1e-7 m/s. The difference's error is F^(3) h^2 / 6 + eps |F| / h: the plain
/// network's zero crossing is steep (slopes up to ~1e6 N s/m over ~1e-3 m/s, so F^(3) up
/// to ~1e12 N s^3/m^3), giving up to ~1e-3 N s/m, and rounding ~1e-7 N s/m: 1e-6
/// relative plus 1e-5 N s/m bounds both. The force is the same number as
/// `sliding_force`'s.
#[test]
fn network_slope_is_the_derivative_of_the_force() {
    let h = 1e-7;
    for (name, mut law) in shipped() {
        for v in [-0.35, -0.05, -2e-3, -1e-4, 1e-4, 5e-4, 0.02, 0.2, 0.39] {
            for f_n in [92.0, 100.0, 108.0] {
                let (force, slope) = law.sliding_force_and_slope(v, f_n);
                assert_eq!(
                    force.to_bits(),
                    law.sliding_force(v, f_n).to_bits(),
                    "{name} v {v}"
                );
                let difference =
                    (law.sliding_force(v + h, f_n) - law.sliding_force(v - h, f_n)) / (2.0 * h);
                assert!(
                    (slope - difference).abs() <= 1e-6 * slope.abs() + 1e-5,
                    "{name} v {v} F_n {f_n}: slope {slope}, difference {difference}"
                );
            }
        }
        // Clamped to the training range (|v| <= 0.4 m/s): flat beyond it.
        let (_, slope) = law.sliding_force_and_slope(0.6, 100.0);
        assert_eq!(slope, 0.0, "{name}");
    }
    // The plain network's smoothed jump is steep at v = 0, the signed one's magnitude
    // falls there like the paper's law, -alpha (mu_s - mu_k) F_n = -150 N s/m.
    let [(_, mut plain), (_, mut signed)] = shipped();
    assert!(plain.sliding_force_and_slope(0.0, 100.0).1 > 1e4);
    let (force, slope) = signed.sliding_force_and_slope(0.0, 100.0);
    assert_eq!(force, 0.0);
    assert!((slope + 150.0).abs() < 15.0, "{slope}");
}
