//! Physics: statics and frequencies against beam theory, dynamics (orbits, energy, convergence), the extremes, scene validation, the choice enums, fidelity = auto and the error messages.

mod auto;
mod choices;
mod dynamics;
mod errors;
mod extremes;
mod scene_validation;
mod statics;
