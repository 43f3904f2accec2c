//! Matrix Market coordinate files (`.mtx`, what scipy.io.mmwrite, Code_Aster and PETSc
//! write; Boisvert, Pozo and Remington, "The Matrix Market Exchange Formats: Initial
//! Design", NIST 1996) and the DOF map file that names their rows.
//!
//! # Matrix file
//! A banner `%%MatrixMarket matrix coordinate <field> <symmetry>` (keywords in any case)
//! with field `real` or `integer` and symmetry `symmetric` or `general`; comment lines
//! starting with `%`; a size line `rows cols entries` (square); then `entries` lines
//! `i j value`, 1-based. A `symmetric` file holds the lower triangle with the diagonal
//! (i >= j), as the format defines; it is read as the upper triangle (the transpose). A
//! `general` file is read as written, every entry kept: whether it is symmetric is the
//! physics' check (`stickslip::linear_structure`), which names the worst pair.
//!
//! # DOF map file
//! One line per matrix row, in row order: `node direction`, two integers (node >= 1,
//! direction 1 to 6: x, y, z translations, then rotations about x, y, z, CalculiX's
//! numbering). Blank lines and lines starting with `#` are skipped. Every label appears
//! once.
//!
//! Refused, with the file, the line and the fault: a missing or unsupported banner, a
//! bad size line, non-square sizes, bad numbers, non-finite values, indices out of range,
//! an upper-triangle entry in a symmetric file, an entry twice, fewer or more entries
//! than declared, a DOF map with a repeated label or not one label per row. Allocation
//! is proportional to the input, whatever the size line claims.

use crate::structure_file::{
    direction, fields, index, node, value, DofLabel, DofSet, EntrySet, FileText, Problem,
    ReadError, Stored, StructureMatrices, Triplet, Triplets,
};

/// The structure in the texts of Matrix Market files (K, M, optionally C) and a DOF map
/// file.
pub fn read_structure(
    stiffness: FileText,
    mass: FileText,
    damping: Option<FileText>,
    dof_map: FileText,
) -> Result<StructureMatrices, ReadError> {
    let dofs = read_dof_map(dof_map.name, dof_map.text)?;
    let matrix = |file: FileText| {
        let triplets = read_matrix(file.name, file.text)?;
        if triplets.size != dofs.len() {
            return Err(ReadError {
                file: file.name.to_string(),
                line: None,
                problem: Problem::RowCount {
                    matrix: triplets.size,
                    dofs: dofs.len(),
                    dof_file: dof_map.name.to_string(),
                },
            });
        }
        Ok(triplets)
    };
    Ok(StructureMatrices {
        stiffness: matrix(stiffness)?,
        mass: matrix(mass)?,
        damping: damping.map(matrix).transpose()?,
        dofs,
    })
}

/// Reads a `.mtx` file's text (`name` appears in errors).
pub fn read_matrix(name: &str, text: &str) -> Result<Triplets, ReadError> {
    let source = FileText { name, text };
    let mut lines = text.lines().enumerate().map(|(k, l)| (k + 1, l.trim()));
    let stored = match lines.next() {
        None => return Err(source.error(None, Problem::Empty("no Matrix Market banner"))),
        Some((line, banner)) => header(banner).map_err(|p| source.error(Some(line), p))?,
    };
    let mut data = lines.filter(|(_, l)| !l.is_empty() && !l.starts_with('%'));
    let (size, declared) = match data.next() {
        None => return Err(source.error(None, Problem::Empty("no size line after the banner"))),
        Some((line, content)) => size_line(content).map_err(|p| source.error(Some(line), p))?,
    };
    let mut set = EntrySet::new();
    for (line, content) in data {
        if set.entries.len() == declared {
            return Err(source.error(Some(line), Problem::TooManyEntries { declared }));
        }
        let entry = matrix_entry(content, size, stored).map_err(|p| source.error(Some(line), p))?;
        set.add(entry, line)
            .map_err(|p| source.error(Some(line), p))?;
    }
    if set.entries.len() < declared {
        return Err(source.error(
            None,
            Problem::TooFewEntries {
                found: set.entries.len(),
                declared,
            },
        ));
    }
    Ok(Triplets {
        size,
        stored,
        entries: set.entries,
    })
}

/// The banner's storage: symmetric (read as the upper triangle) or general.
fn header(banner: &str) -> Result<Stored, Problem> {
    let words: Vec<String> = banner
        .split_whitespace()
        .map(|w| w.to_ascii_lowercase())
        .collect();
    let expected = "expected '%%MatrixMarket matrix coordinate real|integer symmetric|general'";
    if words.first().map(String::as_str) != Some("%%matrixmarket") || words.len() != 5 {
        return Err(Problem::Header(format!(
            "'{banner}' is not a Matrix Market banner: {expected}"
        )));
    }
    let refuse = |what: &str, found: &str, why: &str| {
        Err(Problem::Header(format!(
            "{what} '{found}' is not supported ({why}): {expected}"
        )))
    };
    if words[1] != "matrix" {
        return refuse("object", &words[1], "a structure is a matrix");
    }
    if words[2] != "coordinate" {
        return refuse(
            "format",
            &words[2],
            "only the sparse coordinate format is read",
        );
    }
    if words[3] != "real" && words[3] != "integer" {
        return refuse("field", &words[3], "M, K and C are real");
    }
    match words[4].as_str() {
        "symmetric" => Ok(Stored::Upper),
        "general" => Ok(Stored::General),
        other => refuse("symmetry", other, "M, K and C are symmetric"),
    }
}

