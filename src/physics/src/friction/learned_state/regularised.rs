//! The rate-and-state friction force regularised at v = 0 (Rice & Ben-Zion 1996;
//! Lapusta et al. 2000):
//!
//! ```text
//! F = F_n a asinh( v / (2 V_0) exp(Omega / a) ),   Omega = mu_0 + b psi (+ correction)
//! ```
//!
//! with psi = ln(theta V_0 / D_c). For |v| >> 2 V_0 exp(-Omega/a) this is
//! sign(v) F_n [mu_0 + a ln(|v| / V_0) + b psi], the Dieterich-Ruina law; at v = 0 it
//! is 0 and odd and smooth across, with slope F_n a exp(Omega/a) / (2 V_0), so that
//! sticking and reversal are defined. Units: v, V_0 in m/s; F_n, F in N; a, Omega 1.

/// The force and its partial derivatives at fixed state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegularisedForce {
    /// F (N).
    pub force: f64,
    /// dF/dv at fixed Omega (N s/m), > 0.
    pub d_velocity: f64,
    /// dF/d Omega (N), F_n sign(v) q with q = y / sqrt(1 + y^2), y = |v| E.
    pub d_level: f64,
    /// dF/da at fixed Omega (N).
    pub d_direct: f64,
}

/// Above this ln y, asinh(y) = ln(2 y) to within 1/(4 y^2) < 1e-26.
const LOG_ASYMPTOTE: f64 = 30.0;
/// ln E is capped here so that the slope at v = 0, F_n a E, stays finite (e^700 ~
/// 1e304): a law that steep is a jump for any solver. The analytical law's parameter
/// range and the weights file's check hold its initial state below the cap; only a
/// state or a correction that moves Omega / a above it reaches the cap.
const LOG_SCALE_CAP: f64 = crate::friction::rate_and_state::LARGEST_LOG_SCALE;

/// 1/E = 2 V_0 exp(-Omega / a), with ln E capped as in [`force`].
pub fn inverse_scale(level: f64, direct: f64, reference_velocity: f64) -> f64 {
    crate::elementary::exp(
        -(level / direct - crate::elementary::ln(2.0 * reference_velocity)).min(LOG_SCALE_CAP),
    )
}

/// sqrt(1/E^2 + v^2) (m/s) from `inverse_scale` (1/E) and `velocity` (v): the plain sum
/// where it is a normal f64 (the same bits as before), else scaled by the larger of the
/// two. With ln E > 354, 1/E^2 underflows, and at v = 0 the plain root was 0: the slope
/// at rest F_n a E was infinite (and dS/dv NaN) although it is finite up to ln E = 709.
pub fn root_sum_of_squares(inverse_scale: f64, velocity: f64) -> f64 {
    let sum = inverse_scale * inverse_scale + velocity * velocity;
    if sum.is_normal() {
        return sum.sqrt();
    }
    let larger = inverse_scale.abs().max(velocity.abs());
    if larger == 0.0 {
        return 0.0;
    }
    let (x, y) = (inverse_scale / larger, velocity / larger);
    larger * (x * x + y * y).sqrt()
}

/// F and its derivatives (module formula) at sliding velocity `velocity` (m/s), normal
/// force `normal_force` (N), level `level` (Omega, 1), direct effect `direct` (a > 0)
/// and reference velocity `reference_velocity` (V_0 > 0, m/s).
pub fn force(
    velocity: f64,
    normal_force: f64,
    level: f64,
    direct: f64,
    reference_velocity: f64,
) -> RegularisedForce {
    let log_scale =
        (level / direct - crate::elementary::ln(2.0 * reference_velocity)).min(LOG_SCALE_CAP);
    let inverse_scale = inverse_scale(level, direct, reference_velocity);
    let sign = crate::elementary::signum_or_zero(velocity);
    let d_velocity = normal_force * direct / root_sum_of_squares(inverse_scale, velocity);
    if velocity == 0.0 {
        return RegularisedForce {
            force: 0.0,
            d_velocity,
            d_level: 0.0,
            d_direct: 0.0,
        };
    }
    let log_y = crate::elementary::ln(velocity.abs()) + log_scale;
    let (asinh, q) = if log_y > LOG_ASYMPTOTE {
        (log_y + std::f64::consts::LN_2, 1.0)
    } else {
        let y = crate::elementary::exp(log_y);
        (crate::elementary::asinh(y), y / (1.0 + y * y).sqrt())
    };
    RegularisedForce {
        force: sign * normal_force * direct * asinh,
        d_velocity,
        d_level: sign * normal_force * q,
        // d/da of a asinh(y(a)) with ln y = ... + Omega / a: asinh - q Omega / a.
        d_direct: sign * normal_force * (asinh - q * level / direct),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Far from v = 0 the force is the Dieterich-Ruina law (to 1e-12 relative at
    /// |v| / V_0 = 1e4 and a = 0.01: the neglected term is 1 / (4 y^2)); the
    /// derivatives match central differences of the force.
    #[test]
    fn the_regularised_force_is_dieterich_ruina_away_from_zero_with_exact_derivatives() {
        let (f_n, a, v0, level) = (100.0, 0.01, 1e-6, 0.6);
        for v in [1e-2f64, -3e-4] {
            let expected = v.signum() * f_n * (level + a * crate::elementary::ln(v.abs() / v0));
            let got = force(v, f_n, level, a, v0).force;
            assert!(
                (got - expected).abs() < 1e-12 * expected.abs(),
                "{got} {expected}"
            );
        }
        for v in [0.0, 1e-9, -2e-8, 1e-3] {
            let f = force(v, f_n, level, a, v0);
            // A step well inside the linear zone |v| < 1/E at v = 0, relative elsewhere.
            let inverse_scale = f_n * a / f.d_velocity;
            let h = 1e-4 * v.abs().max(inverse_scale);
            let fd = (force(v + h, f_n, level, a, v0).force
                - force(v - h, f_n, level, a, v0).force)
                / (2.0 * h);
            assert!(
                (f.d_velocity - fd).abs() < 1e-5 * fd.abs(),
                "v {v}: {} {fd}",
                f.d_velocity
            );
            if v != 0.0 {
                let e = 1e-7;
                let fd_level = (force(v, f_n, level + e, a, v0).force
                    - force(v, f_n, level - e, a, v0).force)
                    / (2.0 * e);
                assert!((f.d_level - fd_level).abs() < 1e-5 * fd_level.abs().max(1.0));
                let e = 1e-9;
                let fd_a = (force(v, f_n, level, a + e, v0).force
                    - force(v, f_n, level, a - e, v0).force)
                    / (2.0 * e);
                assert!(
                    (f.d_direct - fd_a).abs() < 1e-4 * fd_a.abs().max(1.0),
                    "{} {fd_a}",
                    f.d_direct
                );
            }
        }
        assert_eq!(force(0.0, f_n, level, a, v0).force, 0.0);
        assert_eq!(
            force(-1e-3, f_n, level, a, v0).force,
            -force(1e-3, f_n, level, a, v0).force
        );
    }
}
