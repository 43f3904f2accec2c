//! What the structure readers (`calculix`, `matrix_market`) give and how they refuse: a
//! sparse matrix as triplets, the DOF labels of its rows, and [`ReadError`], which names
//! the file, the line and what is wrong.
//!
//! Plain data only: no check here needs the physics. Whether a matrix is symmetric,
//! positive definite on the free DOFs, or fits its DOF map is the physics' to decide
//! (`stickslip::linear_structure`); what a reader refuses is what makes a file unreadable
//! (a bad number, an index out of range, an entry where the format has none, a count
//! that does not match).

use std::collections::HashMap;
use std::fmt;

/// One degree of freedom: a node number of the user's mesh and a direction, in the
/// numbering CalculiX uses (1, 2, 3: translations x, y, z; 4, 5, 6: rotations about them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct DofLabel {
    pub node: u64,
    pub direction: u8,
}

impl fmt::Display for DofLabel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "node {} direction {}", self.node, self.direction)
    }
}

/// The largest direction number: three translations and three rotations.
pub const MAX_DIRECTION: u8 = 6;

/// Which entries a [`Triplets`] holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stored {
    /// The upper triangle with the diagonal (row <= col); the matrix is symmetric by
    /// construction, a_ji = a_ij.
    Upper,
    /// Every entry as written; symmetry is a claim the physics checks.
    General,
}

/// One entry a_(row, col) = value, 0-based.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triplet {
    pub row: usize,
    pub col: usize,
    pub value: f64,
}

/// A square sparse matrix of `size` rows as a list of entries, each (row, col) at most
/// once; entries not listed are zero.
#[derive(Clone, Debug, PartialEq)]
pub struct Triplets {
    pub size: usize,
    pub stored: Stored,
    pub entries: Vec<Triplet>,
}

/// A structure as its files give it: M, K, optionally C, all of the same size, and the
/// label of each row.
#[derive(Clone, Debug, PartialEq)]
pub struct StructureMatrices {
    pub stiffness: Triplets,
    pub mass: Triplets,
    pub damping: Option<Triplets>,
    pub dofs: Vec<DofLabel>,
}

/// Why a structure file could not be read: the file, the line (1-based, when the
/// problem is on one) and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct ReadError {
    pub file: String,
    pub line: Option<usize>,
    pub problem: Problem,
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}, line {}: {}", self.file, line, self.problem),
            None => write!(f, "{}: {}", self.file, self.problem),
        }
    }
}

/// What is wrong with a structure file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Problem {
    #[error("is empty: {0}")]
    Empty(&'static str),
    #[error("{found} fields where {expected} are expected ({form})")]
    FieldCount {
        found: usize,
        expected: usize,
        form: &'static str,
    },
    #[error("'{text}' is not a {what}")]
    NotANumber { text: String, what: &'static str },
    #[error("the value {text} is not finite")]
    NotFinite { text: String },
    #[error("{what} {index} is outside 1..={size} ({why})")]
    IndexOutOfRange {
        what: &'static str,
        index: u64,
        size: usize,
        why: String,
    },
    #[error("entry ({row}, {col}) is {side} the diagonal: {why}")]
    WrongTriangle {
        row: usize,
        col: usize,
        side: &'static str,
        why: &'static str,
    },
    #[error("entry ({row}, {col}) appears a second time (first on line {first_line})")]
    DuplicateEntry {
        row: usize,
        col: usize,
        first_line: usize,
    },
    #[error("{label} appears a second time (first on line {first_line}){hint}")]
    DuplicateDof {
        label: DofLabel,
        first_line: usize,
        /// What the format's writer may have meant by it, or empty.
        hint: &'static str,
    },
    #[error("the matrix has {matrix} rows but {dof_file} lists {dofs} DOFs: one label per row is needed")]
    RowCount {
        matrix: usize,
        dofs: usize,
        dof_file: String,
    },
    #[error("{0}")]
    Header(String),
    #[error("the file ends after {found} of the {declared} entries its size line declares")]
    TooFewEntries { found: usize, declared: usize },
    #[error("an entry beyond the {declared} its size line declares")]
    TooManyEntries { declared: usize },
}

/// A file's name (as errors show it) and its text. The readers take text, not paths: the
/// files a user hands in are opened in one place (`stickslip::files`, which refuses
/// FIFOs, devices, oversized and non-UTF-8 files before any parser sees them).
#[derive(Clone, Copy, Debug)]
pub struct FileText<'a> {
    pub name: &'a str,
    pub text: &'a str,
}

