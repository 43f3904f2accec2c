//! Getting and setting variables through the model's table: which variables may be
//! read or written in which mode, and the outputs made current before a read.

use super::base::{CallResult, Failed, Instance};
use super::machine::{Call, Mode};
use crate::model::Model;
use crate::variables::{lookup, AccessError, BaseType, Causality, Variable};

impl<M: Model> Instance<M> {
    fn access_failed(&mut self, call: &str, error: AccessError) -> Failed {
        self.fail(call, &error.to_string())
    }

    /// Prepares a get: when outputs are asked for, they are made current first (not in
    /// the Error mode, which only reports).
    fn before_get(&mut self, call: &str, vrs: &[u32], base: BaseType) -> CallResult<()> {
        self.check(Call::Get)?;
        let mut outputs = false;
        for &vr in vrs {
            match lookup(M::variables(), vr, base) {
                Ok(v) => outputs |= v.causality == Causality::Output,
                Err(AccessError::UnknownReference(_))
                    if base == BaseType::Real && self.dynamic_output(vr).is_some() =>
                {
                    outputs = true
                }
                Err(e) => return Err(self.access_failed(call, e)),
            }
        }
        if outputs && self.mode != Mode::Error {
            if let Err(reason) = self.model.refresh_outputs(self.start_time, self.stop_time) {
                return Err(self.fail(call, &reason));
            }
        }
        Ok(())
    }

    fn get_with<T>(
        &mut self,
        call: &str,
        vrs: &[u32],
        out: &mut [T],
        base: BaseType,
        read: fn(&Variable<M>, &M) -> T,
    ) -> CallResult<()> {
        if vrs.len() != out.len() {
            return Err(self.fail(call, "value buffer and value references differ in length"));
        }
        self.before_get(call, vrs, base)?;
        for (slot, &vr) in out.iter_mut().zip(vrs) {
            // Looked up successfully in before_get.
            if let Ok(v) = lookup(M::variables(), vr, base) {
                *slot = read(v, &self.model);
            }
        }
        Ok(())
    }

    /// The position of value reference `vr` among the model's dynamic outputs.
    fn dynamic_output(&self, vr: u32) -> Option<usize> {
        self.model
            .dynamic_outputs()
            .iter()
            .position(|o| o.value_reference == vr)
    }

    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> CallResult<()> {
        self.get_with(
            self.names().get_real,
            vrs,
            out,
            BaseType::Real,
            Variable::get_real,
        )?;
        // The table's rows are read; the rest were found dynamic in before_get.
        for (slot, &vr) in out.iter_mut().zip(vrs) {
            if let Some(k) = self.dynamic_output(vr) {
                *slot = self.model.dynamic_output_value(k);
            }
        }
        Ok(())
    }

    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> CallResult<()> {
        self.get_with(
            self.names().get_integer,
            vrs,
            out,
            BaseType::Integer,
            Variable::get_integer,
        )
    }

    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> CallResult<()> {
        self.get_with(
            self.names().get_boolean,
            vrs,
            out,
            BaseType::Boolean,
            Variable::get_boolean,
        )
    }

    pub fn get_string(&mut self, vrs: &[u32]) -> CallResult<Vec<String>> {
        let mut out = vec![String::new(); vrs.len()];
        self.get_with(
            self.names().get_string,
            vrs,
            &mut out,
            BaseType::String,
            Variable::get_string,
        )?;
        Ok(out)
    }

    /// Checks that variable `vr` may be set now: fixed parameters only before
    /// initialisation ends, inputs at any settable time, outputs never.
    fn settable(
        &mut self,
        call: &str,
        vr: u32,
        base: BaseType,
    ) -> CallResult<&'static Variable<M>> {
        let variable = match lookup(M::variables(), vr, base) {
            Ok(v) => v,
            Err(e) => {
                if let Some(k) = self.dynamic_output(vr) {
                    let reason = format!(
                        "{} is an output and cannot be set",
                        self.model.dynamic_outputs()[k].name
                    );
                    return Err(self.fail(call, &reason));
                }
                return Err(self.access_failed(call, e));
            }
        };
        let when_ok = match variable.causality {
            Causality::Parameter => {
                matches!(self.mode, Mode::Instantiated | Mode::InitializationMode)
            }
            Causality::Input => true,
            Causality::Output => false,
        };
        if !variable.access.is_settable() || variable.causality == Causality::Output {
            return Err(self.access_failed(
                call,
                AccessError::NotSettable {
                    name: variable.name,
                    causality: variable.causality,
                },
            ));
        }
        if !when_ok {
            let reason = format!(
                "{} is a fixed parameter; it can be set only before {} (mode is {:?})",
                variable.name,
                self.names().exit_initialization_mode,
                self.mode
            );
            return Err(self.fail(call, &reason));
        }
        Ok(variable)
    }

    fn set_with<T: Copy>(
        &mut self,
        call: &str,
        vrs: &[u32],
        values: &[T],
        base: BaseType,
        write: fn(&Variable<M>, &mut M, T) -> Result<(), AccessError>,
    ) -> CallResult<()> {
        self.check(Call::Set)?;
        if vrs.len() != values.len() {
            return Err(self.fail(call, "value buffer and value references differ in length"));
        }
        for (&vr, &value) in vrs.iter().zip(values) {
            let variable = self.settable(call, vr, base)?;
            if let Err(e) = write(variable, &mut self.model, value) {
                return Err(self.access_failed(call, e));
            }
        }
        Ok(())
    }

    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> CallResult<()> {
        self.set_with(
            self.names().set_real,
            vrs,
            values,
            BaseType::Real,
            Variable::set_real,
        )
    }

    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> CallResult<()> {
        self.set_with(
            self.names().set_integer,
            vrs,
            values,
            BaseType::Integer,
            Variable::set_integer,
        )
    }

    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> CallResult<()> {
        self.set_with(
            self.names().set_boolean,
            vrs,
            values,
            BaseType::Boolean,
            Variable::set_boolean,
        )
    }

    pub fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> CallResult<()> {
        self.check(Call::Set)?;
        let call = self.names().set_string;
        if vrs.len() != values.len() {
            return Err(self.fail(call, "value buffer and value references differ in length"));
        }
        for (&vr, value) in vrs.iter().zip(values) {
            let variable = self.settable(call, vr, BaseType::String)?;
            if let Err(e) = variable.set_string(&mut self.model, value) {
                return Err(self.access_failed(call, e));
            }
        }
        Ok(())
    }
}
