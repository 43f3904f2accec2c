//! The choice of state evolution for training the learned law: the aging law, the slip
//! law, or both (`evolution` trains the candidates and keeps the better).

use stickslip::friction::learned_state::StateEvolution;

stickslip::choice! {
    /// The state evolution the learned law is trained with.
    #[choice(name = "LearnedEvolution", description = "State evolution of the learned law with memory")]
    #[derive(Default)]
    pub enum LearnedEvolution {
        /// The aging law (Dieterich): the default, today's behaviour and speed.
        #[default]
        Aging = "aging": "the aging law d theta/dt = 1 - |v| theta / D_c: heals at rest",
        /// The slip law (Ruina).
        Slip = "slip": "the slip law d theta/dt = -(|v| theta / D_c) ln(|v| theta / D_c): frozen at rest",
        /// Each, keeping the better.
        Both = "both": "train with each law and keep the one with the lower held-out RMS force error (twice the time)",
    }
}

impl LearnedEvolution {
    /// The evolutions to train, in order.
    pub fn candidates(self) -> &'static [StateEvolution] {
        match self {
            LearnedEvolution::Aging => &[StateEvolution::Aging],
            LearnedEvolution::Slip => &[StateEvolution::Slip],
            LearnedEvolution::Both => &[StateEvolution::Aging, StateEvolution::Slip],
        }
    }
}
