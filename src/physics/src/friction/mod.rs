//! Kinetic friction laws acting on the beam tip during slip, one file per law with its
//! parameters beside it.
//!
//! Every law maps a signed sliding velocity v (m/s) and a normal force F_n (N) to the
//! signed friction force (N) that acts in the direction of v. The contact passes the
//! belt-relative velocity v = v_b - v_tip, so the force drags the tip toward the belt.
//! The static limit mu_s F_n is not part of a law: it belongs to the contact. Which law
//! a run uses is `crate::law_source::LawSource`.
//!
//! - memoryless: [`exponential`] (the paper's Eq. 6), [`coulomb`], and the trained
//!   network ([`neural`], evaluated by `crate::neural`);
//! - with state: [`lugre`], [`rate_and_state`] and the learned law [`learned_state`],
//!   stepped by the time loop through [`state::StatefulLaw`] (their shared stepping);
//! - [`registry`]: one description per law (how it is built, its parameters), read by
//!   the scene file, the command line, both FMUs and the study;
//! - [`parameters`]: how a law's parameter out of range is told;
//! - [`FrictionLawKind`]: the one list of the laws, whose words the scene file, the
//!   command line and both FMUs use.

pub mod coulomb;
pub mod exponential;
pub mod kind;
pub mod law;
pub mod learned_state;
pub mod lugre;
pub mod neural;
pub mod parameters;
pub mod rate_and_state;
pub mod registry;
pub mod state;
pub mod stribeck;
pub mod tabulated;

pub use kind::FrictionLawKind;
pub use law::FrictionLaw;
use registry::{LawBuild, LawDescription};

impl FrictionLawKind {
    /// The law's entry in the registry ([`registry`]): how it is built, its parameters.
    /// A new law's registration: its `pub mod` above, its variant in [`kind`] and its
    /// line here.
    pub const fn entry(self) -> &'static LawDescription {
        match self {
            FrictionLawKind::Exponential => &exponential::LAW,
            FrictionLawKind::Coulomb => &coulomb::LAW,
            FrictionLawKind::Neural => &neural::LAW,
            FrictionLawKind::External => &EXTERNAL,
            FrictionLawKind::Lugre => &lugre::LAW,
            FrictionLawKind::RateAndState => &rate_and_state::LAW,
            FrictionLawKind::Stribeck => &stribeck::LAW,
        }
    }

    /// Whether the law has internal state ([`state`]): no set-valued stick, its state
    /// stepped with the structure (see `contact`).
    pub fn has_memory(self) -> bool {
        self.entry().has_state
    }
}

/// `external`: no law of its own, the force comes from the FMU's inputs.
static EXTERNAL: LawDescription =
    LawDescription::plain(FrictionLawKind::External, LawBuild::External);
