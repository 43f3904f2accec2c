//! Physics: statics and frequencies against beam theory, dynamics (orbits, energy, convergence), the extremes, scene validation and fidelity = auto.

mod auto;
mod dynamics;
mod extremes;
mod scene_validation;
mod statics;
