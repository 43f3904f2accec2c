//! A structure's files opened through `files` (the one reader of what a user hands in:
//! type, size, emptiness and UTF-8 checked) and parsed by `stickslip_formats`.

use crate::files::{InputFileError, STRUCTURE_FILE};
use std::path::Path;
use stickslip_formats::calculix;
use stickslip_formats::matrix_market;
use stickslip_formats::structure_file::{FileText, ReadError, StructureMatrices};

/// Why a structure's files could not be read: the file itself (missing, empty, not text,
/// too large) or its contents (the file, the line and the fault).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StructureFileError {
    #[error("{0}")]
    File(#[from] InputFileError),
    #[error("{0}")]
    Contents(#[from] ReadError),
}

/// A file's text and its path as messages show it.
struct Opened {
    name: String,
    text: String,
}

impl Opened {
    fn new(path: &Path) -> Result<Self, InputFileError> {
        Ok(Self {
            name: path.display().to_string(),
            text: STRUCTURE_FILE.read_text(path)?,
        })
    }

    fn text(&self) -> FileText<'_> {
        FileText {
            name: &self.name,
            text: &self.text,
        }
    }
}

/// The matrices CalculiX wrote for job `job` (a path without extension: `dir/beam` for
/// `dir/beam.sti`, `.mas`, `.dof`).
pub fn read_calculix(job: &Path) -> Result<StructureMatrices, StructureFileError> {
    let [sti, mas, dof] = calculix::job_files(job);
    // The .dof first: a missing job is named by the file that gives the rows.
    let dof = Opened::new(&dof)?;
    let sti = Opened::new(&sti)?;
    let mas = Opened::new(&mas)?;
    Ok(calculix::read_job(sti.text(), mas.text(), dof.text())?)
}

/// A structure in Matrix Market files: K, M, optionally C, and the DOF map file
/// (`matrix_market`'s module doc gives both formats).
pub fn read_matrix_market(
    stiffness: &Path,
    mass: &Path,
    damping: Option<&Path>,
    dof_map: &Path,
) -> Result<StructureMatrices, StructureFileError> {
    let map = Opened::new(dof_map)?;
    let k = Opened::new(stiffness)?;
    let m = Opened::new(mass)?;
    let c = damping.map(Opened::new).transpose()?;
    Ok(matrix_market::read_structure(
        k.text(),
        m.text(),
        c.as_ref().map(Opened::text),
        map.text(),
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_or_empty_file_is_named_by_the_file_reader() {
        assert_eq!(
            read_calculix(Path::new("/nonexistent/job"))
                .unwrap_err()
                .to_string(),
            "structure file /nonexistent/job.dof: no such file"
        );
        let dir = std::env::temp_dir().join(format!("structure-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (k, map) = (dir.join("k.mtx"), dir.join("k.dofs"));
        std::fs::write(&k, "").unwrap();
        std::fs::write(&map, "1 1\n").unwrap();
        let e = read_matrix_market(&k, &k, None, &map).unwrap_err();
        std::fs::write(
            &k,
            "%%MatrixMarket matrix coordinate real symmetric\n1 1 1\n1 1 x\n",
        )
        .unwrap();
        let contents = read_matrix_market(&k, &k, None, &map).unwrap_err();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(
            e.to_string(),
            format!("structure file {}: the file is empty", k.display())
        );
        assert_eq!(
            contents.to_string(),
            format!("{}, line 3: 'x' is not a real number", k.display())
        );
    }
}
