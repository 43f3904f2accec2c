//! The elementary (transcendental) functions of the physics and the network, from one
//! implementation that gives the same bits on every platform and CPU.
//!
//! Rust's `f64::exp`, `tanh`, `sin`, ... call the platform's C library: glibc chooses
//! its kernel per CPU when it loads (an FMA build on CPUs that have FMA), and the Windows
//! and other C runtimes are different code again, so the same FMU gave different last
//! bits on two x86_64 CPUs (7 to 26 of 20 000 arguments differed by up to 2 ulp between
//! glibc's FMA and SSE2 kernels, /work/shared/notes/platforms.md), and a last-bit
//! difference grows after breakaway. These wrappers call the pure-Rust `libm` crate
//! (a port of musl's libm, pinned to 0.2.16): plain IEEE arithmetic with no run-time
//! dispatch, which gave identical bits on x86_64 with and without FMA, aarch64 and
//! Windows (issue 25; tests/physics/reproducible.rs checks the whole paper scene).
//!
//! The workspace's clippy.toml forbids the `f64`/`f32` methods that these replace, so a
//! direct call fails `cargo clippy -D warnings`. Not wrapped, because they are exactly
//! rounded IEEE operations on every target: `sqrt`, `mul_add`, `abs`, `floor`, `copysign`.
//! `powi(n)` is allowed too: LLVM expands a constant exponent into the square-and-multiply
//! sequence that compiler-builtins' `__powidf2` runs for a variable one (x, x^2, x^4, ...
//! multiplied from the lowest bit up, then 1 / r for n < 0), all correctly rounded
//! multiplications, so its bits do not depend on the target either.

/// e^x.
#[inline]
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// e^x - 1, accurate near 0.
#[inline]
pub fn exp_m1(x: f64) -> f64 {
    libm::expm1(x)
}

/// Natural logarithm.
#[inline]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// Base-2 logarithm.
#[inline]
pub fn log2(x: f64) -> f64 {
    libm::log2(x)
}

/// Base-10 logarithm.
#[inline]
pub fn log10(x: f64) -> f64 {
    libm::log10(x)
}

/// ln(1 + x), accurate near 0.
#[inline]
pub fn ln_1p(x: f64) -> f64 {
    libm::log1p(x)
}

/// x^y for a real exponent.
#[inline]
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// Sine (x in rad).
#[inline]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// Cosine (x in rad).
#[inline]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// Hyperbolic tangent.
#[inline]
pub fn tanh(x: f64) -> f64 {
    libm::tanh(x)
}

/// Hyperbolic cosine.
#[inline]
pub fn cosh(x: f64) -> f64 {
    libm::cosh(x)
}

/// Inverse hyperbolic sine, ln(x + sqrt(x^2 + 1)).
#[inline]
pub fn asinh(x: f64) -> f64 {
    libm::asinh(x)
}

/// sqrt(x^2 + y^2) without overflow or underflow in the squares.
#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

/// The angle of (x, y) in (-pi, pi] (rad).
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// e^x in single precision.
#[inline]
pub fn exp_f32(x: f32) -> f32 {
    libm::expf(x)
}

/// Hyperbolic tangent in single precision.
#[inline]
pub fn tanh_f32(x: f32) -> f32 {
    libm::tanhf(x)
}

/// sign(v) with sign(0) = 0, so that a law at exactly zero speed exerts no force.
pub fn signum_or_zero(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Identities that hold to a few ulp whatever the implementation (so they test the
    /// wiring, not libm): e^ln x = x, sin^2 + cos^2 = 1, tanh = (e^2x - 1)/(e^2x + 1).
    #[test]
    fn the_wrappers_are_the_functions_they_name() {
        for i in 1..200 {
            let x = i as f64 * 0.037;
            assert!((exp(ln(x)) - x).abs() <= 4.0 * f64::EPSILON * x, "{x}");
            assert!((sin(x).powi(2) + cos(x).powi(2) - 1.0).abs() <= 4.0 * f64::EPSILON);
            let e = exp(2.0 * x);
            assert!((tanh(x) - (e - 1.0) / (e + 1.0)).abs() <= 4.0 * f64::EPSILON);
            assert!((exp_m1(x) - (e.sqrt() - 1.0)).abs() <= 8.0 * f64::EPSILON * e);
            assert!((ln_1p(x) - ln(1.0 + x)).abs() <= 4.0 * f64::EPSILON);
            assert!(
                (log2(x) * std::f64::consts::LN_2 - ln(x)).abs()
                    <= 4.0 * f64::EPSILON * (1.0 + ln(x).abs())
            );
            assert!((powf(x, 1.5) - x * x.sqrt()).abs() <= 4.0 * f64::EPSILON * x * x);
            assert!((cosh(x) - (e.sqrt() + 1.0 / e.sqrt()) / 2.0).abs() <= 8.0 * f64::EPSILON * e);
            // musl's hypot is within 1 ulp, not correctly rounded (8.694999999999999 for
            // 5 x 1.739), so the bound is on the result's scale.
            assert!((hypot(3.0 * x, 4.0 * x) - 5.0 * x).abs() <= 4.0 * f64::EPSILON * 5.0 * x);
            assert!((atan2(x, x) - std::f64::consts::FRAC_PI_4).abs() <= f64::EPSILON);
            let xf = x as f32;
            let (e, t) = (exp(f64::from(xf)), tanh(f64::from(xf)));
            assert!((f64::from(exp_f32(xf)) - e).abs() <= 4.0 * f64::from(f32::EPSILON) * e);
            assert!((f64::from(tanh_f32(xf)) - t).abs() <= 4.0 * f64::from(f32::EPSILON));
        }
    }
}