impl FileText<'_> {
    pub(crate) fn error(&self, line: Option<usize>, problem: Problem) -> ReadError {
        ReadError {
            file: self.name.to_string(),
            line,
            problem,
        }
    }

    /// The lines with their 1-based numbers, without the blank ones and those that start
    /// with one of `comment` (after leading blanks).
    pub(crate) fn data_lines<'s>(
        &'s self,
        comment: &'s [char],
    ) -> impl Iterator<Item = (usize, &'s str)> + 's {
        self.text
            .lines()
            .enumerate()
            .map(|(k, l)| (k + 1, l.trim()))
            .filter(move |(_, l)| !l.is_empty() && !l.starts_with(comment))
    }
}

/// The `N` whitespace-separated fields of a line of the form `form`, without allocating
/// (the matrix readers call it once per entry: 1.86 M times for a 50,700-DOF `.sti`).
pub(crate) fn fields<'a, const N: usize>(
    content: &'a str,
    form: &'static str,
) -> Result<[&'a str; N], Problem> {
    let mut words = content.split_whitespace();
    let mut out = [""; N];
    for (found, slot) in out.iter_mut().enumerate() {
        *slot = words.next().ok_or(Problem::FieldCount {
            found,
            expected: N,
            form,
        })?;
    }
    match words.count() {
        0 => Ok(out),
        more => Err(Problem::FieldCount {
            found: N + more,
            expected: N,
            form,
        }),
    }
}

/// A 1-based index, at most `size`, as 0-based.
pub(crate) fn index(text: &str, what: &'static str, size: usize) -> Result<usize, Problem> {
    let value: u64 = text.parse().map_err(|_| Problem::NotANumber {
        text: text.to_string(),
        what: "positive integer (1-based index)",
    })?;
    if value == 0 || value > size as u64 {
        return Err(Problem::IndexOutOfRange {
            what,
            index: value,
            size,
            why: if value == 0 {
                "indices are 1-based".to_string()
            } else {
                format!("the matrix has {size} rows")
            },
        });
    }
    Ok(value as usize - 1)
}

/// A finite real number.
pub(crate) fn value(text: &str) -> Result<f64, Problem> {
    let value: f64 = text.parse().map_err(|_| Problem::NotANumber {
        text: text.to_string(),
        what: "real number",
    })?;
    if !value.is_finite() {
        return Err(Problem::NotFinite {
            text: text.to_string(),
        });
    }
    Ok(value)
}

/// A direction 1..=6.
pub(crate) fn direction(text: &str) -> Result<u8, Problem> {
    match text.parse::<u8>() {
        Ok(d) if (1..=MAX_DIRECTION).contains(&d) => Ok(d),
        _ => Err(Problem::NotANumber {
            text: text.to_string(),
            what: "direction (1 to 6: x, y, z, then rotations about them)",
        }),
    }
}

/// A node number, 1 or more.
pub(crate) fn node(text: &str) -> Result<u64, Problem> {
    match text.parse::<u64>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(Problem::NotANumber {
            text: text.to_string(),
            what: "node number (a positive integer)",
        }),
    }
}

/// Collects entries refusing a repeated (row, col), naming the line of the first.
///
/// Files written by a program list their entries in order (ccx: column by column, rows
/// ascending), and entries strictly increasing in (column, row) cannot repeat: while they
/// come so, only the last key is compared. The first entry out of that order moves the
/// set to a hash map of every key seen (with its line), the general check. Measured on
/// ccx's 1.86 M-entry `.sti` of 50,700 DOFs: the map alone took about a third of the
/// read (docs/structures.md, "The 50,000-DOF claim").
pub(crate) struct EntrySet {
    /// Every key seen with its line, once the entries left (column, row) order.
    seen: Option<HashMap<(usize, usize), usize>>,
    /// The line of each entry, while they are in order (the map's lines when it is built).
    lines: Vec<usize>,
    pub entries: Vec<Triplet>,
}

