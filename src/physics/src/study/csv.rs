//! study.csv: one line per run.

use super::configuration::Resolution;
use super::front::Row;
use crate::choice::Choice;
use crate::neural::inference::Inference;

/// The CSV header of [`csv_line`].
pub const CSV_HEADER: &str = "level,modes,beam_elements,element_size_m,dt_s,integrator,inference,law,dofs,wall_s,realtime_factor,err_breakaway_s,err_first_slip_duration_s,err_period_s,err_corridor_m,err_rms_m,pareto";

/// One CSV line of a row; missing values are empty fields. The `law` column is the
/// run's law as `--laws` spells it ([`super::Law`]'s Display); a path with a comma in it
/// would break the line, and `--laws` (comma-separated) cannot name one either.
pub fn csv_line(row: &Row, end_time: f64) -> String {
    let c = &row.measured.configuration;
    let level = c.resolution.kind();
    let (modes, elements, size) = match c.resolution {
        Resolution::Modal { modes } => (modes.to_string(), String::new(), String::new()),
        Resolution::Beam { elements } => (String::new(), elements.to_string(), String::new()),
        Resolution::PlaneStress { element_size } => {
            (String::new(), String::new(), element_size.to_string())
        }
        Resolution::PlaneStressModal {
            element_size,
            modes,
        } => (modes.to_string(), String::new(), element_size.to_string()),
        Resolution::Structure => (String::new(), String::new(), String::new()),
        Resolution::StructureModal { modes } => (modes.to_string(), String::new(), String::new()),
    };
    let opt = |v: Option<f64>| v.map(|v| format!("{v:.6e}")).unwrap_or_default();
    let e = &row.errors;
    format!(
        "{level},{modes},{elements},{size},{:e},{},{},{},{},{:.6e},{:.3},{},{},{},{},{:.6e},{}",
        c.dt,
        c.scheme_name(),
        c.inference.map_or("", Inference::name),
        row.law,
        row.measured.dofs,
        row.measured.seconds,
        end_time / row.measured.seconds,
        opt(e.breakaway),
        opt(e.first_slip_duration),
        opt(e.period),
        opt(e.corridor),
        e.rms,
        row.on_front as u8
    )
}
