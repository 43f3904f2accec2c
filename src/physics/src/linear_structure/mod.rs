//! A linear structure from a user's FE code: M u'' + C u' + K u = f, with M, K (C
//! optional) read from files (`stickslip_formats::calculix`, `matrix_market`), each row
//! named by a DOF label (node, direction), clamped DOFs removed by label, and checked once
//! (issue 35 item 1):
//! - the matrices have one row per label, and every label is there once;
//! - each matrix is symmetric: a `general` file's a_ij and a_ji differ by at most
//!   [`SYMMETRY_TOLERANCE`] sqrt(|a_ii a_jj|) (else refused with the worst pair);
//! - K and M are positive definite on the free DOFs (else refused with the Cholesky pivot
//!   and the DOF where it fails, which names the unclamped rigid-body motion or the
//!   mechanism).
//!
//! # Solver
//! The free DOFs are renumbered by reverse Cuthill-McKee (`ordering`) and the matrices
//! stored in the symmetric band of `banded`, whose Cholesky the beam and the plane-stress
//! mesh use: its pivots name the failing row, its operation order is fixed (the same
//! bits on every CPU, which the project tests), and on the 2D meshes issue 35 starts
//! with it is as fast as faer's sparse Cholesky or faster (docs/structures.md,
//! "Factorisation", measured here). Its cost grows with the band, O(n b^2): a structure
//! whose band would pass the memory limit (a 3D solid) is refused here and reduced by
//! `sparse_modal` from faer's sparse factorisation (`sparse`).
//!
//! The files are read by [`read_calculix`] and [`read_matrix_market`] (opened through
//! `files`, parsed by `stickslip_formats`).
//!
//! Provided: the static displacement under a load given at labelled DOFs, and the lowest
//! natural frequencies by shift-invert Lanczos on the factor of K (`modal::lanczos`, the
//! plane-stress mesh's solver).

pub mod estimates;
mod ordering;
mod read;
pub mod scene_model;
pub mod sparse;
pub mod sparse_modal;

pub use read::{read_calculix, read_matrix_market, StructureFileError};

use crate::banded::{BandCholesky, SymBandMatrix};
use crate::modal::{self, Modes};
use crate::short::Short;
use crate::structure::ModelError;
use std::collections::HashMap;
use stickslip_formats::structure_file::{DofLabel, Stored, StructureMatrices, Triplets};

/// Largest |a_ij - a_ji| / sqrt(|a_ii a_jj|) a symmetric matrix may show. The files carry
/// 14 significant digits, so one printed entry is off by up to 5e-14 of itself, and an
/// entry of a positive definite matrix is at most sqrt(a_ii a_jj) (Cauchy-Schwarz):
/// two printings of one value differ by at most 1e-13 of that scale. 1e-12 allows ten
/// times that for round-off of an assembly that summed the two triangles' element
/// contributions in different orders, and is far below any modelling asymmetry (a
/// follower load, a gyroscopic term: 1e-3 and up).
pub const SYMMETRY_TOLERANCE: f64 = 1e-12;

/// Band matrices alive at the peak of [`LinearStructure::new`]: K, M, C, the factor of K
/// (stored twice, by rows and by columns) and the working copy of the mass matrix's
/// factorisation (three more).
const BAND_COPIES: f64 = 8.0;

/// The most memory (bytes) the band storage may take: a 3D solid of 40,560 DOFs (an
/// 80 x 12 x 12 C3D8 block from ccx) has a band of 1,409 after reverse Cuthill-McKee,
/// 3.7 GB at [`BAND_COPIES`], and its factorisation would take about 40 s at the
/// 1 GFlop/s measured on the 10k-DOF block, where faer's sparse one takes 1.8 s
/// (docs/structures.md, "Factorisation").
const BAND_MEMORY_LIMIT: f64 = 2e9;

