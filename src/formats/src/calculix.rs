//! CalculiX's matrix storage: the files `ccx` writes for a step
//! `*FREQUENCY, SOLVER=MATRIXSTORAGE` (no data line; `*STATIC` with that solver writes
//! nothing), read into [`Triplets`] and [`DofLabel`]s.
//!
//! - `JOB.sti` (stiffness) and `JOB.mas` (mass): one entry `i j value` per line, 1-based,
//!   the upper triangle with the diagonal (i <= j), column by column, 14 significant
//!   digits (`%.13e`); both share one sparsity pattern, explicit zeros included.
//! - `JOB.dof`: one label `node.direction` per matrix row, in row order, with the user's
//!   node numbers; DOFs fixed by `*BOUNDARY` are already removed from the matrices.
//!
//! Measured with CalculiX 2.20 (Debian `calculix-ccx`): a CPE8 (plane strain) model lists
//! only in-plane DOFs, one label each; a CPS8 model lists the out-of-plane DOFs of the 3D
//! slab ccx expands it into under repeated labels, which [`read_dofs`] refuses (a
//! repeated label cannot name one row).
//!
//! The reader checks what makes the files unreadable: numbers, indices within the
//! `.dof`'s row count, no entry below the diagonal, no entry twice, finite values, a
//! matrix with as many rows as the `.dof` has labels. Allocation is proportional to the
//! input.

use crate::structure_file::{
    direction, fields, index, node, value, DofLabel, DofSet, EntrySet, FileText, Problem,
    ReadError, Stored, StructureMatrices, Triplet, Triplets,
};
use std::path::{Path, PathBuf};

/// What a `JOB.dof` duplicate usually means.
const DUPLICATE_HINT: &str = "; ccx lists a CPS8 or other expanded 2D model's out-of-plane DOFs under the in-plane labels, so a 2D model must be CPE8 (plane strain; for plane stress use E* = E (1 + 2 nu) / (1 + nu)^2, nu* = nu / (1 + nu)) or a 3D one";

/// The three files of job `job` (a path without extension: `dir/beam` for
/// `dir/beam.sti`, `.mas`, `.dof`).
pub fn job_files(job: &Path) -> [PathBuf; 3] {
    let with = |ext: &str| {
        let mut p = job.as_os_str().to_owned();
        p.push(ext);
        PathBuf::from(p)
    };
    [with(".sti"), with(".mas"), with(".dof")]
}

/// The structure in the texts of `JOB.sti`, `JOB.mas` and `JOB.dof` (ccx writes no damping
/// matrix).
pub fn read_job(
    stiffness: FileText,
    mass: FileText,
    dofs: FileText,
) -> Result<StructureMatrices, ReadError> {
    let labels = read_dofs(dofs.name, dofs.text)?;
    let matrix = |file: FileText| read_matrix(file.name, file.text, labels.len(), dofs.name);
    Ok(StructureMatrices {
        stiffness: matrix(stiffness)?,
        mass: matrix(mass)?,
        damping: None,
        dofs: labels,
    })
}

/// Reads a `.dof` file's text (`name` appears in errors): one `node.direction` per line.
pub fn read_dofs(name: &str, text: &str) -> Result<Vec<DofLabel>, ReadError> {
    let source = FileText { name, text };
    let mut set = DofSet::new(DUPLICATE_HINT);
    for (line, content) in source.data_lines(&[]) {
        let label = dof_label(content).map_err(|p| source.error(Some(line), p))?;
        set.add(label, line)
            .map_err(|p| source.error(Some(line), p))?;
    }
    if set.labels.is_empty() {
        return Err(source.error(None, Problem::Empty("no DOF labels (node.direction)")));
    }
    Ok(set.labels)
}

fn dof_label(content: &str) -> Result<DofLabel, Problem> {
    let fields: Vec<&str> = content.split_whitespace().collect();
    if fields.len() != 1 {
        return Err(Problem::FieldCount {
            found: fields.len(),
            expected: 1,
            form: "node.direction",
        });
    }
    let (n, d) = fields[0]
        .split_once('.')
        .ok_or_else(|| Problem::NotANumber {
            text: fields[0].to_string(),
            what: "DOF label node.direction",
        })?;
    Ok(DofLabel {
        node: node(n)?,
        direction: direction(d)?,
    })
}

/// Reads a `.sti` or `.mas` file's text (`name` appears in errors) for a model of `dofs`
/// rows, as listed by the file `dof_file`.
pub fn read_matrix(
    name: &str,
    text: &str,
    dofs: usize,
    dof_file: &str,
) -> Result<Triplets, ReadError> {
    let source = FileText { name, text };
    let mut set = EntrySet::new();
    let mut largest = 0;
    for (line, content) in source.data_lines(&[]) {
        let entry = matrix_entry(content, dofs).map_err(|p| source.error(Some(line), p))?;
        largest = largest.max(entry.col + 1);
        set.add(entry, line)
            .map_err(|p| source.error(Some(line), p))?;
    }
    if set.entries.is_empty() {
        return Err(source.error(None, Problem::Empty("no entries (i j value)")));
    }
    // ccx writes every diagonal entry, so the largest index is the row count.
    if largest != dofs {
        return Err(source.error(
            None,
            Problem::RowCount {
                matrix: largest,
                dofs,
                dof_file: dof_file.to_string(),
            },
        ));
    }
    Ok(Triplets {
        size: dofs,
        stored: Stored::Upper,
        entries: set.entries,
    })
}