impl EntrySet {
    pub fn new() -> Self {
        Self {
            seen: None,
            lines: Vec::new(),
            entries: Vec::new(),
        }
    }

    /// Adds a 0-based entry read on `line`; a duplicate names both (1-based) positions.
    pub fn add(&mut self, entry: Triplet, line: usize) -> Result<(), Problem> {
        let key = |t: &Triplet| (t.col, t.row);
        if self.seen.is_none() {
            let in_order = self
                .entries
                .last()
                .is_none_or(|last| key(last) < key(&entry));
            if in_order {
                self.entries.push(entry);
                self.lines.push(line);
                return Ok(());
            }
            let map = self
                .entries
                .iter()
                .zip(&self.lines)
                .map(|(t, &l)| ((t.row, t.col), l))
                .collect();
            self.seen = Some(map);
            self.lines = Vec::new();
        }
        let seen = self.seen.as_mut().expect("built above");
        if let Some(&first_line) = seen.get(&(entry.row, entry.col)) {
            return Err(Problem::DuplicateEntry {
                row: entry.row + 1,
                col: entry.col + 1,
                first_line,
            });
        }
        seen.insert((entry.row, entry.col), line);
        self.entries.push(entry);
        Ok(())
    }
}

/// Collects DOF labels refusing a repeated one, naming the line of the first.
pub(crate) struct DofSet {
    seen: HashMap<DofLabel, usize>,
    pub labels: Vec<DofLabel>,
    hint: &'static str,
}

impl DofSet {
    /// `hint` is appended to a duplicate's message.
    pub fn new(hint: &'static str) -> Self {
        Self {
            seen: HashMap::new(),
            labels: Vec::new(),
            hint,
        }
    }

    pub fn add(&mut self, label: DofLabel, line: usize) -> Result<(), Problem> {
        if let Some(&first_line) = self.seen.get(&label) {
            return Err(Problem::DuplicateDof {
                label,
                first_line,
                hint: self.hint,
            });
        }
        self.seen.insert(label, line);
        self.labels.push(label);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::{calculix, matrix_market};

    /// Every reader on 20,000 corruptions of a valid file (bytes replaced, deleted or
    /// repeated at deterministic pseudo-random places) returns a value or an error naming
    /// the file: none panics, and every error's line is a line of the input.
    #[test]
    fn corrupted_files_are_refused_without_panicking() {
        let sti = "1 1  4.0000000000000e+00\n1 2 -1.0000000000000e+00\n2 2  5.0000000000000e+00\n";
        let dof = "1.2\n3.1\n";
        let mtx = "%%MatrixMarket matrix coordinate real symmetric\n% c\n2 2 3\n1 1 2.0\n2 1 -1\n2 2 1e0\n";
        let map = "# node direction\n1 1\n1 2\n";
        let alphabet = b"0123456789.-+eE \n%#x";
        let mut state: u64 = 0x2545_F491_4F6C_DD1D;
        let mut next = |bound: usize| {
            // xorshift64 (Marsaglia 2003): enough to spread the corruptions.
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % bound as u64) as usize
        };
        for round in 0..20_000 {
            let original = [sti, dof, mtx, map][round % 4];
            let mut bytes = original.as_bytes().to_vec();
            for _ in 0..1 + next(3) {
                let at = next(bytes.len());
                match next(3) {
                    0 => bytes[at] = alphabet[next(alphabet.len())],
                    1 => {
                        bytes.remove(at);
                    }
                    _ => {
                        let end = (at + next(8)).min(bytes.len());
                        let copy = bytes[at..end].to_vec();
                        bytes.splice(at..at, copy);
                    }
                }
                if bytes.is_empty() {
                    break;
                }
            }
            let text = String::from_utf8(bytes).expect("the alphabet is ASCII");
            let lines = text.lines().count();
            let error = match round % 4 {
                0 => calculix::read_matrix("f", &text, 2, "d").err(),
                1 => calculix::read_dofs("f", &text).err(),
                2 => matrix_market::read_matrix("f", &text).err(),
                _ => matrix_market::read_dof_map("f", &text).err(),
            };
            if let Some(e) = error {
                assert_eq!(e.file, "f");
                assert!(
                    e.line.is_none_or(|l| (1..=lines).contains(&l)),
                    "{e}\n{text}"
                );
            }
        }
    }
}
