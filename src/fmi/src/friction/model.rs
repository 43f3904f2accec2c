//! NeuralFriction as an FMI model (`crate::model::Model`): its description, variables,
//! and the calls the instance makes.

use super::variables::{ARRAYS, VARIABLES};
use super::*;
use crate::model::{Model, ModelInfo, PartialDerivatives, Restoring};
use crate::networks::WEIGHTS_RESOURCES;
use crate::variables::{ArrayVariable, Variable};
use std::path::Path;

impl Model for NeuralFriction {
    const INFO: ModelInfo = ModelInfo {
        model_identifier: "NeuralFriction",
        description: "Kinetic friction force from a trained neural network (or an analytical law, with or without state), for coupling with StickSlipBeam",
        start_time: 0.0,
        stop_time: 1.2,
        step_size: 1e-3,
        resources: WEIGHTS_RESOURCES,
        returns_early_at_events: false,
        provides_directional_derivatives: true,
    };

    fn variables() -> &'static [Variable<Self>] {
        &VARIABLES
    }

    fn arrays() -> &'static [ArrayVariable] {
        ARRAYS
    }

    fn with_defaults() -> Self {
        Self {
            settings: Settings::default(),
            networks: Networks::default(),
            outputs: Outputs::default(),
            scratch: Vec::new(),
            derivatives_at: None,
            built: None,
            law_state: Vec::new(),
            time: 0.0,
            step_size: 0.0,
            mean_linked: false,
        }
    }

    fn load_resources(&mut self, resources: &Path) -> Result<(), String> {
        self.networks
            .open_and_read_default(resources)
            .map_err(|e| e.to_string())
    }

    fn reset(&mut self) {
        self.settings = Settings::default();
        self.outputs = Outputs::default();
        self.law_state.clear();
        self.time = 0.0;
        self.step_size = 0.0;
        self.mean_linked = false;
    }

    fn refresh_outputs(&mut self, _start_time: f64, _stop_time: Option<f64>) -> Result<(), String> {
        self.outputs = self.evaluate().map_err(|e| e.to_string())?;
        Ok(())
    }

    fn initialize(&mut self, start_time: f64, _stop_time: Option<f64>) -> Result<(), String> {
        // A law with state starts at its initial state.
        self.law_state.clear();
        self.step_size = 0.0;
        self.initialise_outputs().map_err(|e| e.to_string())?;
        self.time = start_time;
        Ok(())
    }

    fn do_step(&mut self, to: f64, size: f64, _events: &mut Vec<String>) -> Result<(), String> {
        self.advance_state(to, size).map_err(|e| e.to_string())?;
        // An event iteration's step of size 0 keeps the master's h.
        if size > 0.0 {
            self.step_size = size;
        }
        self.outputs = self.evaluate().map_err(|e| e.to_string())?;
        Ok(())
    }

    fn partial_derivatives(&mut self) -> Result<PartialDerivatives, String> {
        self.derivatives().map_err(|e| e.to_string())
    }

    /// State versions 4 to 6: the settings, the law state and the last step's size
    /// (`state_laws`).
    fn save(&self) -> serde_json::Value {
        self.saved()
    }

    fn check_saved(&mut self, saved: &serde_json::Value, at: &Restoring) -> Result<(), String> {
        self.check_saved_state(saved, at)
    }

    /// Versions 1 to 3 hold the settings alone, versions 4 to 6 the law state besides
    /// (and the step size, required from version 6 on).
    fn restore(&mut self, saved: serde_json::Value, at: &Restoring) -> Result<(), String> {
        self.restore_saved(saved, at)
    }
}
