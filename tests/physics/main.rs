//! Physics: statics and frequencies against beam theory, dynamics (orbits, energy, convergence), the extremes, scene validation, the choice enums and fidelity = auto.

mod auto;
mod choices;
mod dynamics;
mod extremes;
mod scene_validation;
mod statics;
