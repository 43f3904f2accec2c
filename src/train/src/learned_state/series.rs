//! Force records under velocity histories, as a tribometer writes them: per sample the
//! time t (s), the sliding velocity v (m/s), the normal force F_n (N) and the measured
//! friction force F (N), in records (series) that each start from steady sliding.
//!
//! A law with state is simulated along a record ([`simulate`]): the state starts at
//! the steady state of the first velocity (|v_0| > 0, checked), and over each sample
//! interval (t_{k-1}, t_k] the velocity is taken as v_k, the value at its end (a
//! tribometer's zero-order hold; the aging step is exact for it).

use std::fmt::Write as _;
use std::path::Path;

use crate::csv::{parse_csv, ColumnSelection};
use crate::error::TrainError;
use stickslip::friction::learned_state::LearnedStateLaw;

/// One record.
#[derive(Clone, Debug, PartialEq)]
pub struct ForceSeries {
    /// What the record is ("steps at 100 N", or "file.csv, record 2").
    pub name: String,
    pub time: Vec<f64>,
    pub velocity: Vec<f64>,
    pub normal_force: Vec<f64>,
    pub force: Vec<f64>,
}

impl ForceSeries {
    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Checks what simulating from steady sliding needs: [`ForceSeries::check_samples`]
    /// and a first velocity that is not 0 (its steady state starts the state).
    pub fn check(&self) -> Result<(), TrainError> {
        self.check_samples()?;
        if self.velocity[0] == 0.0 {
            return Err(TrainError::InvalidInput(format!(
                "{}: the first velocity is 0: a record must start from steady sliding (or train its initial state)",
                self.name
            )));
        }
        Ok(())
    }

    /// Checks what simulating from a given state needs: equal lengths, at least two
    /// samples, time strictly increasing, positive normal forces, finite numbers.
    pub fn check_samples(&self) -> Result<(), TrainError> {
        let bad = |m: String| Err(TrainError::InvalidInput(format!("{}: {m}", self.name)));
        let n = self.time.len();
        if [
            self.velocity.len(),
            self.normal_force.len(),
            self.force.len(),
        ] != [n, n, n]
        {
            return bad("columns of different lengths".into());
        }
        if n < 2 {
            return bad(format!("{n} sample(s); a record needs at least two"));
        }
        for k in 0..n {
            let values = [
                self.time[k],
                self.velocity[k],
                self.normal_force[k],
                self.force[k],
            ];
            if values.iter().any(|v| !v.is_finite()) {
                return bad(format!(
                    "sample {} holds a number that is not finite",
                    k + 1
                ));
            }
            if self.normal_force[k] <= 0.0 {
                return bad(format!(
                    "sample {}: normal force {} N, must be positive",
                    k + 1,
                    self.normal_force[k]
                ));
            }
            if k > 0 && self.time[k] <= self.time[k - 1] {
                return bad(format!(
                    "sample {}: time {} s does not increase",
                    k + 1,
                    self.time[k]
                ));
            }
        }
        Ok(())
    }
}

/// The law's force along `series` (one value per sample) and, per sample, the state,
/// from steady sliding at the first velocity.
pub fn simulate(law: &LearnedStateLaw, series: &ForceSeries) -> (Vec<f64>, Vec<f64>) {
    simulate_from(law, series, law.steady_state(series.velocity[0].abs()))
}

/// As [`simulate`], from the state `start` (psi).
pub fn simulate_from(
    law: &LearnedStateLaw,
    series: &ForceSeries,
    start: f64,
) -> (Vec<f64>, Vec<f64>) {
    let mut state = start;
    let mut forces = Vec::with_capacity(series.len());
    let mut states = Vec::with_capacity(series.len());
    for k in 0..series.len() {
        if k > 0 {
            let dt = series.time[k] - series.time[k - 1];
            state = law.step_state(state, series.velocity[k], dt).state;
        }
        forces.push(
            law.force(state, series.velocity[k], series.normal_force[k])
                .force,
        );
        states.push(state);
    }
    (forces, states)
}

/// Root-mean-square force error (N) of `law` over `records`, each from its state in
/// `starts` (NaN for none).
pub fn rms_error(law: &LearnedStateLaw, records: &[&ForceSeries], starts: &[f64]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (record, start) in records.iter().zip(starts) {
        let (forces, _) = simulate_from(law, record, *start);
        sum += forces
            .iter()
            .zip(&record.force)
            .map(|(f, m)| (f - m) * (f - m))
            .sum::<f64>();
        n += record.len();
    }
    (sum / n as f64).sqrt()
}

/// The CSV header the records are read and written with.
pub const COLUMNS: [(&str, &str); 4] = [("t", "s"), ("v", "m/s"), ("F_n", "N"), ("F", "N")];