/// Why a structure was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StructureError {
    #[error("the {matrix} matrix has {rows} rows but the DOF map lists {dofs} DOFs")]
    RowCount {
        matrix: &'static str,
        rows: usize,
        dofs: usize,
    },
    #[error("{label} is listed twice in the DOF map (rows {first} and {second})")]
    DuplicateDof {
        label: DofLabel,
        first: usize,
        second: usize,
    },
    #[error("{role} {label} is not in the DOF map (it has {dofs} DOFs{why})")]
    UnknownDof {
        role: &'static str,
        label: DofLabel,
        dofs: usize,
        why: &'static str,
    },
    #[error("the {matrix} matrix is not symmetric: a({row}, {col}) = {upper:e} but a({col}, {row}) = {lower:e} (row {row}: {row_label}, row {col}: {col_label}); the difference is {ratio:.1e} of sqrt(|a_ii a_jj|), above the {SYMMETRY_TOLERANCE:e} that 14-digit files and assembly round-off allow")]
    NotSymmetric {
        matrix: &'static str,
        row: usize,
        col: usize,
        upper: f64,
        lower: f64,
        row_label: DofLabel,
        col_label: DofLabel,
        ratio: f64,
    },
    #[error("the {matrix} matrix is not positive definite on the free DOFs: the Cholesky pivot at {label} (row {row} of the file) is {}, {reason}", Short(*pivot))]
    NotPositiveDefinite {
        matrix: &'static str,
        label: DofLabel,
        row: usize,
        pivot: f64,
        reason: &'static str,
    },
    #[error("the {matrix} matrix is not positive definite on the free DOFs: the sparse Cholesky's pivot at {label} (row {row} of the file) is not positive, {reason}")]
    NotPositiveDefiniteSparse {
        matrix: &'static str,
        label: DofLabel,
        row: usize,
        reason: &'static str,
    },
    #[error("the {matrix} matrix has an entry ({row}, {col}) outside its {size} rows")]
    EntryOutOfRange {
        matrix: &'static str,
        row: usize,
        col: usize,
        size: usize,
    },
    #[error("the structure's half-bandwidth after reverse Cuthill-McKee is {band} for {dofs} free DOFs: the band Cholesky would take about {gigabytes:.1} GB (limit {} GB); its full model does not run in the time loop; fidelity.level = modal reduces it from its sparse matrices (docs/structures.md, \"A 3D solid\")", BAND_MEMORY_LIMIT / 1e9)]
    BandTooWide {
        dofs: usize,
        band: usize,
        gigabytes: f64,
    },
    #[error("the damping matrix is not positive semi-definite on the free DOFs: c({row}, {col}) = {entry:e} (row {row}: {label}) where a semi-definite C has {} {bound:e}, so some motion there would gain energy from its damping", if row == col { "at least" } else { "|c_ij| <= sqrt(c_ii c_jj) =" })]
    DampingNotSemidefinite {
        row: usize,
        col: usize,
        label: DofLabel,
        entry: f64,
        bound: f64,
    },
    #[error("every DOF of the structure is clamped: nothing is left to move")]
    NothingFree,
    #[error("{0}")]
    Modes(ModelError),
}

/// A checked linear structure on its free DOFs, in the band order of reverse
/// Cuthill-McKee, with the factor of K.
#[derive(Clone, Debug)]
pub struct LinearStructure {
    /// The label of each free DOF, in solver order.
    labels: Vec<DofLabel>,
    /// Solver index of each label.
    index: HashMap<DofLabel, usize>,
    /// M (kg, kg m2), K (N/m, ...), C (N s/m, ...) on the free DOFs.
    mass: SymBandMatrix,
    stiffness: SymBandMatrix,
    damping: Option<SymBandMatrix>,
    factor: BandCholesky,
}

impl LinearStructure {
    /// Checks `matrices` and removes the DOFs `clamped` (each must be in the DOF map:
    /// files that already removed a fixed DOF, as CalculiX's do, must not name it again).
    pub fn new(matrices: &StructureMatrices, clamped: &[DofLabel]) -> Result<Self, StructureError> {
        let dofs = &matrices.dofs;
        let row_of = Self::row_of_labels(dofs)?;
        let mut free = vec![true; dofs.len()];
        for &label in clamped {
            let row = *row_of.get(&label).ok_or(StructureError::UnknownDof {
                role: "the clamped DOF",
                label,
                dofs: dofs.len(),
                why: "; CalculiX's files already leave out the DOFs *BOUNDARY fixes",
            })?;
            free[row] = false;
        }
        let upper = Self::checked_upper_triangles(matrices, &free)?;
        let band_order = BandOrder::new(&free, &upper)?;
        let kept = |&(i, j, _): &(usize, usize, f64)| free[i] && free[j];
        let assemble = |entries: &[(usize, usize, f64)]| {
            let mut m = SymBandMatrix::zeros(band_order.dofs(), band_order.band);
            for e in entries.iter().filter(|e| kept(e)) {
                m.add(band_order.solver_row[e.0], band_order.solver_row[e.1], e.2);
            }
            m
        };
        let stiffness = assemble(&upper[0]);
        let mass = assemble(&upper[1]);
        let damping = upper.get(2).map(|u| assemble(u));
        let labels: Vec<DofLabel> = band_order
            .order
            .iter()
            .map(|&k| dofs[band_order.file_rows[k]])
            .collect();
        let factor = Self::factor_definite("stiffness", &stiffness, &labels, &row_of)?;
        Self::factor_definite("mass", &mass, &labels, &row_of)?;
        let index = labels.iter().enumerate().map(|(k, &l)| (l, k)).collect();
        Ok(Self {
            labels,
            index,
            mass,
            stiffness,
            damping,
            factor,
        })
    }

