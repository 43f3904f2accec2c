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

/// A choice variable's set of values, read off a [`Choice`]: the type's name and
/// description ([`Choice::TYPE_NAME`], [`Choice::TYPE_DESCRIPTION`]), and one value per
/// item of [`Choice::ALL`], numbered 1, 2, ... ([`Choice::code`]), with its word and
/// description. A scene file, the command line and the FMU therefore use the same words.
///
/// In an FMU a choice is an FMI Integer with min 1 and max `len`, not an FMI
/// Enumeration: libcosim and Ecos ignore Enumeration variables, so a choice could not be
/// set there. The words reach the model description twice, both generated from here:
/// in the variable's description (for people) and in the `stickslip` tool annotation
/// (for programs; see `stickslip_fmi::model_description`). Here, beside [`Choice`], because
/// a law's parameter that is a choice (`friction::registry`) carries its list as data.
#[derive(Clone, Copy, Debug)]
pub struct ChoiceType {
    pub name: &'static str,
    pub description: &'static str,
    /// Number of values; their codes are 1..=len.
    pub len: usize,
    /// (word, description) of the value with a 1-based code, if there is one.
    item: fn(i32) -> Option<(&'static str, &'static str)>,
}

fn item_of<T: Choice>(code: i32) -> Option<(&'static str, &'static str)> {
    T::from_code(code).map(|c| (c.name(), c.description()))
}

impl ChoiceType {
    /// The values of the choice `T`.
    pub const fn of<T: Choice>() -> Self {
        Self {
            name: T::TYPE_NAME,
            description: T::TYPE_DESCRIPTION,
            len: T::ALL.len(),
            item: item_of::<T>,
        }
    }

    /// (code, word, description) of every value, in code order.
    pub fn items(&self) -> impl Iterator<Item = (i32, &'static str, &'static str)> + '_ {
        (1..=self.len as i32).filter_map(|v| (self.item)(v).map(|(n, d)| (v, n, d)))
    }

    /// Word of the value with code `code` (1-based), or an error naming the allowed codes.
    pub fn item(&self, code: i32) -> Result<&'static str, String> {
        (self.item)(code)
            .map(|(name, _)| name)
            .ok_or_else(|| self.not_an_item(code))
    }

    /// The codes and their words, "1 = exponential, 2 = coulomb, ...".
    pub fn codes(&self) -> String {
        let codes: Vec<String> = self
            .items()
            .map(|(code, name, _)| format!("{code} = {name}"))
            .collect();
        codes.join(", ")
    }

    /// Why `code` is not a value: the allowed codes.
    fn not_an_item(&self, code: i32) -> String {
        format!(
            "{code} is not a {} code; allowed: {}",
            self.name,
            self.codes()
        )
    }
}

/// The value of choice `T` with code `code` (1-based), or an error naming the allowed
/// codes.
pub fn choice_at<T: Choice>(code: i32) -> Result<T, String> {
    T::from_code(code).ok_or_else(|| ChoiceType::of::<T>().not_an_item(code))
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
