//! Numbers in messages, printed short. Rust's `{}` prints an f64 in full positional
//! notation (5e-324 takes 326 characters) and `{:?}` / `{:e}` print all 17 significant
//! digits a value may need to round-trip; an error message needs the value found again,
//! not its last bit. [`Short`] prints the shortest round-trip form in exponent notation
//! (as the scene's messages always did: "-1e0", "5e-324", "1e-6") when it has at most
//! seven significant digits, and else the value rounded to seven (1/3 is "3.333333e-1"):
//! at most 14 characters for any f64.

use std::fmt;

/// An f64 for a message (module notes). Non-finite values print as Rust prints them
/// ("NaN", "inf", "-inf").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Short(pub f64);

/// Significant digits kept where the shortest round-trip form has more.
const DIGITS: usize = 7;

impl fmt::Display for Short {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if !x.is_finite() {
            return write!(f, "{x}");
        }
        let shortest = format!("{x:e}");
        let (mantissa, exponent) = shortest.split_once('e').unwrap_or((&shortest, "0"));
        if mantissa.chars().filter(char::is_ascii_digit).count() <= DIGITS {
            return f.write_str(&shortest);
        }
        let rounded = format!("{x:.prec$e}", prec = DIGITS - 1);
        let (mantissa, exponent) = rounded.split_once('e').unwrap_or((&rounded, exponent));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        write!(f, "{mantissa}e{exponent}")
    }
}

#[cfg(test)]
mod tests {
    use super::Short;

    #[test]
    fn values_print_short_and_round_trip_to_seven_digits() {
        for (x, shown) in [
            (5e-324, "5e-324"),
            (-5e-324, "-5e-324"),
            (-1.0, "-1e0"),
            (0.0, "0e0"),
            (1e-6, "1e-6"),
            (0.02, "2e-2"),
            (1.0 / 3.0, "3.333333e-1"),
            (0.1 + 0.2, "3e-1"),
            (2.0 / 3.0, "6.666667e-1"),
            (9.9999999e-3, "1e-2"),
            (f64::MAX, "1.797693e308"),
            (-f64::MIN_POSITIVE, "-2.225074e-308"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(Short(x).to_string(), shown, "{x:e}");
        }
        // Every f64 fits in 14 characters and reads back to within half a unit of the
        // seventh digit (5e-7 relative).
        let mut bits: u64 = 0x9E37_79B9_7F4A_7C15;
        for _ in 0..10_000 {
            bits = bits.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            let x = f64::from_bits(bits);
            if !x.is_finite() {
                continue;
            }
            let shown = Short(x).to_string();
            assert!(shown.len() <= 14, "{shown}");
            let back: f64 = shown.parse().unwrap();
            assert!((back - x).abs() <= 5e-7 * x.abs(), "{x:e} shown {shown}");
        }
    }
}