    /// The file row (0-based) of each DOF label; a label twice is refused.
    fn row_of_labels(dofs: &[DofLabel]) -> Result<HashMap<DofLabel, usize>, StructureError> {
        let mut row_of: HashMap<DofLabel, usize> = HashMap::with_capacity(dofs.len());
        for (row, &label) in dofs.iter().enumerate() {
            if let Some(first) = row_of.insert(label, row) {
                return Err(StructureError::DuplicateDof {
                    label,
                    first: first + 1,
                    second: row + 1,
                });
            }
        }
        Ok(row_of)
    }

    /// The upper triangle of K, M and (if given) C in file rows, in that order, each
    /// checked for its size against the DOF map, entries inside it, and symmetry; C also
    /// for what positive semi-definiteness needs on the free DOFs (`free`, by file row):
    /// [`semidefinite_necessary`].
    fn checked_upper_triangles(
        matrices: &StructureMatrices,
        free: &[bool],
    ) -> Result<Vec<UpperTriangle>, StructureError> {
        let dofs = &matrices.dofs;
        let named = [
            ("stiffness", Some(&matrices.stiffness)),
            ("mass", Some(&matrices.mass)),
            ("damping", matrices.damping.as_ref()),
        ];
        let mut upper: Vec<UpperTriangle> = Vec::new();
        for (name, triplets) in named.iter().filter_map(|(n, t)| t.map(|t| (*n, t))) {
            if triplets.size != dofs.len() {
                return Err(StructureError::RowCount {
                    matrix: name,
                    rows: triplets.size,
                    dofs: dofs.len(),
                });
            }
            // The readers never give an entry outside the matrix; data built otherwise
            // might.
            if let Some(t) = triplets
                .entries
                .iter()
                .find(|t| t.row >= triplets.size || t.col >= triplets.size)
            {
                return Err(StructureError::EntryOutOfRange {
                    matrix: name,
                    row: t.row + 1,
                    col: t.col + 1,
                    size: triplets.size,
                });
            }
            upper.push(symmetric_upper(name, triplets, dofs)?);
        }
        if let Some(damping) = upper.get(2) {
            semidefinite_necessary(damping, free, dofs)?;
        }
        Ok(upper)
    }

    /// The Cholesky factor of `m` (the matrix `name`), or the DOF where it is not
    /// positive definite, by its label and file row.
    fn factor_definite(
        name: &'static str,
        m: &SymBandMatrix,
        labels: &[DofLabel],
        row_of: &HashMap<DofLabel, usize>,
    ) -> Result<BandCholesky, StructureError> {
        m.cholesky().map_err(|e| {
            let label = labels[e.row];
            StructureError::NotPositiveDefinite {
                matrix: name,
                label,
                row: row_of[&label] + 1,
                pivot: e.pivot,
                reason: not_definite_reason(name),
            }
        })
    }

    /// The number of free DOFs.
    pub fn dofs(&self) -> usize {
        self.labels.len()
    }

    /// The half-bandwidth after reordering.
    pub fn half_bandwidth(&self) -> usize {
        self.stiffness.half_bandwidth()
    }

    /// The free DOFs' labels, in the order of the vectors this structure returns.
    pub fn labels(&self) -> &[DofLabel] {
        &self.labels
    }

    /// The solver index of a free DOF, or an error naming it.
    pub fn index_of(&self, label: DofLabel) -> Result<usize, StructureError> {
        self.index
            .get(&label)
            .copied()
            .ok_or(StructureError::UnknownDof {
                role: "the loaded DOF",
                label,
                dofs: self.dofs(),
                why: " free ones; a clamped DOF takes no load",
            })
    }

    pub fn mass(&self) -> &SymBandMatrix {
        &self.mass
    }

    pub fn stiffness(&self) -> &SymBandMatrix {
        &self.stiffness
    }

    pub fn damping(&self) -> Option<&SymBandMatrix> {
        self.damping.as_ref()
    }