/// `rows cols entries`, square.
fn size_line(content: &str) -> Result<(usize, usize), Problem> {
    let fields: Vec<&str> = content.split_whitespace().collect();
    if fields.len() != 3 {
        return Err(Problem::FieldCount {
            found: fields.len(),
            expected: 3,
            form: "size line: rows cols entries",
        });
    }
    let count = |text: &str| {
        text.parse::<usize>().map_err(|_| Problem::NotANumber {
            text: text.to_string(),
            what: "count (a non-negative integer)",
        })
    };
    let (rows, cols, entries) = (count(fields[0])?, count(fields[1])?, count(fields[2])?);
    if rows != cols || rows == 0 {
        return Err(Problem::Header(format!(
            "the size line declares {rows} x {cols}: a structure's matrix is square and not empty"
        )));
    }
    Ok((rows, entries))
}

fn matrix_entry(content: &str, size: usize, stored: Stored) -> Result<Triplet, Problem> {
    let [i, j, v] = fields(content, "i j value")?;
    let row = index(i, "row", size)?;
    let col = index(j, "column", size)?;
    let value = value(v)?;
    match stored {
        Stored::General => Ok(Triplet { row, col, value }),
        Stored::Upper if row < col => Err(Problem::WrongTriangle {
            row: row + 1,
            col: col + 1,
            side: "above",
            why: "a symmetric Matrix Market file holds the lower triangle (i >= j)",
        }),
        // The transpose of the lower triangle.
        Stored::Upper => Ok(Triplet {
            row: col,
            col: row,
            value,
        }),
    }
}

