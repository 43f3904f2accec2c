//! NeuralFriction's state outputs: one Real output per state variable of the laws with
//! state (`stickslip::memory::STATE_VARIABLES`: LuGre's bristle deflection z, rate-and-
//! state's theta, the learned law's psi), named, with unit and description, from that
//! list. Each holds the committed state of the law in use, and 0 when that law has not
//! that variable (a memoryless law has none).

use stickslip::memory::{StateVariable, STATE_VARIABLES};

/// Their value references, in the order of `STATE_VARIABLES`.
pub(super) const STATE_OUTPUT: [u32; STATE_VARIABLES.len()] = [30, 31, 32];

/// The unit as the variable tables write it: none for the dimensionless "1".
pub(super) const fn unit(variable: &StateVariable) -> Option<&'static str> {
    match variable.unit.as_bytes() {
        b"1" => None,
        _ => Some(variable.unit),
    }
}

/// What every description ends with.
const ABSENT: &str = "; 0 when the law in use has no such state";

/// `text` followed by [`ABSENT`], as bytes of length `N`.
const fn with_absent<const N: usize>(text: &str) -> [u8; N] {
    let mut out = [0u8; N];
    let (a, b) = (text.as_bytes(), ABSENT.as_bytes());
    let mut k = 0;
    while k < N {
        out[k] = if k < a.len() { a[k] } else { b[k - a.len()] };
        k += 1;
    }
    out
}

/// The description of state output `k`: the state variable's, with [`ABSENT`].
macro_rules! state_description {
    ($k:expr) => {{
        const TEXT: &str = ::stickslip::memory::STATE_VARIABLES[$k].description;
        const BYTES: [u8; TEXT.len() + ABSENT.len()] = with_absent(TEXT);
        const JOINED: &str = match ::core::str::from_utf8(&BYTES) {
            Ok(s) => s,
            Err(_) => panic!("a state description is not UTF-8"),
        };
        JOINED
    }};
}

/// The descriptions, in the order of `STATE_VARIABLES`.
pub(super) const DESCRIPTION: [&str; STATE_VARIABLES.len()] = [
    state_description!(0),
    state_description!(1),
    state_description!(2),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn descriptions_are_the_state_variables_with_the_absent_note() {
        for (variable, description) in STATE_VARIABLES.iter().zip(DESCRIPTION) {
            assert_eq!(description, format!("{}{ABSENT}", variable.description));
        }
    }
}