    /// The static displacement K u = f under the load f given as (label, force) pairs
    /// (N, or N m for rotations), in solver order (`labels`), with one step of iterative
    /// refinement as the beam's model does (K's condition number reaches 1e10 and more).
    pub fn static_displacement(
        &self,
        load: &[(DofLabel, f64)],
    ) -> Result<Vec<f64>, StructureError> {
        let mut f = vec![0.0; self.dofs()];
        for &(label, force) in load {
            f[self.index_of(label)?] += force;
        }
        let mut u = f.clone();
        self.factor.solve_in_place(&mut u);
        let mut residual = vec![0.0; self.dofs()];
        self.stiffness.mul_vec(&u, &mut residual);
        residual.iter_mut().zip(&f).for_each(|(r, fi)| *r = fi - *r);
        self.factor.solve_in_place(&mut residual);
        u.iter_mut().zip(&residual).for_each(|(a, d)| *a += d);
        Ok(u)
    }

    /// The value of a solver-order vector at `label`.
    pub fn value_at(&self, u: &[f64], label: DofLabel) -> Result<f64, StructureError> {
        Ok(u[self.index_of(label)?])
    }

    /// The lowest `count` modes by shift-invert Lanczos: omega^2 ascending (rad^2/s^2),
    /// M-normalised vectors in solver order.
    pub fn lowest_modes(&self, count: usize) -> Result<Modes, StructureError> {
        if count == 0 || count > self.dofs() {
            return Err(StructureError::Modes(ModelError::TooManyModes {
                asked: count,
                available: self.dofs(),
            }));
        }
        modal::lanczos(&self.mass, &self.factor, count).map_err(StructureError::Modes)
    }

    /// The lowest `count` natural frequencies f = omega / (2 pi) (Hz).
    pub fn natural_frequencies(&self, count: usize) -> Result<Vec<f64>, StructureError> {
        Ok(self
            .lowest_modes(count)?
            .eigenvalues
            .iter()
            .map(|w2| w2.sqrt() / (2.0 * std::f64::consts::PI))
            .collect())
    }
}

/// What a pivot that is not positive means in the matrix `name`.
fn not_definite_reason(name: &str) -> &'static str {
    if name == "stiffness" {
        "so the structure can move there without deforming (clamp a rigid-body motion or a mechanism at or near that DOF)"
    } else {
        "so some motion there has no mass"
    }
}

/// A matrix's upper triangle as (file row, file column, value) entries, i <= j.
type UpperTriangle = Vec<(usize, usize, f64)>;

/// Refuses a damping matrix C that cannot be positive semi-definite on the free DOFs
/// (a C that is not feeds energy into some motion): a negative diagonal entry, or an
/// entry larger than the geometric mean of its diagonals, |c_ij| > sqrt(c_ii c_jj), which
/// makes the 2 x 2 principal minor negative. Both are necessary conditions, so no
/// semi-definite C is refused (the pair's bound is widened by [`SYMMETRY_TOLERANCE`] for
/// the 14-digit printing of a dashpot's exact c_ij^2 = c_ii c_jj); an indefinite C that
/// meets both passes (a full check would need a factorisation that tolerates zero
/// pivots: not done).
fn semidefinite_necessary(
    upper: &UpperTriangle,
    free: &[bool],
    dofs: &[DofLabel],
) -> Result<(), StructureError> {
    let mut diagonal = vec![0.0; free.len()];
    for &(i, j, v) in upper {
        if i == j {
            diagonal[i] += v;
        }
    }
    if let Some(i) = (0..free.len()).find(|&i| free[i] && diagonal[i] < 0.0) {
        return Err(StructureError::DampingNotSemidefinite {
            row: i + 1,
            col: i + 1,
            label: dofs[i],
            entry: diagonal[i],
            bound: 0.0,
        });
    }
    for &(i, j, v) in upper {
        let bound = (diagonal[i] * diagonal[j]).sqrt() * (1.0 + SYMMETRY_TOLERANCE);
        if i != j && free[i] && free[j] && v.abs() > bound {
            return Err(StructureError::DampingNotSemidefinite {
                row: i + 1,
                col: j + 1,
                label: dofs[i],
                entry: v,
                bound,
            });
        }
    }
    Ok(())
}

/// The free DOFs' order for the band solver: reverse Cuthill-McKee on the graph of the
/// kept entries, with its half-bandwidth, refused if the band would not fit in memory.
struct BandOrder {
    /// File rows of the free DOFs, in file order.
    file_rows: Vec<usize>,
    /// For each band position, the index into `file_rows`.
    order: Vec<usize>,
    /// Half-bandwidth in that order.
    band: usize,
    /// Solver row of each file row (`usize::MAX` for a clamped one).
    solver_row: Vec<usize>,
}

