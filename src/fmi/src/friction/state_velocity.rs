//! The velocity NeuralFriction commits its law's state with over a communication step
//! (issue 36, docs/cosimulation.md "The velocity a law's state is committed with").
//!
//! The law steps its state exactly for a velocity held over the step. Held at the
//! step's end velocity `sliding_velocity` (v_rel(t_k+1) in Gauss-Seidel), the state
//! moves by v(t_k+1) h where the beam slid another distance; held at the step's mean
//! velocity, the distance slid over the step divided by h (StickSlipBeam's output
//! `mean_relative_velocity`, NeuralFriction's input `mean_sliding_velocity`), a state
//! that integrates the slip (LuGre's bristles, dz/dt = v - |v| z sigma_0 / g(v)) moves
//! by the distance slid. Measured at the SSP systems' h = 1e-3 s, Gauss-Seidel, against
//! each law embedded (largest tip difference to 0.7 s, period error to 1.2 s), end ->
//! mean: with the `table` coupling (the SSP systems') rate-and-state with the aging law
//! 0.098 -> 0.020 mm, -0.84 -> 0.00 %, the learned law with memory 0.098 -> 0.021 mm,
//! -1.01 -> 0.00 %; with the `step` coupling LuGre 0.244 -> 0.0069 mm, the slip law
//! 0.092 -> 0.066 mm, but the aging law 0.138 -> 0.197 mm and the learned law 0.168 ->
//! 0.230 mm. Hence `auto`: the mean for every law with state (the table coupling's
//! need; `end` remains for a `step` coupling of the aging or the learned law).

stickslip::choice! {
    /// Which velocity commits NeuralFriction's law state over a step (`state_velocity`).
    #[choice(name = "StateVelocity", description = "The velocity a law with state is committed with over a communication step")]
    #[derive(Default)]
    pub enum StateVelocity {
        /// `Mean` for every law with state (the `table` coupling's need).
        #[default]
        Auto = "auto": "mean for every law with state (by the table coupling's error at h = 1e-3 s)",
        /// `sliding_velocity`, held over the step.
        End = "end": "sliding_velocity as set before the step (Gauss-Seidel: the beam's v_rel at the step's end)",
        /// `mean_sliding_velocity` once a master has set it, else `sliding_velocity`.
        Mean = "mean": "mean_sliding_velocity, the beam's distance slid over the step / h, once a master has set it (linked); else sliding_velocity",
    }
}
