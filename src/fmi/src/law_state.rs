//! The friction law's state as FMU outputs: one Real output per entry of
//! `stickslip::friction::state::STATE_VARIABLES` (LuGre's bristle deflection, rate-and-state's
//! theta, the learned law's psi), named, united and described by that entry, so that
//! the physics crate is the one place that says what a state variable is. A run whose
//! law has not the variable outputs 0, and the description says so.
//!
//! The rows live in `'static` tables, so their descriptions are built at compile time
//! ([`Text`]): the entry's own description followed by [`ABSENT`].

/// What every state output's description adds to its variable's: the value of a law
/// without it.
pub const ABSENT: &str = "; the friction law's state, 0 for a law without this variable";

/// Room for a description built at compile time (bytes).
const CAPACITY: usize = 256;

/// A string joined at compile time, for the `&'static str` of a table row: declared as
/// a `static`, read with [`Text::as_str`].
pub struct Text {
    bytes: [u8; CAPACITY],
    len: usize,
}

impl Text {
    /// `first` followed by `second`; fails to compile when they exceed [`CAPACITY`].
    pub const fn join(first: &str, second: &str) -> Self {
        let (a, b) = (first.as_bytes(), second.as_bytes());
        assert!(a.len() + b.len() <= CAPACITY, "description too long");
        let mut bytes = [0; CAPACITY];
        let mut i = 0;
        while i < a.len() {
            bytes[i] = a[i];
            i += 1;
        }
        let mut j = 0;
        while j < b.len() {
            bytes[a.len() + j] = b[j];
            j += 1;
        }
        Self {
            bytes,
            len: a.len() + b.len(),
        }
    }

    /// The joined string (two `str`s joined at a character boundary stay UTF-8).
    pub const fn as_str(&'static self) -> &'static str {
        match std::str::from_utf8(self.bytes.split_at(self.len).0) {
            Ok(text) => text,
            Err(_) => panic!("joined text is not UTF-8"),
        }
    }
}

/// A state variable's unit as an FMU unit: "1" (dimensionless) is no unit, as for every
/// other dimensionless variable of the tables.
pub const fn fmi_unit(unit: &'static str) -> Option<&'static str> {
    match unit.as_bytes() {
        b"1" => None,
        _ => Some(unit),
    }
}

/// The Real output row of entry `$index` of `STATE_VARIABLES`, value reference `$vr`,
/// read off the model as `$value`, depending on `$depends_on`.
macro_rules! law_state_output {
    ($vr:expr, $index:literal, $depends_on:expr, |$m:ident: $model:ty| $value:expr) => {{
        static DESCRIPTION: $crate::law_state::Text = $crate::law_state::Text::join(
            ::stickslip::friction::state::STATE_VARIABLES[$index].description,
            $crate::law_state::ABSENT,
        );
        $crate::declare::real_output!(
            $vr,
            ::stickslip::friction::state::STATE_VARIABLES[$index].name,
            $crate::law_state::fmi_unit(::stickslip::friction::state::STATE_VARIABLES[$index].unit),
            DESCRIPTION.as_str(),
            $depends_on,
            |$m: $model| $value
        )
    }};
}

pub(crate) use law_state_output;

#[cfg(test)]
mod tests {
    use super::*;

    static JOINED: Text = Text::join("bristle z", ABSENT);

    #[test]
    fn text_joins_and_units_map() {
        assert_eq!(JOINED.as_str(), format!("bristle z{ABSENT}"));
        assert_eq!(fmi_unit("1"), None);
        assert_eq!(fmi_unit("m"), Some("m"));
    }
}