impl BandOrder {
    fn new(free: &[bool], upper: &[UpperTriangle]) -> Result<Self, StructureError> {
        // Free DOFs in file order, then in band order.
        let file_rows: Vec<usize> = (0..free.len()).filter(|&r| free[r]).collect();
        if file_rows.is_empty() {
            return Err(StructureError::NothingFree);
        }
        let mut free_index = vec![usize::MAX; free.len()];
        for (k, &r) in file_rows.iter().enumerate() {
            free_index[r] = k;
        }
        let kept = |&(i, j, _): &(usize, usize, f64)| free[i] && free[j];
        let graph = ordering::Graph::new(
            file_rows.len(),
            upper
                .iter()
                .flatten()
                .filter(|e| kept(e))
                .map(|&(i, j, _)| (free_index[i], free_index[j])),
        );
        let order = ordering::reverse_cuthill_mckee(&graph);
        let mut position = vec![0; order.len()];
        for (new, &old) in order.iter().enumerate() {
            position[old] = new;
        }
        let band = ordering::half_bandwidth(&graph, &position);
        let bytes = BAND_COPIES * order.len() as f64 * (band + 1) as f64 * 8.0;
        if bytes > BAND_MEMORY_LIMIT {
            return Err(StructureError::BandTooWide {
                dofs: order.len(),
                band,
                gigabytes: bytes / 1e9,
            });
        }
        let solver_row: Vec<usize> = free_index
            .iter()
            .map(|&k| if k == usize::MAX { k } else { position[k] })
            .collect();
        Ok(Self {
            file_rows,
            order,
            band,
            solver_row,
        })
    }

    /// The number of free DOFs.
    fn dofs(&self) -> usize {
        self.order.len()
    }
}

/// The upper triangle (i <= j) of a matrix, checked symmetric when the file gave every
/// entry: the mean of a_ij and a_ji when they agree within [`SYMMETRY_TOLERANCE`], else the
/// worst pair refused.
fn symmetric_upper(
    name: &'static str,
    triplets: &Triplets,
    dofs: &[DofLabel],
) -> Result<Vec<(usize, usize, f64)>, StructureError> {
    let entries = triplets.entries.iter().map(|t| (t.row, t.col, t.value));
    if triplets.stored == Stored::Upper {
        return Ok(entries.collect());
    }
    let mut diagonal = vec![0.0; triplets.size];
    let mut lower: HashMap<(usize, usize), f64> = HashMap::new();
    for (i, j, v) in entries.clone() {
        if i == j {
            diagonal[i] = v;
        } else if i > j {
            lower.insert((j, i), v);
        }
    }
    let mut upper = Vec::with_capacity(triplets.entries.len() / 2 + triplets.size);
    // (ratio, row, col, a_ij, a_ji) of the worst pair.
    let mut worst = (0.0, 0, 0, 0.0, 0.0);
    let mut pair = |i: usize, j: usize, a: f64, b: f64| {
        let scale = (diagonal[i] * diagonal[j])
            .abs()
            .sqrt()
            .max(a.abs())
            .max(b.abs());
        let ratio = if scale > 0.0 {
            (a - b).abs() / scale
        } else {
            0.0
        };
        if ratio > worst.0 {
            worst = (ratio, i, j, a, b);
        }
    };
    for (i, j, v) in entries {
        if i < j {
            let w = lower.remove(&(i, j)).unwrap_or(0.0);
            pair(i, j, v, w);
            upper.push((i, j, 0.5 * (v + w)));
        } else if i == j {
            upper.push((i, j, v));
        }
    }
    // Lower entries with no upper partner.
    for (&(i, j), &w) in &lower {
        pair(i, j, 0.0, w);
        upper.push((i, j, 0.5 * w));
    }
    let (ratio, i, j, a, b) = worst;
    if ratio > SYMMETRY_TOLERANCE {
        return Err(StructureError::NotSymmetric {
            matrix: name,
            row: i + 1,
            col: j + 1,
            upper: a,
            lower: b,
            row_label: dofs[i],
            col_label: dofs[j],
            ratio,
        });
    }
    Ok(upper)
}

#[cfg(test)]
mod tests {
    use super::*;
    use stickslip_formats::structure_file::Triplet;

    fn label(node: u64, direction: u8) -> DofLabel {
        DofLabel { node, direction }
    }

