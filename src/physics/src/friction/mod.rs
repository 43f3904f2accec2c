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
//! - [`parameters`]: how a law's parameter out of range is told;
//! - [`FrictionLawKind`]: the one list of the laws, whose words the scene file, the
//!   command line and both FMUs use.

pub mod coulomb;
pub mod exponential;
pub mod learned_state;
pub mod lugre;
pub mod neural;
pub mod parameters;
pub mod rate_and_state;
pub mod state;

use state::StatefulLaw;

crate::choice! {
    /// The friction laws, each by the word the scene file (`friction.law`), the command
    /// line and the FMUs name it with. StickSlipBeam's parameter `friction.law` (FMI type
    /// `FrictionModel`) offers all of them in this order; NeuralFriction's `law` (type
    /// `FrictionLaw`) the ones it evaluates on their own, in an order of its own
    /// (`stickslip_fmi::friction::NeuralFrictionLaw`), which saved states hold.
    #[choice(name = "FrictionModel", description = "Where the kinetic friction force comes from")]
    pub enum FrictionLawKind {
        /// mu(v) = mu_k + (mu_s - mu_k) exp(-alpha |v|) (paper, Eq. 6), [`exponential::ExponentialLaw`].
        Exponential = "exponential": "mu(v) = mu_k + (mu_s - mu_k) exp(-alpha |v|) (paper, Eq. 6)",
        /// mu(v) = mu_k (plain Coulomb), [`coulomb::CoulombLaw`].
        Coulomb = "coulomb": "mu = mu_k",
        /// A trained network (see the `neural` module); weights from `friction.weights`
        /// (NeuralFriction: `weights`). A file of format `stickslip-state-friction` is
        /// the learned law with state ([`learned_state`]).
        Neural = "neural": "the network in friction.weights",
        /// The kinetic force and the static limit come from outside, as the
        /// StickSlipBeam FMU's inputs `external.*` (to couple it with NeuralFriction or
        /// any other friction FMU): a magnitude `external.kinetic_force` or a signed
        /// tangent, as `external.coupling` says (`simulation::ExternalKinetic`), and
        /// `external.static_limit`. Only a run that has those inputs can honour it: a
        /// stand-alone run refuses it (`run::run_scene`).
        External = "external": "inputs external.*: the kinetic force as external.coupling says, and external.static_limit",
        /// LuGre (Canudas de Wit et al. 1995), a law with the bristle deflection as state
        /// ([`lugre`]), parameters in `friction.lugre`; g(v) is the exponential law.
        Lugre = "lugre": "LuGre: bristle state z, dz/dt = v - sigma0 |v| z / g(v), F = sigma0 z + sigma1 dz/dt + sigma2 v, g the exponential law (friction.lugre)",
        /// Rate-and-state friction (Dieterich-Ruina), regularised at v = 0, with the state
        /// theta ([`rate_and_state`]), parameters in `friction.rate_and_state`.
        RateAndState = "rate-and-state": "rate-and-state: mu = a asinh(v / (2 V_0) exp((mu_0 + b ln(V_0 theta / D_c)) / a)), theta by the aging or slip law (friction.rate_and_state)",
    }
}

impl FrictionLawKind {
    /// Whether the law has internal state ([`state`]): no set-valued stick, its state
    /// stepped with the structure (see `contact`).
    pub fn has_memory(self) -> bool {
        matches!(self, FrictionLawKind::Lugre | FrictionLawKind::RateAndState)
    }
}

/// A kinetic friction law F(v, F_n).
///
/// `&mut self` lets a law keep scratch buffers (the neural law evaluates without
/// allocating); a law carries no history, so the same inputs give the same force.
pub trait FrictionLaw: Send {
    /// Short name for summaries ("exponential", "coulomb", "neural").
    fn name(&self) -> &str;

    /// Signed kinetic friction force (N) in the direction of `sliding_velocity` (m/s),
    /// under `normal_force` (N).
    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64;

    /// The force of [`FrictionLaw::sliding_force`] (N, the same number) and its exact
    /// slope dF/dv (N s/m) at `sliding_velocity`, computed in the same pass: the slip
    /// solve's Newton iteration (`contact`) needs both at every iterate.
    ///
    /// A law that jumps at v = 0 (sign(v) times a magnitude) gives there its force 0 and
    /// the slope of its magnitude; the contact handles the jump itself.
    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64);

    /// The force difference (N) below which this law's values are rounding noise: a law
    /// evaluated in f32 moves in steps of ~1e-6 N as its inputs round. The slip solve
    /// resolves the force no finer (0, the default, for laws evaluated in f64).
    fn resolution(&self) -> f64 {
        0.0
    }

    /// This law as a law with internal state ([`state`]), if it is one; the time loop
    /// then steps its state instead of calling the methods above. `None` (the default)
    /// for a memoryless law.
    fn as_stateful(&self) -> Option<&dyn StatefulLaw> {
        None
    }

    /// [`FrictionLaw::as_stateful`], mutable.
    fn as_stateful_mut(&mut self) -> Option<&mut dyn StatefulLaw> {
        None
    }
}
