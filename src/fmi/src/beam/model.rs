//! StickSlipBeam as a [`Model`]: what the FMI layer calls, delegating to `build` and
//! `saved`.

use super::variables::VARIABLES;
use super::{Settings, StickSlipBeam};
use crate::model::{Model, ModelInfo, Restoring};
use crate::networks::{Networks, WEIGHTS_RESOURCES};
use crate::variables::{DynamicOutput, Variable};
use std::path::Path;

impl Model for StickSlipBeam {
    const INFO: ModelInfo = ModelInfo {
        model_identifier: "StickSlipBeam",
        description: "Cantilever beam whose tip rides on a conveyor belt: stick-slip with an analytical, neural or external friction law (Vater, Stender and Hoffmann)",
        start_time: 0.0,
        stop_time: 1.2,
        step_size: 1e-3,
        resources: WEIGHTS_RESOURCES,
        returns_early_at_events: true,
        provides_directional_derivatives: false,
    };

    fn variables() -> &'static [Variable<Self>] {
        &VARIABLES
    }

    fn with_defaults() -> Self {
        Self {
            settings: Settings::default(),
            start: Settings::default(),
            networks: Networks::default(),
            auto_log: Vec::new(),
            running: None,
            initialized: false,
            sensors: Vec::new(),
        }
    }

    fn dynamic_outputs(&self) -> &[DynamicOutput] {
        &self.sensors
    }

    fn dynamic_output_value(&self, index: usize) -> f64 {
        self.sensor_value(index)
    }

    fn load_resources(&mut self, resources: &Path) -> Result<(), String> {
        self.networks.open(resources).map_err(|e| e.to_string())
    }

    fn reset(&mut self) {
        self.settings = self.start.clone();
        self.running = None;
        self.initialized = false;
    }

    fn refresh_outputs(&mut self, start_time: f64, stop_time: Option<f64>) -> Result<(), String> {
        if !self.initialized {
            // Outputs asked for during initialisation: the state at the start time of
            // the current parameters and inputs.
            self.ensure_running(start_time, stop_time)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    fn initialize(&mut self, start_time: f64, stop_time: Option<f64>) -> Result<(), String> {
        self.ensure_running(start_time, stop_time)
            .map_err(|e| e.to_string())?;
        if let Some(running) = &mut self.running {
            running.start_time = start_time;
        }
        self.initialized = true;
        Ok(())
    }

    // The beam steps on its own time grid to `to`; the step size divides the distance
    // slid over it (`mean_relative_velocity`).
    fn do_step(&mut self, to: f64, size: f64, events: &mut Vec<String>) -> Result<(), String> {
        self.advance(to, size, false, events).map(|_| ())
    }

    fn do_step_until_event(
        &mut self,
        to: f64,
        size: f64,
        events: &mut Vec<String>,
    ) -> Result<Option<f64>, String> {
        self.advance(to, size, true, events)
    }

    fn take_notes(&mut self) -> Vec<String> {
        std::mem::take(&mut self.auto_log)
    }

    fn save(&self) -> serde_json::Value {
        self.saved()
    }

    fn check_saved(&mut self, saved: &serde_json::Value, at: &Restoring) -> Result<(), String> {
        self.check_saved_state(saved, at)
    }

    fn restore(&mut self, saved: serde_json::Value, at: &Restoring) -> Result<(), String> {
        self.restore_saved(saved, at)
    }
}
