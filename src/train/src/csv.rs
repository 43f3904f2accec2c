//! A small reader for measured friction data in CSV form.
//!
//! Format (deliberately simple, no dependency):
//! - comma-separated; fields are trimmed; a field may be wrapped in double quotes, which
//!   are removed (quoted commas are not supported);
//! - the first non-blank, non-comment line is the header: one name per column, with an
//!   optional unit in square brackets, `sliding_velocity[m/s]`; a column without brackets
//!   has an empty unit. Names must be unique;
//! - every later line is one sample with exactly as many fields as the header; blank lines
//!   and lines starting with `#` are skipped;
//! - only the selected feature and target columns must hold numbers; each must parse as a
//!   finite f64 (NaN and infinities are refused). Other columns may hold anything.
//!
//! Every error names the source and the 1-based line number.

use nalgebra::DMatrix;

use crate::data::{Dataset, Quantity};
use crate::TrainError;
use stickslip::neural::FeatureRole;

/// Which columns to read and what they mean to the beam.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnSelection {
    /// Feature column names, in the order the network will see them.
    pub features: Vec<String>,
    /// Target column name.
    pub target: String,
    /// Feature carrying the signed sliding velocity, if any.
    pub sliding_velocity: Option<String>,
    /// Feature carrying the normal force, if any.
    pub normal_force: Option<String>,
}

/// Splits `name[unit]` into name and unit.
pub fn parse_header_field(field: &str) -> (String, String) {
    let field = field.trim();
    if let (Some(open), true) = (field.find('['), field.ends_with(']')) {
        let name = field[..open].trim().to_string();
        let unit = field[open + 1..field.len() - 1].trim().to_string();
        (name, unit)
    } else {
        (field.to_string(), String::new())
    }
}

fn split_fields(line: &str) -> Vec<&str> {
    line.split(',')
        .map(|f| {
            let f = f.trim();
            f.strip_prefix('"')
                .and_then(|g| g.strip_suffix('"'))
                .unwrap_or(f)
        })
        .collect()
}

/// Reads a CSV file; see the module documentation for the format.
pub fn read_csv_file(
    path: &std::path::Path,
    selection: &ColumnSelection,
) -> Result<Dataset, TrainError> {
    let text = std::fs::read_to_string(path).map_err(|e| TrainError::io("cannot read", path, e))?;
    parse_csv(&text, &path.display().to_string(), selection)
}

