//! e. NeuralFriction against the paper's law.

use super::*;

/// The paper's law, Eq. 6, with mu_s = 0.5, mu_k = 0.2, alpha = 5 s/m.
fn paper_law(v: f64, normal: f64) -> f64 {
    v.signum() * (0.2 + 0.3 * stickslip::elementary::exp(-5.0 * v.abs())) * normal
}

/// Tolerance of the shipped network (`weights/paper-plain.json`) against Eq. 6 at 0.1 m/s
/// and 100 N. Measured: 37.921 N against 38.196 N, 0.72 %. The network is the paper's
/// plain one: 3 x 100 tanh, trained on 3500 noisy samples of Eq. 6 with v ~ N(0, 0.1 m/s)
/// and a weight penalty. Its error is smallest where the samples are dense and the law
/// is smooth, and 0.1 m/s is such a point, so 1 % holds the measurement with margin and
/// is three times tighter than the 3 % the brief allows.
const NEURAL_TOLERANCE_AT_01: f64 = 0.01;

/// Tolerance over the well-sampled band 5 mm/s <= |v| <= 0.2 m/s (within two standard
/// deviations of the training velocities, away from the jump at v = 0 that the network
/// smooths). Measured worst: 1.50 % at +0.15 m/s. Outside the band the error grows:
/// 6.4 % at +1 mm/s (the smoothed jump), 7.9 % at 0.35 m/s (sparse samples), 20 % at
/// 0.5 m/s, where the input is clamped to the training range (max 0.361 m/s).
const NEURAL_TOLERANCE_BAND: f64 = 0.02;

#[test]
fn e_neural_friction_fmu_matches_the_law() {
    let import = import(FmuKind::NeuralFriction);
    let vrs = FrictionVrs::of(&import);

    // Exponential law: Eq. 6 to 1e-12, signed, and the static limit mu_s F_n.
    let mut exponential = start_friction(
        &import,
        "friction-exponential",
        Some(NeuralFrictionLaw::EXPONENTIAL),
    );
    let mut law = [0i32; 1];
    exponential.get_integer(&[vrs.law], &mut law).expect("law");
    assert_eq!(law[0], NeuralFrictionLaw::EXPONENTIAL.code());
    for v in [0.1, -0.1] {
        let [force, magnitude, coefficient, limit] = friction_at(&mut exponential, &vrs, v, 100.0);
        let expected = v.signum() * (0.2 + 0.3 * stickslip::elementary::exp(-5.0 * 0.1)) * 100.0;
        assert!(
            (force - expected).abs() <= 1e-12,
            "exponential at v = {v}: {force} N, expected {expected} N"
        );
        assert_eq!(magnitude, force.abs());
        assert!((coefficient - expected.abs() / 100.0).abs() <= 1e-14);
        assert_eq!(limit, 50.0);
    }
    // Outputs follow inputs after a step too.
    exponential.do_step(0.0, H, true).expect("do_step");
    let [force, ..] = friction_at(&mut exponential, &vrs, 0.05, 80.0);
    assert!((force - paper_law(0.05, 80.0)).abs() <= 1e-12);

    // The default law is the shipped network.
    let mut neural = start_friction(&import, "friction-neural", None);
    neural.get_integer(&[vrs.law], &mut law).expect("law");
    assert_eq!(law[0], NeuralFrictionLaw::NEURAL.code());
    let [force, magnitude, _, limit] = friction_at(&mut neural, &vrs, 0.1, 100.0);
    let expected = paper_law(0.1, 100.0);
    let error_at_01 = (force - expected).abs() / expected.abs();
    assert!(
        error_at_01 <= NEURAL_TOLERANCE_AT_01,
        "neural at 0.1 m/s: {force} N vs {expected} N ({:.3} %)",
        100.0 * error_at_01
    );
    assert!(force > 0.0, "the force acts in the direction of v_rel");
    assert_eq!(magnitude, force.abs());
    assert_eq!(limit, 50.0, "static_limit is mu_s F_n exactly");

    let mut worst = (0.0f64, 0.0);
    for v in [
        -0.2, -0.15, -0.1, -0.08, -0.05, -0.03, -0.02, -0.01, -0.005, 0.005, 0.01, 0.02, 0.03,
        0.05, 0.08, 0.1, 0.15, 0.2,
    ] {
        let [force, ..] = friction_at(&mut neural, &vrs, v, 100.0);
        let error = (force - paper_law(v, 100.0)).abs() / paper_law(v, 100.0).abs();
        if error > worst.0 {
            worst = (error, v);
        }
    }
    assert!(
        worst.0 <= NEURAL_TOLERANCE_BAND,
        "neural: {:.3} % off at v = {} m/s",
        100.0 * worst.0,
        worst.1
    );
    // The FMU evaluates the same network as the library, and clamps the input to the
    // training range (max 0.361 m/s) like it.
    let network = stickslip::neural::NeuralLaw::paper_default().expect("shipped weights");
    let v_max = network
        .model()
        .features
        .iter()
        .find(|f| f.role == stickslip::neural::FeatureRole::SlidingVelocity)
        .expect("a sliding-velocity feature")
        .max;
    let [beyond, ..] = friction_at(&mut neural, &vrs, 0.5, 100.0);
    let [at_max, ..] = friction_at(&mut neural, &vrs, v_max, 100.0);
    assert!(v_max < 0.5);
    assert_eq!(beyond.to_bits(), at_max.to_bits());
    let mut library = network.into_friction_law().expect("a beam law");
    let [force, ..] = friction_at(&mut neural, &vrs, 0.1, 100.0);
    assert_eq!(force.to_bits(), library.sliding_force(0.1, 100.0).to_bits());
    println!(
        "neural friction: {force:.6} N at 0.1 m/s vs Eq. 6 {expected:.6} N ({:.3} %); worst {:.3} % at {} m/s",
        100.0 * error_at_01,
        100.0 * worst.0,
        worst.1
    );
}
