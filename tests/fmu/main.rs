//! The FMI 2.0 adapter: the instance state machine, the C ABI, the call matrix, threads and resources, fuzz regressions and the generated modelDescription.

mod allocations;
mod authors_options;
mod call_matrix;
mod coupling_lab;
mod dependencies;
mod directional;
mod directional_errors;
mod ffi;
mod ffi3;
mod friction_laws;
mod friction_laws_coupled;
mod friction_memory;
mod fuzz_regressions;
mod instance;
mod law_state_outputs;
mod long_run;
mod memory_laws;
mod model_description;
mod old_states;
mod state_corruption;
mod state_tampering;
mod stribeck;
mod threads_resources;
mod values3;