    /// A chain of `n` equal springs k and masses m along x, node 0 (the wall) to node n,
    /// with the rows in a scrambled file order (so that the band comes from the ordering,
    /// not the file). Node 0 is in the file and must be clamped.
    pub(super) fn chain(n: usize, k: f64, m: f64) -> StructureMatrices {
        let rows = n + 1;
        let file_row = |node: usize| (node * 7) % rows; // a permutation when 7 does not divide rows
        let mut dofs = vec![label(0, 1); rows];
        for node in 0..rows {
            dofs[file_row(node)] = label(node as u64 + 1, 1);
        }
        let mut stiffness = Vec::new();
        let mut mass = Vec::new();
        let upper = |a: usize, b: usize, value: f64| {
            let (i, j) = (file_row(a).min(file_row(b)), file_row(a).max(file_row(b)));
            Triplet {
                row: i,
                col: j,
                value,
            }
        };
        for node in 0..rows {
            let springs = if node == 0 || node == n { 1.0 } else { 2.0 };
            stiffness.push(upper(node, node, springs * k));
            mass.push(upper(node, node, m));
            if node < n {
                stiffness.push(upper(node, node + 1, -k));
            }
        }
        let triplets = |entries| Triplets {
            size: rows,
            stored: Stored::Upper,
            entries,
        };
        StructureMatrices {
            stiffness: triplets(stiffness),
            mass: triplets(mass),
            damping: None,
            dofs,
        }
    }

    #[test]
    fn a_spring_chain_has_its_closed_form_statics_and_frequencies() {
        let (n, k, m) = (30, 1.0e6, 2.0);
        let s = LinearStructure::new(&chain(n, k, m), &[label(1, 1)]).unwrap();
        assert_eq!(s.dofs(), n);
        // A chain renumbered by reverse Cuthill-McKee is tridiagonal again.
        assert_eq!(s.half_bandwidth(), 1);
        // n springs in series under a unit end force: u = n / k. Round-off only.
        let end = label(n as u64 + 1, 1);
        let u = s.static_displacement(&[(end, 1.0)]).unwrap();
        let expected = n as f64 / k;
        assert!((s.value_at(&u, end).unwrap() - expected).abs() < 1e-13 * expected);
        // Fixed-free chain: omega_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2n + 1))).
        let f = s.natural_frequencies(3).unwrap();
        for (j, fj) in f.iter().enumerate() {
            let angle = (2 * j + 1) as f64 * std::f64::consts::PI / (2.0 * (2 * n + 1) as f64);
            let exact =
                2.0 * (k / m).sqrt() * crate::elementary::sin(angle) / (2.0 * std::f64::consts::PI);
            // Lanczos stops at 1e-10 relative residual, ~1e-20 on the eigenvalue.
            assert!(
                (fj - exact).abs() < 1e-10 * exact,
                "mode {j}: {fj} vs {exact}"
            );
        }
    }

