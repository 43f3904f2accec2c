//! The contact's state between steps: stick or slip, its transitions, and what the last
//! step left.

use serde::{Deserialize, Serialize};

/// Contact state of the tip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactState {
    Stick,
    Slip,
}

/// A change of contact state at time `time` (s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Transition {
    pub time: f64,
    pub to: ContactState,
}

/// The contact as the last step left it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Previous {
    pub state: ContactState,
    /// v_rel = v_b - v_tip at t_n (m/s), as the last step ended.
    pub relative_velocity: f64,
    /// Tip force of the last step (N); the slip iteration starts from it.
    pub force: f64,
}
