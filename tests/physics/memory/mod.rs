//! Friction laws with state (`stickslip::memory`): the laws' own equations against
//! their closed forms (`laws`), and the laws in the time loop (`contact`).

mod contact;
mod laws;