    #[test]
    fn damping_is_carried_in_the_same_order_and_checked_like_the_others() {
        let mut matrices = chain(5, 1.0e6, 2.0);
        let mut damping = matrices.stiffness.clone();
        damping.entries.iter_mut().for_each(|e| e.value *= 1e-3);
        matrices.damping = Some(damping);
        let s = LinearStructure::new(&matrices, &[label(1, 1)]).unwrap();
        let c = s.damping().unwrap();
        for i in 0..s.dofs() {
            for j in 0..s.dofs() {
                // Stiffness-proportional C = 1e-3 K, entry by entry in the band order.
                assert_eq!(c.get(i, j), 1e-3 * s.stiffness().get(i, j), "({i}, {j})");
            }
        }
        // A `general` C whose (1, 3) and (3, 1) differ by 1e-6 of the entry: refused with
        // the pair, as K would be (the same check).
        let mut skewed = matrices.damping.clone().unwrap();
        skewed.stored = Stored::General;
        let lower: Vec<Triplet> = skewed
            .entries
            .iter()
            .filter(|e| e.row != e.col)
            .map(|e| Triplet {
                row: e.col,
                col: e.row,
                value: e.value * (1.0 + 1e-6),
            })
            .collect();
        skewed.entries.extend(lower);
        let mut unsymmetric = matrices.clone();
        unsymmetric.damping = Some(skewed);
        let message = LinearStructure::new(&unsymmetric, &[label(1, 1)])
            .unwrap_err()
            .to_string();
        assert!(
            message.starts_with("the damping matrix is not symmetric: a(")
                && message.contains("-1e3 but a(")
                && message.contains("-1.000000999"),
            "{message}"
        );
        // C = -1e-3 K has negative diagonals; C with a 2 x 2 block [[1, 2], [2, 1]] (c_24
        // against sqrt(1 * 1), file rows 2 and 4; row 1 is the clamped node) has positive ones and a negative minor.
        let mut negative = matrices.clone();
        if let Some(c) = &mut negative.damping {
            c.entries.iter_mut().for_each(|e| e.value = -e.value);
        }
        let message = LinearStructure::new(&negative, &[label(1, 1)])
            .unwrap_err()
            .to_string();
        assert!(
            message.starts_with(
                "the damping matrix is not positive semi-definite on the free DOFs: c("
            ) && message.contains("= -2e3 (row")
                && message.contains("has at least 0e0"),
            "{message}"
        );
        let mut minor = matrices.clone();
        let c = minor.damping.as_mut().unwrap();
        c.entries = (0..c.size)
            .map(|i| Triplet {
                row: i,
                col: i,
                value: 1.0,
            })
            .chain([Triplet {
                row: 1,
                col: 3,
                value: 2.0,
            }])
            .collect();
        assert_eq!(
            LinearStructure::new(&minor, &[label(1, 1)]).unwrap_err().to_string(),
            format!("the damping matrix is not positive semi-definite on the free DOFs: c(2, 4) = 2e0 (row 2: {}) where a semi-definite C has |c_ij| <= sqrt(c_ii c_jj) = 1.000000000001e0, so some motion there would gain energy from its damping", minor.dofs[1])
        );
        // The same pair at 1 (a dashpot between the two DOFs, c_24^2 = c_22 c_44) passes.
        minor
            .damping
            .as_mut()
            .unwrap()
            .entries
            .last_mut()
            .unwrap()
            .value = -1.0;
        assert!(LinearStructure::new(&minor, &[label(1, 1)]).is_ok());
        let mut short = matrices.damping.clone().unwrap();
        short.size = 3;
        matrices.damping = Some(short);
        assert_eq!(
            LinearStructure::new(&matrices, &[label(1, 1)])
                .unwrap_err()
                .to_string(),
            "the damping matrix has 3 rows but the DOF map lists 6 DOFs"
        );
    }

    #[test]
    fn a_general_file_is_accepted_only_symmetric() {
        let mut matrices = chain(4, 1.0e6, 2.0);
        let general = |t: &Triplets, skew: f64| {
            let mut entries = t.entries.clone();
            for e in &t.entries {
                if e.row != e.col {
                    entries.push(Triplet {
                        row: e.col,
                        col: e.row,
                        value: e.value * (1.0 + skew),
                    });
                }
            }
            Triplets {
                size: t.size,
                stored: Stored::General,
                entries,
            }
        };
        let reference = LinearStructure::new(&matrices, &[label(1, 1)])
            .unwrap()
            .natural_frequencies(2)
            .unwrap();
        // Round-off of 14-digit printing (1e-14 of the entry) passes.
        matrices.stiffness = general(&chain(4, 1.0e6, 2.0).stiffness, 1e-14);
        let s = LinearStructure::new(&matrices, &[label(1, 1)]).unwrap();
        let f = s.natural_frequencies(2).unwrap();
        for (a, b) in f.iter().zip(&reference) {
            assert!((a - b).abs() < 1e-12 * b);
        }
        // 1e-6 of an off-diagonal entry -1e6; the worst pair is at the free end, between
        // diagonals 2e6 and 1e6: 1 / sqrt(2) 1e-6 of the scale.
        matrices.stiffness = general(&chain(4, 1.0e6, 2.0).stiffness, 1e-6);
        let e = LinearStructure::new(&matrices, &[label(1, 1)]).unwrap_err();
        match &e {
            StructureError::NotSymmetric {
                ratio,
                upper,
                lower,
                ..
            } => {
                assert!((ratio - 1e-6 / 2f64.sqrt()).abs() < 1e-12, "{ratio}");
                assert_eq!(*upper, -1.0e6);
                assert_eq!(*lower, -1.0e6 * (1.0 + 1e-6));
            }
            other => panic!("{other}"),
        }
        assert_eq!(e.to_string(), "the stiffness matrix is not symmetric: a(1, 3) = -1e6 but a(3, 1) = -1.0000009999999999e6 (row 1: node 1 direction 1, row 3: node 2 direction 1); the difference is 7.1e-7 of sqrt(|a_ii a_jj|), above the 1e-12 that 14-digit files and assembly round-off allow");
    }

