//! A reader for measured friction data in CSV form.
//!
//! The `csv` crate splits the text into records (RFC 4180 quoting, so a quoted field may
//! hold commas, doubled quotes and line breaks; lines end at `\n` or `\r\n`) and tells
//! where each record starts; this module adds the training-data rules on top:
//! - comma-separated; fields are trimmed; a field wrapped in double quotes after trimming
//!   (`1, "2.5"`) has them removed, as the hand-written reader this replaced did;
//! - the first non-blank, non-comment line is the header: one name per column, with an
//!   optional unit in square brackets, `sliding_velocity[m/s]`; a column without brackets
//!   has an empty unit. Names must be unique;
//! - every later line is one sample with exactly as many fields as the header; blank lines
//!   and lines starting with `#` (after leading blanks) are skipped;
//! - only the selected feature and target columns must hold numbers; each must parse as a
//!   finite f64 (NaN and infinities are refused). Other columns may hold anything.
//!
//! Every error names the source and the 1-based line number (of the record's first line).
//!
//! Speed, measured against the hand-written splitter it replaced, both in one process,
//! parses interleaved (100 000 rows, 7.7 MB, two features and a target selected out of
//! five columns; median of 31 parses each, `--release`, a shared 2-core machine): csv
//! crate / hand-written = 0.88 to 0.93 over three runs (about 50 ms against 55 ms), 0.90
//! at 10^6 rows. Fields are trimmed here rather than with `csv::Trim`, which rebuilds
//! every record and made the reader 1.6x slower than the hand-written one.

use nalgebra::DMatrix;

use crate::data::{Dataset, Quantity};
use crate::error::TrainError;
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

/// A field's text: trimmed (not with `csv::Trim`, see the module doc), and unwrapped from
/// double quotes that the `csv` crate kept (` "2.5"`: the quote is not the field's first
/// byte).
fn field_text(field: &str) -> &str {
    let field = field.trim();
    field
        .strip_prefix('"')
        .and_then(|f| f.strip_suffix('"'))
        .unwrap_or(field)
}

/// Blank (only whitespace) and comment (`#` after leading blanks) lines; the `csv` crate
/// skips empty lines and lines starting with `#` by itself.
fn skipped(record: &csv::StringRecord) -> bool {
    match record.get(0) {
        None => true,
        Some(first) => {
            let first = first.trim_start();
            (record.len() == 1 && first.is_empty()) || first.starts_with('#')
        }
    }
}

/// 1-based line numbers of records, counted here: the `csv` crate's `Position::line` is
/// the line where reading started, before the blank and comment lines it skipped, and
/// misses `\r\n` ends (rust-csv issues 208 and 395, open). Its `Position::byte` is right,
/// so from there this skips what csv-core skips before a record (empty lines, and `#`
/// lines up to their end; the terminator is `\n`) and counts the `\n` bytes before the
/// record's first byte.
struct LineCounter<'a> {
    text: &'a [u8],
    /// Where the last counted record starts, and its line.
    offset: usize,
    line: usize,
}

impl<'a> LineCounter<'a> {
    fn new(text: &'a [u8]) -> Self {
        Self {
            text,
            offset: 0,
            line: 1,
        }
    }

    /// The line of the record whose reading started at byte `from`; records come in order.
    fn line_of(&mut self, from: usize) -> usize {
        let line_end = |b: &u8| *b == b'\n';
        let mut start = from.clamp(self.offset, self.text.len());
        loop {
            match self.text.get(start) {
                Some(b) if line_end(b) => start += 1,
                Some(b'#') => {
                    start += self.text[start..]
                        .iter()
                        .position(line_end)
                        .unwrap_or(self.text.len() - start)
                }
                _ => break,
            }
        }
        self.line += self.text[self.offset..start]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.offset = start;
        self.line
    }
}