/// Reads records from CSV text with columns `t[s]`, `v[m/s]`, `F_n[N]`, `F[N]` (others
/// are ignored; a unit, if written, must be these). A new record starts wherever t does
/// not increase, so records written one after another each restart their clock. Bad
/// rows are refused with their line (the CSV reader's rules, `crate::csv`); a bad record
/// with its number and sample.
pub fn parse_series_csv(text: &str, source_name: &str) -> Result<Vec<ForceSeries>, TrainError> {
    let selection = ColumnSelection {
        features: COLUMNS[..3].iter().map(|(n, _)| n.to_string()).collect(),
        target: COLUMNS[3].0.into(),
        sliding_velocity: Some(COLUMNS[1].0.into()),
        normal_force: Some(COLUMNS[2].0.into()),
    };
    let data = parse_csv(text, source_name, &selection)?;
    let quantities = data.features.iter().chain(std::iter::once(&data.target));
    for (quantity, (name, unit)) in quantities.zip(COLUMNS) {
        if !quantity.unit.is_empty() && quantity.unit != unit {
            return Err(TrainError::InvalidInput(format!(
                "{source_name}: column '{name}' is in '{}', expected '{unit}' (convert the record to SI units)",
                quantity.unit
            )));
        }
    }
    let mut records: Vec<ForceSeries> = Vec::new();
    for k in 0..data.len() {
        let t = data.inputs[(0, k)];
        let restart = records
            .last()
            .is_none_or(|r| r.time.last().is_some_and(|&last| t <= last));
        if restart {
            records.push(ForceSeries {
                name: format!("{source_name}, record {}", records.len() + 1),
                time: Vec::new(),
                velocity: Vec::new(),
                normal_force: Vec::new(),
                force: Vec::new(),
            });
        }
        let record = records.last_mut().expect("pushed above");
        record.time.push(t);
        record.velocity.push(data.inputs[(1, k)]);
        record.normal_force.push(data.inputs[(2, k)]);
        record.force.push(data.targets[k]);
    }
    if records.is_empty() {
        return Err(TrainError::InvalidInput(format!(
            "{source_name}: no samples"
        )));
    }
    for record in &records {
        record.check()?;
    }
    Ok(records)
}

/// Reads a CSV file of records ([`parse_series_csv`]).
pub fn read_series_csv(path: &Path) -> Result<Vec<ForceSeries>, TrainError> {
    let text = stickslip::files::RECORDS_FILE.read_text(path)?;
    parse_series_csv(&text, &path.display().to_string())
}

/// Writes records as the CSV [`parse_series_csv`] reads, whole or not at all.
pub fn write_series_csv(series: &[ForceSeries], path: &Path) -> Result<(), TrainError> {
    Ok(stickslip::files::write_atomically(
        path,
        series_csv(series),
    )?)
}

/// Records as the CSV [`parse_series_csv`] reads (shortest round-trip numbers).
pub fn series_csv(series: &[ForceSeries]) -> String {
    let header: Vec<String> = COLUMNS.iter().map(|(n, u)| format!("{n}[{u}]")).collect();
    let mut text = header.join(",");
    text.push('\n');
    for s in series {
        let _ = writeln!(text, "# {}", s.name);
        for k in 0..s.len() {
            let _ = writeln!(
                text,
                "{},{},{},{}",
                s.time[k], s.velocity[k], s.normal_force[k], s.force[k]
            );
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_split_where_time_restarts_and_bad_input_is_named() {
        let text = "t[s],v[m/s],F_n[N],F[N]\n0,0.01,100,60\n0.1,0.02,100,61\n0,0.01,90,50\n0.5,0.01,90,51\n";
        let records = parse_series_csv(text, "r.csv").unwrap();
        assert_eq!(records.len(), 2);
        assert_eq!(records[1].normal_force, vec![90.0, 90.0]);
        let e = parse_series_csv("t,v,F_n,F\n0,0.01,100,60\n0.1,x,100,61\n", "r.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "r.csv, line 3: column 'v': 'x' is not a number"
        );
        let e = parse_series_csv("t,v[mm/s],F_n,F\n0,1,100,60\n", "r.csv").unwrap_err();
        assert!(
            e.to_string()
                .contains("column 'v' is in 'mm/s', expected 'm/s'"),
            "{e}"
        );
        let e = parse_series_csv("t,v,F_n,F\n0,0,100,60\n1,0.01,100,60\n", "r.csv").unwrap_err();
        assert!(
            e.to_string().contains("record 1: the first velocity is 0"),
            "{e}"
        );
        let e = parse_series_csv("t,v,F_n,F\n0,0.1,100,60\n1,0.01,-5,60\n", "r.csv").unwrap_err();
        assert!(e.to_string().contains("sample 2: normal force -5 N"), "{e}");
        let e = parse_series_csv("t,v,F\n0,0.1,60\n", "r.csv").unwrap_err();
        assert!(e.to_string().contains("no column named 'F_n'"), "{e}");
    }
}
