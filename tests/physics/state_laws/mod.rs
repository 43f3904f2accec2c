//! Friction laws with state (`stickslip::friction::state`): the laws' own equations against
//! their closed forms (`laws`), the laws in the time loop (`contact`), their state in
//! the samples (`state_output`), and the laws at their edges (`edges`: v = 0, parameters
//! without a finite slope at rest, the smallest velocities), and `fidelity = auto` with
//! them (`auto`).

mod auto;
mod contact;
mod edges;
mod laws;
mod state_output;