    #[test]
    fn an_unclamped_structure_is_refused_with_the_pivot_and_the_dof() {
        let e = LinearStructure::new(&chain(4, 1.0e6, 2.0), &[]).unwrap_err();
        match &e {
            StructureError::NotPositiveDefinite {
                matrix,
                pivot,
                label,
                row,
                ..
            } => {
                assert_eq!(*matrix, "stiffness");
                // The last pivot of a free chain is round-off of k's sums: zero in exact
                // arithmetic, at most a few ulps of k here.
                assert!(pivot.abs() < 1e-9 * 1.0e6, "{pivot}");
                assert_eq!(chain(4, 1.0e6, 2.0).dofs[*row - 1], *label);
            }
            other => panic!("{other}"),
        }
        // docs/structures.md's bad-file table.
        assert_eq!(e.to_string(), "the stiffness matrix is not positive definite on the free DOFs: the Cholesky pivot at node 1 direction 1 (row 1 of the file) is 0e0, so the structure can move there without deforming (clamp a rigid-body motion or a mechanism at or near that DOF)");
        let mut massless = chain(4, 1.0e6, 2.0);
        massless.mass.entries[2].value = 0.0;
        assert_eq!(
            LinearStructure::new(&massless, &[label(1, 1)]).unwrap_err().to_string(),
            "the mass matrix is not positive definite on the free DOFs: the Cholesky pivot at node 3 direction 1 (row 5 of the file) is 0e0, so some motion there has no mass"
        );
    }

    #[test]
    fn a_structure_too_wide_for_the_band_is_refused_before_allocating() {
        // A star: DOF 0 coupled to all others. Cuthill-McKee starts at a leaf, the hub
        // comes second and every other leaf after it, so the reversed order has the hub
        // next to last and a band of n - 2: 10,000 x 9,999 x 8 copies x 8 bytes = 6.4 GB.
        let n = 10_000;
        let mut k = vec![Triplet {
            row: 0,
            col: 0,
            value: n as f64,
        }];
        let mut m = Vec::new();
        for i in 0..n {
            if i > 0 {
                k.push(Triplet {
                    row: 0,
                    col: i,
                    value: -1.0,
                });
                k.push(Triplet {
                    row: i,
                    col: i,
                    value: 2.0,
                });
            }
            m.push(Triplet {
                row: i,
                col: i,
                value: 1.0,
            });
        }
        let triplets = |entries| Triplets {
            size: n,
            stored: Stored::Upper,
            entries,
        };
        let matrices = StructureMatrices {
            stiffness: triplets(k),
            mass: triplets(m),
            damping: None,
            dofs: (1..=n as u64).map(|node| label(node, 1)).collect(),
        };
        match LinearStructure::new(&matrices, &[]).unwrap_err() {
            StructureError::BandTooWide {
                dofs,
                band,
                gigabytes,
            } => {
                assert_eq!(dofs, n);
                assert_eq!(band, n - 2);
                assert!((gigabytes - 6.4).abs() < 0.01, "{gigabytes}");
            }
            other => panic!("{other}"),
        }
    }

    #[test]
    fn the_dof_map_must_match() {
        let matrices = chain(4, 1.0e6, 2.0);
        let e = LinearStructure::new(&matrices, &[label(9, 1)]).unwrap_err();
        assert_eq!(e.to_string(), "the clamped DOF node 9 direction 1 is not in the DOF map (it has 5 DOFs; CalculiX's files already leave out the DOFs *BOUNDARY fixes)");
        let mut short = matrices.clone();
        short.dofs.pop();
        assert_eq!(
            LinearStructure::new(&short, &[]).unwrap_err().to_string(),
            "the stiffness matrix has 5 rows but the DOF map lists 4 DOFs"
        );
        let mut twice = matrices.clone();
        twice.dofs[3] = twice.dofs[1];
        assert!(matches!(
            LinearStructure::new(&twice, &[]),
            Err(StructureError::DuplicateDof {
                first: 2,
                second: 4,
                ..
            })
        ));
        let mut outside = matrices.clone();
        outside.mass.entries[0].col = 5;
        assert_eq!(
            LinearStructure::new(&outside, &[]).unwrap_err().to_string(),
            "the mass matrix has an entry (1, 6) outside its 5 rows"
        );
        let all: Vec<DofLabel> = matrices.dofs.clone();
        assert_eq!(
            LinearStructure::new(&matrices, &all).unwrap_err(),
            StructureError::NothingFree
        );
        let s = LinearStructure::new(&matrices, &[label(1, 1)]).unwrap();
        assert!(matches!(
            s.static_displacement(&[(label(1, 1), 1.0)]),
            Err(StructureError::UnknownDof { .. })
        ));
    }
}
