//! The exact step of a linear relaxation y' = f - c y with constant c >= 0 and f over a
//! step: y(dt) = y0 E + f dt P with s = c dt, E = exp(-s) and P(s) = (1 - E) / s. Both
//! analytical laws advance their state this way for a velocity held over the step,
//! which is stable (|E| <= 1) however stiff the relaxation.

use crate::elementary;

/// E = exp(-s), P = (1 - exp(-s)) / s and dP/ds at s = c dt >= 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Relaxation {
    pub(crate) decay: f64,
    pub(crate) average: f64,
    pub(crate) average_slope: f64,
}

impl Relaxation {
    /// The factors at `s` >= 0 (1). P and dP/ds come from their Taylor series below
    /// s = 0.5, where the closed forms lose digits to cancellation (dP/ds =
    /// (E (1 + s) - 1) / s^2 loses eps / s^2), and from the closed forms above.
    pub(crate) fn at(s: f64) -> Self {
        let decay = elementary::exp(-s);
        if s < 0.5 {
            // P = sum_k (-s)^k / (k + 1)!, dP/ds = sum_k k (-s)^(k-1) (-1) / (k + 1)!;
            // 14 terms leave a remainder below 0.5^14 / 15! ~ 5e-17.
            let (mut average, mut average_slope) = (0.0, 0.0);
            let mut power = 1.0; // (-s)^k
            let mut factorial = 1.0; // (k + 1)!
            for k in 0..14 {
                factorial *= (k + 1) as f64;
                average += power / factorial;
                if k + 1 < 14 {
                    // Term k + 1 of dP/ds: (k + 1) (-1)^(k+1) s^k / (k + 2)!.
                    average_slope -= (k + 1) as f64 * power / (factorial * (k + 2) as f64);
                }
                power *= -s;
            }
            Self {
                decay,
                average,
                average_slope,
            }
        } else {
            Self {
                decay,
                average: -elementary::exp_m1(-s) / s,
                average_slope: (decay * (1.0 + s) - 1.0) / (s * s),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Relaxation;
    use crate::elementary;

    /// The series and the closed forms meet at s = 0.5 and agree with a central
    /// difference of P elsewhere (h = 1e-5: truncation P''' h^2 / 6 < 1e-11, rounding
    /// eps / h ~ 2e-11).
    #[test]
    fn factors_match_their_closed_forms_and_derivative() {
        assert_eq!(Relaxation::at(0.0).average, 1.0);
        assert_eq!(Relaxation::at(0.0).average_slope, -0.5);
        let below = Relaxation::at(0.5 - 1e-15);
        let above = Relaxation::at(0.5);
        assert!((below.average - above.average).abs() < 1e-15);
        assert!((below.average_slope - above.average_slope).abs() < 1e-14);
        let h = 1e-5;
        for s in [1e-3, 0.1, 0.4, 0.7, 3.0, 40.0] {
            let r = Relaxation::at(s);
            assert!((r.average - (1.0 - elementary::exp(-s)) / s).abs() < 1e-15 * (1.0 + 1.0 / s));
            let difference =
                (Relaxation::at(s + h).average - Relaxation::at(s - h).average) / (2.0 * h);
            assert!((r.average_slope - difference).abs() < 1e-10, "s {s}");
        }
    }
}