/// Reads a DOF map file's text (`name` appears in errors): `node direction` per line.
pub fn read_dof_map(name: &str, text: &str) -> Result<Vec<DofLabel>, ReadError> {
    let source = FileText { name, text };
    let mut set = DofSet::new("");
    for (line, content) in source.data_lines(&['#']) {
        let fields: Vec<&str> = content.split_whitespace().collect();
        let label = if fields.len() != 2 {
            Err(Problem::FieldCount {
                found: fields.len(),
                expected: 2,
                form: "node direction",
            })
        } else {
            node(fields[0]).and_then(|node| {
                Ok(DofLabel {
                    node,
                    direction: direction(fields[1])?,
                })
            })
        };
        label
            .and_then(|label| set.add(label, line))
            .map_err(|p| source.error(Some(line), p))?;
    }
    if set.labels.is_empty() {
        return Err(source.error(None, Problem::Empty("no DOF labels (node direction)")));
    }
    Ok(set.labels)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SYMMETRIC: &str = "%%MatrixMarket matrix coordinate real symmetric\n% K of two springs\n2 2 3\n1 1 2.0\n2 1 -1\n2 2 1e0\n";

    #[test]
    fn a_symmetric_file_is_read_as_its_upper_triangle() {
        let m = read_matrix("k.mtx", SYMMETRIC).unwrap();
        assert_eq!(m.size, 2);
        assert_eq!(m.stored, Stored::Upper);
        assert_eq!(
            m.entries,
            vec![
                Triplet {
                    row: 0,
                    col: 0,
                    value: 2.0
                },
                Triplet {
                    row: 0,
                    col: 1,
                    value: -1.0
                },
                Triplet {
                    row: 1,
                    col: 1,
                    value: 1.0
                },
            ]
        );
        let general = read_matrix(
            "k.mtx",
            "%%MatrixMarket MATRIX Coordinate integer General\n2 2 2\n1 2 3\n2 1 3\n",
        )
        .unwrap();
        assert_eq!(general.stored, Stored::General);
        assert_eq!(general.entries.len(), 2);
        let map = read_dof_map("k.dofs", "# node direction\n7 1\n\n7 2\n").unwrap();
        assert_eq!(
            map[1],
            DofLabel {
                node: 7,
                direction: 2
            }
        );
    }

    /// Each malformed file and the message a user sees (docs/structures.md's table).
    #[test]
    fn bad_files_name_the_file_the_line_and_the_fault() {
        let mtx = |text: &str| read_matrix("k.mtx", text).unwrap_err().to_string();
        let map = |text: &str| read_dof_map("k.dofs", text).unwrap_err().to_string();
        let banner = "%%MatrixMarket matrix coordinate real symmetric\n";
        let expected = "expected '%%MatrixMarket matrix coordinate real|integer symmetric|general'";
        let cases: Vec<(String, String)> = vec![
            (mtx(""), "k.mtx: is empty: no Matrix Market banner".into()),
            (
                mtx("2 2 1\n1 1 1\n"),
                format!("k.mtx, line 1: '2 2 1' is not a Matrix Market banner: {expected}"),
            ),
            (
                mtx("%%MatrixMarket matrix array real symmetric\n"),
                format!("k.mtx, line 1: format 'array' is not supported (only the sparse coordinate format is read): {expected}"),
            ),
            (
                mtx("%%MatrixMarket matrix coordinate complex symmetric\n"),
                format!("k.mtx, line 1: field 'complex' is not supported (M, K and C are real): {expected}"),
            ),
            (
                mtx("%%MatrixMarket matrix coordinate real skew-symmetric\n"),
                format!("k.mtx, line 1: symmetry 'skew-symmetric' is not supported (M, K and C are symmetric): {expected}"),
            ),
            (
                mtx(banner),
                "k.mtx: is empty: no size line after the banner".into(),
            ),
            (
                mtx(&format!("{banner}2 3 1\n")),
                "k.mtx, line 2: the size line declares 2 x 3: a structure's matrix is square and not empty".into(),
            ),
            (
                mtx(&format!("{banner}2 2\n")),
                "k.mtx, line 2: 2 fields where 3 are expected (size line: rows cols entries)".into(),
            ),
            (
                mtx(&format!("{banner}2 2 x\n")),
                "k.mtx, line 2: 'x' is not a count (a non-negative integer)".into(),
            ),
            (
                mtx(&format!("{banner}2 2 2\n1 1 1\n1 2 1\n")),
                "k.mtx, line 4: entry (1, 2) is above the diagonal: a symmetric Matrix Market file holds the lower triangle (i >= j)".into(),
            ),
            (
                mtx(&format!("{banner}2 2 2\n1 1 1\n3 1 1\n")),
                "k.mtx, line 4: row 3 is outside 1..=2 (the matrix has 2 rows)".into(),
            ),
            (
                mtx(&format!("{banner}2 2 2\n1 1 1\n2 1 1.5.2\n")),
                "k.mtx, line 4: '1.5.2' is not a real number".into(),
            ),
            (
                mtx(&format!("{banner}2 2 2\n1 1 1\n2 1 -inf\n")),
                "k.mtx, line 4: the value -inf is not finite".into(),
            ),
            (
                mtx(&format!("{banner}2 2 3\n1 1 1\n2 1 1\n")),
                "k.mtx: the file ends after 2 of the 3 entries its size line declares".into(),
            ),
            (
                mtx(&format!("{banner}2 2 1\n1 1 1\n2 2 1\n")),
                "k.mtx, line 4: an entry beyond the 1 its size line declares".into(),
            ),
            (
                mtx(&format!("{banner}2 2 2\n2 1 1\n2 1 1\n")),
                "k.mtx, line 4: entry (1, 2) appears a second time (first on line 3)".into(),
            ),
            (map(""), "k.dofs: is empty: no DOF labels (node direction)".into()),
            (
                map("1 1\n1.2\n"),
                "k.dofs, line 2: 1 fields where 2 are expected (node direction)".into(),
            ),
            (
                map("1 1\n1 0\n"),
                "k.dofs, line 2: '0' is not a direction (1 to 6: x, y, z, then rotations about them)".into(),
            ),
            (
                map("1 1\n# x\n1 1\n"),
                "k.dofs, line 3: node 1 direction 1 appears a second time (first on line 1)".into(),
            ),
        ];
        for (got, want) in &cases {
            assert_eq!(got, want);
        }
    }

    #[test]
    fn a_size_line_does_not_reserve_memory() {
        // A size line claiming 10^18 entries is refused once the file ends, having
        // allocated for the one entry there is.
        let e = read_matrix(
            "k.mtx",
            "%%MatrixMarket matrix coordinate real general\n1000000000 1000000000 1000000000000000000\n1 1 1\n",
        )
        .unwrap_err();
        assert!(matches!(e.problem, Problem::TooFewEntries { found: 1, .. }));
    }

    #[test]
    fn the_dof_map_must_have_one_label_per_row() {
        let k = FileText {
            name: "k.mtx",
            text: SYMMETRIC,
        };
        let dofs = FileText {
            name: "k.dofs",
            text: "1 1\n1 2\n2 1\n",
        };
        let e = read_structure(k, k, None, dofs).unwrap_err();
        assert_eq!(
            e.to_string(),
            "k.mtx: the matrix has 2 rows but k.dofs lists 3 DOFs: one label per row is needed"
        );
        let two = FileText {
            name: "k.dofs",
            text: "1 1\n1 2\n",
        };
        let c = FileText {
            name: "c.mtx",
            text: "%%MatrixMarket matrix coordinate real general\n3 3 1\n1 1 1\n",
        };
        let with_damping = read_structure(k, k, Some(k), two).unwrap();
        assert_eq!(with_damping.damping.unwrap().entries.len(), 3);
        assert_eq!(
            read_structure(k, k, Some(c), two).unwrap_err().to_string(),
            "c.mtx: the matrix has 3 rows but k.dofs lists 2 DOFs: one label per row is needed"
        );
    }
}