fn matrix_entry(content: &str, size: usize) -> Result<Triplet, Problem> {
    let [i, j, v] = fields(content, "i j value")?;
    let row = index(i, "row", size)?;
    let col = index(j, "column", size)?;
    let value = value(v)?;
    if row > col {
        return Err(Problem::WrongTriangle {
            row: row + 1,
            col: col + 1,
            side: "below",
            why: "CalculiX writes the upper triangle (i <= j)",
        });
    }
    Ok(Triplet { row, col, value })
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOF: &str = "1.2\n3.1\n3.2\n";
    const STI: &str = "1 1  4.0000000000000e+00\n1 2 -1.0000000000000e+00\n2 2  5.0000000000000e+00\n3 3  6.0000000000000e+00\n";

    fn message(e: ReadError) -> String {
        e.to_string()
    }

    #[test]
    fn reads_labels_and_the_upper_triangle() {
        let dofs = read_dofs("b.dof", DOF).unwrap();
        assert_eq!(
            dofs,
            vec![
                DofLabel {
                    node: 1,
                    direction: 2
                },
                DofLabel {
                    node: 3,
                    direction: 1
                },
                DofLabel {
                    node: 3,
                    direction: 2
                }
            ]
        );
        let k = read_matrix("b.sti", STI, 3, "b.dof").unwrap();
        assert_eq!(k.size, 3);
        assert_eq!(k.stored, Stored::Upper);
        assert_eq!(
            k.entries[1],
            Triplet {
                row: 0,
                col: 1,
                value: -1.0
            }
        );
        assert_eq!(k.entries.len(), 4);
    }

    /// Each malformed file and the message a user sees (docs/structures.md's table).
    #[test]
    fn bad_files_name_the_file_the_line_and_the_fault() {
        let sti = |text: &str| message(read_matrix("b.sti", text, 3, "b.dof").unwrap_err());
        let dof = |text: &str| message(read_dofs("b.dof", text).unwrap_err());
        let cases: Vec<(String, &str)> = vec![
            (sti(""), "b.sti: is empty: no entries (i j value)"),
            (
                sti("1 1 4\n1 2 x\n"),
                "b.sti, line 2: 'x' is not a real number",
            ),
            (sti("1 1 4\n1 2 nan\n"), "b.sti, line 2: the value nan is not finite"),
            (sti("1 1 inf\n"), "b.sti, line 1: the value inf is not finite"),
            (
                sti("1 1 4\n1 4 1\n"),
                "b.sti, line 2: column 4 is outside 1..=3 (the matrix has 3 rows)",
            ),
            (
                sti("0 1 4\n"),
                "b.sti, line 1: row 0 is outside 1..=3 (indices are 1-based)",
            ),
            (
                sti("1 1 4\n-1 2 4\n"),
                "b.sti, line 2: '-1' is not a positive integer (1-based index)",
            ),
            (
                sti("1 1 4\n2 1 4\n"),
                "b.sti, line 2: entry (2, 1) is below the diagonal: CalculiX writes the upper triangle (i <= j)",
            ),
            (
                sti("1 1 4\n2 2 4\n1 1 5\n"),
                "b.sti, line 3: entry (1, 1) appears a second time (first on line 1)",
            ),
            (
                // Out of ccx's column order from line 3 on, the repeat two lines later.
                sti("1 1 4\n2 2 4\n1 2 1\n3 3 1\n1 2 2\n"),
                "b.sti, line 5: entry (1, 2) appears a second time (first on line 3)",
            ),
            (
                sti("1 1 4\n2 2 4\n"),
                "b.sti: the matrix has 2 rows but b.dof lists 3 DOFs: one label per row is needed",
            ),
            (
                sti("1 1 4 5\n"),
                "b.sti, line 1: 4 fields where 3 are expected (i j value)",
            ),
            (dof("\n\n"), "b.dof: is empty: no DOF labels (node.direction)"),
            (
                dof("1.2\n3\n"),
                "b.dof, line 2: '3' is not a DOF label node.direction",
            ),
            (
                dof("1.2\n3.7\n"),
                "b.dof, line 2: '7' is not a direction (1 to 6: x, y, z, then rotations about them)",
            ),
            (
                dof("0.1\n"),
                "b.dof, line 1: '0' is not a node number (a positive integer)",
            ),
            (
                dof("1.1 1.2\n"),
                "b.dof, line 1: 2 fields where 1 are expected (node.direction)",
            ),
        ];
        for (got, want) in &cases {
            assert_eq!(got, want);
        }
        let duplicate = dof("1.1\n1.2\n1.1\n");
        assert!(
            duplicate.starts_with(
                "b.dof, line 3: node 1 direction 1 appears a second time (first on line 1); ccx lists a CPS8"
            ),
            "{duplicate}"
        );
    }
}
