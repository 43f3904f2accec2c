//! Named choices: every closed set of options in a scene (friction law, fidelity level,
//! scheme, ...) is one Rust enum that implements [`Choice`]. The scene file's words
//! (serde), the command line's values and the FMI enumeration items with their
//! descriptions are all read from it, so a choice is typed exactly once.

/// A closed set of named options.
pub trait Choice: Copy + PartialEq + Send + Sync + 'static {
    /// The type's name where one is shown (the FMI enumeration type).
    const TYPE_NAME: &'static str;
    /// One line on what the choice decides.
    const TYPE_DESCRIPTION: &'static str;
    /// Every value, in the order FMI numbers them (1, 2, ...).
    const ALL: &'static [Self];

    /// The word for this value in the scene file, on the command line and in the FMU.
    fn name(self) -> &'static str;

    /// One line on what this value means.
    fn description(self) -> &'static str;

    /// The value whose word is `name`.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|c| c.name() == name)
    }

    /// 1-based position in [`Choice::ALL`] (the FMI enumeration value).
    fn code(self) -> i32 {
        Self::ALL
            .iter()
            .position(|c| *c == self)
            .map_or(0, |k| k as i32 + 1)
    }

    /// The value at 1-based position `code`.
    fn from_code(code: i32) -> Option<Self> {
        usize::try_from(code)
            .ok()
            .and_then(|c| c.checked_sub(1))
            .and_then(|k| Self::ALL.get(k))
            .copied()
    }
}

/// Defines a choice enum with its serde words and descriptions in one place:
///
/// ```ignore
/// choice! {
///     /// Doc of the type.
///     #[choice(name = "Scheme", description = "Time integrator")]
///     pub enum Scheme {
///         /// Doc of the value.
///         GeneralizedAlpha = "generalized-alpha": "Chung-Hulbert generalised-alpha",
///         MoreauJean = "moreau-jean": "Moreau-Jean theta time-stepping",
///     }
/// }
/// ```
///
/// The enum derives Clone, Copy, Debug, PartialEq, Eq, Serialize and Deserialize; serde
/// reads and writes the words.
#[macro_export]
macro_rules! choice {
    (
        $(#[doc = $doc:literal])*
        #[choice(name = $type_name:literal, description = $type_description:literal)]
        $(#[$meta:meta])*
        $vis:vis enum $name:ident {
            $(
                $(#[$variant_meta:meta])*
                $variant:ident = $word:literal : $description:literal,
            )+
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
        $(#[$meta])*
        $vis enum $name {
            $(
                $(#[$variant_meta])*
                #[serde(rename = $word)]
                $variant,
            )+
        }

        impl $crate::choice::Choice for $name {
            const TYPE_NAME: &'static str = $type_name;
            const TYPE_DESCRIPTION: &'static str = $type_description;
            const ALL: &'static [Self] = &[$($name::$variant),+];

            fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $word,)+
                }
            }

            fn description(self) -> &'static str {
                match self {
                    $($name::$variant => $description,)+
                }
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::Choice;

    crate::choice! {
        /// A test choice.
        #[choice(name = "Colour", description = "A colour")]
        #[derive(Default)]
        pub enum Colour {
            /// The first.
            #[default]
            DeepRed = "deep-red": "the first colour",
            Blue = "blue": "the second colour",
        }
    }

    #[test]
    fn words_codes_and_serde_agree() {
        assert_eq!(Colour::ALL, &[Colour::DeepRed, Colour::Blue]);
        assert_eq!(Colour::DeepRed.name(), "deep-red");
        assert_eq!(Colour::Blue.description(), "the second colour");
        assert_eq!(Colour::Blue.code(), 2);
        assert_eq!(Colour::from_code(1), Some(Colour::DeepRed));
        assert_eq!(Colour::from_code(0), None);
        assert_eq!(Colour::from_code(3), None);
        assert_eq!(Colour::from_name("blue"), Some(Colour::Blue));
        assert_eq!(Colour::from_name("Blue"), None);
        assert_eq!(
            serde_json::to_string(&Colour::DeepRed).unwrap(),
            "\"deep-red\""
        );
        let parsed: Colour = serde_json::from_str("\"blue\"").unwrap();
        assert_eq!(parsed, Colour::Blue);
        assert_eq!(Colour::default(), Colour::DeepRed);
        assert_eq!(Colour::TYPE_NAME, "Colour");
    }
}
