//! Training the learned friction law with memory (`stickslip::friction::learned_state`) on force
//! records under velocity histories:
//! - `series`: the records (t, v, F_n, F), their CSV form, simulating a law along them;
//! - `protocol`: synthetic tribometer records from a rate-and-state law, with noise;
//! - `fit`: the fit by simulating the records with forward-sensitivity gradients
//!   (`loss`) and L-BFGS;
//! - `learned_evolution`: the choice of state evolution (aging, slip, or both);
//! - `evolution`: training with each chosen evolution and keeping the better.

pub mod evolution;
pub mod fit;
pub mod learned_evolution;
pub mod loss;
pub mod protocol;
pub mod series;

pub use evolution::train_state_law;
pub use fit::{StateTrainConfig, StateTrainReport};
pub use learned_evolution::LearnedEvolution;
pub use protocol::TribometerSpec;
pub use series::{read_series_csv, series_csv, simulate, write_series_csv, ForceSeries};
