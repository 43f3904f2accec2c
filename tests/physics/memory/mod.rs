//! Friction laws with state (`stickslip::memory`): the laws' own equations against
//! their closed forms (`laws`), the laws in the time loop (`contact`), and their state
//! in the samples (`state_output`).

mod contact;
mod laws;
mod state_output;
