//! The one list of the friction laws, [`FrictionLawKind`]: the words the scene file
//! (`friction.law`), the command line and both FMUs name them with, in the order of
//! StickSlipBeam's FMI codes. A law's entry in the registry is
//! [`FrictionLawKind::entry`] (`super`).

crate::choice! {
    /// The friction laws, each by the word the scene file (`friction.law`), the command
    /// line and the FMUs name it with. StickSlipBeam's parameter `friction.law` (FMI type
    /// `FrictionModel`) offers all of them in this order; NeuralFriction's `law` (type
    /// `FrictionLaw`) the ones it evaluates on their own, in an order of its own
    /// (`stickslip_fmi::friction::NeuralFrictionLaw`), which saved states hold.
    #[choice(name = "FrictionModel", description = "Where the kinetic friction force comes from")]
    pub enum FrictionLawKind {
        /// mu(v) = mu_k + (mu_s - mu_k) exp(-alpha |v|) (paper, Eq. 6), [`super::exponential::ExponentialLaw`].
        Exponential = "exponential": "mu(v) = mu_k + (mu_s - mu_k) exp(-alpha |v|) (paper, Eq. 6)",
        /// mu(v) = mu_k (plain Coulomb), [`super::coulomb::CoulombLaw`].
        Coulomb = "coulomb": "mu = mu_k",
        /// A trained network (see the `neural` module); weights from `friction.weights`
        /// (NeuralFriction: `weights`). A file of format `stickslip-state-friction` is
        /// the learned law with state ([`super::learned_state`]).
        Neural = "neural": "the network in friction.weights",
        /// The kinetic force and the static limit come from outside, as the
        /// StickSlipBeam FMU's inputs `external.*` (to couple it with NeuralFriction or
        /// any other friction FMU): a magnitude `external.kinetic_force` or a signed
        /// tangent, as `external.coupling` says (`simulation::ExternalKinetic`), and
        /// `external.static_limit`. Only a run that has those inputs can honour it: a
        /// stand-alone run refuses it (`run::run_scene`).
        External = "external": "inputs external.*: the kinetic force as external.coupling says, and external.static_limit",
        /// LuGre (Canudas de Wit et al. 1995), a law with the bristle deflection as state
        /// ([`super::lugre`]), parameters in `friction.lugre`; g(v) is the exponential law.
        Lugre = "lugre": "LuGre: bristle state z, dz/dt = v - sigma0 |v| z / g(v), F = sigma0 z + sigma1 dz/dt + sigma2 v, g the exponential law (friction.lugre)",
        /// Rate-and-state friction (Dieterich-Ruina), regularised at v = 0, with the state
        /// theta ([`super::rate_and_state`]), parameters in `friction.rate_and_state`.
        RateAndState = "rate-and-state": "rate-and-state: mu = a asinh(v / (2 V_0) exp((mu_0 + b ln(V_0 theta / D_c)) / a)), theta by the aging or slip law (friction.rate_and_state)",
        /// Stribeck friction with viscous friction ([`super::stribeck`]), parameters in
        /// `friction.stribeck`: the example of a law added through the registry.
        Stribeck = "stribeck": "mu(v) = mu_k + (mu_s - mu_k) exp(-(v / v_s)^2), plus sigma_v v (friction.stribeck)",
    }
}