/// Parses CSV text; `source_name` appears in error messages.
pub fn parse_csv(
    text: &str,
    source_name: &str,
    selection: &ColumnSelection,
) -> Result<Dataset, TrainError> {
    let error = |line: usize, message: String| TrainError::Csv {
        source_name: source_name.to_string(),
        line,
        message,
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));

    let (header_line, header) = lines
        .next()
        .ok_or_else(|| error(1, "the file is empty (no header line)".to_string()))?;
    let columns: Vec<(String, String)> = split_fields(header)
        .into_iter()
        .map(parse_header_field)
        .collect();
    for (i, (name, _)) in columns.iter().enumerate() {
        if name.is_empty() {
            return Err(error(header_line, format!("column {} has no name", i + 1)));
        }
        if columns[..i].iter().any(|(other, _)| other == name) {
            return Err(error(header_line, format!("column '{name}' appears twice")));
        }
    }
    let find = |name: &str| -> Result<usize, TrainError> {
        columns.iter().position(|(n, _)| n == name).ok_or_else(|| {
            let known: Vec<&str> = columns.iter().map(|(n, _)| n.as_str()).collect();
            error(
                header_line,
                format!(
                    "no column named '{name}' in the header (columns: {})",
                    known.join(", ")
                ),
            )
        })
    };
    if selection.features.is_empty() {
        return Err(TrainError::InvalidInput(
            "select at least one feature column".to_string(),
        ));
    }
    let mut selected = Vec::with_capacity(selection.features.len() + 1);
    for name in &selection.features {
        if selection.features.iter().filter(|n| *n == name).count() > 1 {
            return Err(TrainError::InvalidInput(format!(
                "feature '{name}' is selected twice"
            )));
        }
        if *name == selection.target {
            return Err(TrainError::InvalidInput(format!(
                "'{name}' cannot be both a feature and the target"
            )));
        }
        selected.push(find(name)?);
    }
    selected.push(find(&selection.target)?);

    let mut roles = vec![FeatureRole::Other; selection.features.len()];
    for (role, wanted) in [
        (FeatureRole::SlidingVelocity, &selection.sliding_velocity),
        (FeatureRole::NormalForce, &selection.normal_force),
    ] {
        if let Some(wanted) = wanted {
            let index = selection
                .features
                .iter()
                .position(|n| n == wanted)
                .ok_or_else(|| {
                    TrainError::InvalidInput(format!(
                        "'{wanted}' is given a role but is not among the features"
                    ))
                })?;
            if roles[index] != FeatureRole::Other {
                return Err(TrainError::InvalidInput(format!(
                    "'{wanted}' cannot be both the sliding velocity and the normal force"
                )));
            }
            roles[index] = role;
        }
    }

    let mut values: Vec<f64> = Vec::new();
    let mut targets: Vec<f64> = Vec::new();
    for (line_number, line) in lines {
        let fields = split_fields(line);
        if fields.len() != columns.len() {
            return Err(error(
                line_number,
                format!(
                    "{} field(s), but the header has {} columns",
                    fields.len(),
                    columns.len()
                ),
            ));
        }
        for (k, &column) in selected.iter().enumerate() {
            let text = fields[column];
            let value: f64 = text.parse().map_err(|_| {
                error(
                    line_number,
                    format!("column '{}': '{text}' is not a number", columns[column].0),
                )
            })?;
            if !value.is_finite() {
                return Err(error(
                    line_number,
                    format!(
                        "column '{}': '{text}' is not a finite number",
                        columns[column].0
                    ),
                ));
            }
            if k + 1 == selected.len() {
                targets.push(value);
            } else {
                values.push(value);
            }
        }
    }
    if targets.is_empty() {
        return Err(error(
            header_line,
            "the file has a header but no data rows".to_string(),
        ));
    }
    let n_features = selection.features.len();
    let quantity = |column: usize| Quantity::new(&columns[column].0, &columns[column].1);
    Ok(Dataset {
        features: selected[..n_features]
            .iter()
            .map(|&c| quantity(c))
            .collect(),
        roles,
        target: quantity(selected[n_features]),
        inputs: DMatrix::from_vec(n_features, targets.len(), values),
        targets,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn selection() -> ColumnSelection {
        ColumnSelection {
            features: vec!["v".into(), "Fn".into()],
            target: "F".into(),
            sliding_velocity: Some("v".into()),
            normal_force: Some("Fn".into()),
        }
    }

    fn message(text: &str) -> String {
        parse_csv(text, "t.csv", &selection())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn reads_selected_columns_with_units() {
        let text = "time[s], F[N], Fn[N], v[m/s], note\n# comment\n0, 1.5, 100, 0.1, ok\n\n1, -2, 90, -0.2, \"x\"\n";
        let data = parse_csv(text, "t.csv", &selection()).unwrap();
        assert_eq!(data.features[0], Quantity::new("v", "m/s"));
        assert_eq!(data.features[1], Quantity::new("Fn", "N"));
        assert_eq!(data.target, Quantity::new("F", "N"));
        assert_eq!(
            data.roles,
            vec![FeatureRole::SlidingVelocity, FeatureRole::NormalForce]
        );
        assert_eq!(data.targets, vec![1.5, -2.0]);
        assert_eq!(data.inputs.column(1).as_slice(), &[-0.2, 90.0]);
    }

    #[test]
    fn bad_files_name_the_line() {
        assert!(message("").contains("empty"));
        assert!(message("v,Fn,F\n").contains("no data rows"));
        assert!(message("v,F\n1,2\n").contains("no column named 'Fn'"));
        let m = message("v,Fn,F\n0.1,100,20\n0.2,abc,20\n");
        assert!(
            m.contains("line 3") && m.contains("'abc' is not a number"),
            "{m}"
        );
        let m = message("v,Fn,F\n0.1,100,NaN\n");
        assert!(m.contains("line 2") && m.contains("not a finite"), "{m}");
        let m = message("v,Fn,F\n0.1,100,inf\n");
        assert!(m.contains("not a finite"), "{m}");
        let m = message("v,Fn,F\n0.1,100,20\n0.1,100\n");
        assert!(m.contains("line 3") && m.contains("2 field(s)"), "{m}");
        assert!(message("v,v,F\n1,2,3\n").contains("twice"));
    }
}