/// Reads a CSV file; see the module documentation for the format.
pub fn read_csv_file(
    path: &std::path::Path,
    selection: &ColumnSelection,
) -> Result<Dataset, TrainError> {
    let text = stickslip::files::DATA_FILE.read_text(path)?;
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
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        // Lines end at '\n' only, as they did for the hand-written reader (`str::lines`): a
        // '\r' before it is trimmed with the field, a lone '\r' is no line end.
        .terminator(csv::Terminator::Any(b'\n'))
        .from_reader(text.as_bytes());
    let mut record = csv::StringRecord::new();
    let mut lines = LineCounter::new(text.as_bytes());
    // The next record that is not blank or a comment, with its 1-based line number.
    let mut next_record = |record: &mut csv::StringRecord| -> Result<Option<usize>, TrainError> {
        loop {
            let more = reader.read_record(record).map_err(|e| {
                // Input from a &str cannot fail to read or decode; kept for safety.
                let from = e.position().map_or(0, csv::Position::byte);
                error(lines.line_of(from as usize), e.to_string())
            })?;
            if !more {
                return Ok(None);
            }
            if !skipped(record) {
                let from = record.position().map_or(0, csv::Position::byte);
                return Ok(Some(lines.line_of(from as usize)));
            }
        }
    };

    let header_line = next_record(&mut record)?
        .ok_or_else(|| error(1, "the file is empty (no header line)".to_string()))?;
    let columns: Vec<(String, String)> = record
        .iter()
        .map(|field| parse_header_field(field_text(field)))
        .collect();
    check_header(&columns).map_err(|message| error(header_line, message))?;
    let selected = selected_columns(selection, &columns, |message| error(header_line, message))?;
    let roles = feature_roles(selection)?;
    let mut values: Vec<f64> = Vec::new();
    let mut targets: Vec<f64> = Vec::new();
    while let Some(line_number) = next_record(&mut record)? {
        read_row(&record, &columns, &selected, &mut values, &mut targets)
            .map_err(|message| error(line_number, message))?;
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

/// Every column has a name, and no name appears twice; else why not.
fn check_header(columns: &[(String, String)]) -> Result<(), String> {
    for (i, (name, _)) in columns.iter().enumerate() {
        if name.is_empty() {
            return Err(format!("column {} has no name", i + 1));
        }
        if columns[..i].iter().any(|(other, _)| other == name) {
            return Err(format!("column '{name}' appears twice"));
        }
    }
    Ok(())
}

/// The columns of the selected features, in selection order, then the target's; a
/// name the header lacks is refused through `header_error`, which places the message
/// on the header line.
fn selected_columns(
    selection: &ColumnSelection,
    columns: &[(String, String)],
    header_error: impl Fn(String) -> TrainError,
) -> Result<Vec<usize>, TrainError> {
    let find = |name: &str| {
        columns.iter().position(|(n, _)| n == name).ok_or_else(|| {
            let known: Vec<&str> = columns.iter().map(|(n, _)| n.as_str()).collect();
            header_error(format!(
                "no column named '{name}' in the header (columns: {})",
                known.join(", ")
            ))
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
    Ok(selected)
}

/// Each selected feature's role: the sliding velocity and the normal force where the
/// selection names them (each a feature, and not both the same), else other.
fn feature_roles(selection: &ColumnSelection) -> Result<Vec<FeatureRole>, TrainError> {
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
    Ok(roles)
}

/// Appends a data row's selected values: the features' to `values`, the target's (the
/// last selected column) to `targets`; else why the row is refused.
fn read_row(
    record: &csv::StringRecord,
    columns: &[(String, String)],
    selected: &[usize],
    values: &mut Vec<f64>,
    targets: &mut Vec<f64>,
) -> Result<(), String> {
    if record.len() != columns.len() {
        return Err(format!(
            "{} field(s), but the header has {} columns",
            record.len(),
            columns.len()
        ));
    }
    for (k, &column) in selected.iter().enumerate() {
        let text = field_text(&record[column]);
        let value: f64 = text
            .parse()
            .map_err(|_| format!("column '{}': '{text}' is not a number", columns[column].0))?;
        if !value.is_finite() {
            return Err(format!(
                "column '{}': '{text}' is not a finite number",
                columns[column].0
            ));
        }
        if k + 1 == selected.len() {
            targets.push(value);
        } else {
            values.push(value);
        }
    }
    Ok(())
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

    /// The error for `text` is on `line` (None: not checked) and contains `needle`.
    fn assert_error(text: &str, line: Option<usize>, needle: &str) {
        let m = message(text);
        let at = line.map_or(String::new(), |l| format!("t.csv, line {l}: "));
        assert!(m.starts_with(&at) && m.contains(needle), "{text:?}: {m}");
    }

    #[test]
    fn bad_files_name_the_line() {
        for (text, line, needle) in [
            ("", Some(1), "empty"),
            ("v,Fn,F\n", Some(1), "no data rows"),
            ("v,F\n1,2\n", Some(1), "no column named 'Fn'"),
            (
                "v,Fn,F\n0.1,100,20\n0.2,abc,20\n",
                Some(3),
                "'abc' is not a number",
            ),
            ("v,Fn,F\n0.1,100,NaN\n", Some(2), "not a finite"),
            ("v,Fn,F\n0.1,100,inf\n", None, "not a finite"),
            ("v,Fn,F\n0.1,100,20\n0.1,100\n", Some(3), "2 field(s)"),
            ("v,v,F\n1,2,3\n", None, "twice"),
        ] {
            assert_error(text, line, needle);
        }
    }

    #[test]
    fn line_numbers_count_blank_comment_and_quoted_lines() {
        // BOM, CRLF, an indented comment, a whitespace-only line, a quoted note spanning
        // lines 6 and 7: the bad value is on line 9 as an editor shows it.
        let text = "\u{feff}# measured\r\n\r\nv, Fn, F, note\r\n  # indented comment\r\n \t \r\n0.1, 100, 20,\"two\nlines\"\r\n0.2, 100, 21, x\r\n0.3, 100, oops, x\r\n";
        assert_error(text, Some(9), "'oops'");
        assert_error(
            "v,Fn,F\n\n\"a\nb\",1,2\n0.1,100\n",
            Some(3),
            "'a\nb' is not a number",
        );
        assert_error("# x\nv,Fn,F\n\"a\nb\",1,2,3\n", Some(3), "4 field(s)");
        assert_error("\n\n# x\nv,,F\n", Some(4), "column 2 has no name");
    }

    #[test]
    fn quoted_fields_may_hold_commas_and_quoted_numbers_read() {
        let text =
            "\"v [m/s]\",\"Fn[N]\", \"F[N]\",note\n\"0.5\", 100 , \"-2.5\",\"a, \"\"b\"\"\"\n";
        let data = parse_csv(text, "t.csv", &selection()).unwrap();
        assert_eq!(data.features[0], Quantity::new("v", "m/s"));
        assert_eq!(data.target, Quantity::new("F", "N"));
        assert_eq!(data.inputs.column(0).as_slice(), &[0.5, 100.0]);
        assert_eq!(data.targets, vec![-2.5]);
    }
}
