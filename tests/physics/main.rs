//! Physics: statics and frequencies against beam theory, dynamics (orbits, energy,
//! convergence), the modal model of the plane-stress mesh, the extremes, scene
//! validation, the choice enums, fidelity = auto, the error messages, the friction
//! reversals of issue 37, and the layering of the crates.

mod authors_rules;
mod authors_scene;
mod auto;
mod auto_horizon;
mod calculix_beam;
mod calculix_block;
mod choices;
mod contact;
mod coupling;
mod dynamics;
mod errors;
mod extremes;
mod fe_tools;
mod gmsh_beam;
mod layering;
mod mesh_modes;
mod modal_slip;
mod reproducible;
mod reversals;
mod scene_validation;
mod slip_solve;
mod state_laws;
mod statics;
mod stribeck;
mod structure_auto;
mod structure_modal;
mod structure_run;
mod structure_sensors;
mod structure_statics;
mod switch_stop;
