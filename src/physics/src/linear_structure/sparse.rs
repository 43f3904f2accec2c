//! A linear structure too wide for the band: its M and K stored sparse (the upper
//! triangle by columns) and K factorised by faer's sparse Cholesky, supernodal where the
//! structure is dense enough (a 3D solid), after faer's approximate minimum degree
//! ordering (docs/structures.md, "Factorisation": on a 1 m x 0.1 m x 0.1 m C3D8 block of
//! 9,720 DOFs the band Cholesky after reverse Cuthill-McKee takes 2.1 s, this one 0.17 s;
//! at 40,560 DOFs the band would need 3.7 GB, this one 0.44 GB).
//!
//! The checks are [`LinearStructure`]'s (the same code: one row per label, symmetric
//! within [`super::SYMMETRY_TOLERANCE`]; K and M positive definite on the free DOFs, M
//! checked block by block by [`mass_definite`]), and a
//! failing pivot is reported with the DOF where it fails, mapped back through faer's
//! ordering; faer does not return the pivot's value, so the message gives its sign only.
//!
//! # Bits
//! faer is built without its default features (the workspace's Cargo.toml): without `std`,
//! pulp, gemm and nano-gemm pick their SIMD kernels by the compile-time target features
//! (x86_64's baseline: none of AVX2 or FMA) instead of by the CPU at run time, and their
//! fused multiply-adds go through `libm::fma`, which rounds once on every CPU. So one
//! binary gives the same bits on every x86_64 CPU (measured under qemu's Nehalem, which
//! has no AVX: docs/structures.md, "A 3D solid"). The products with M and K are this
//! module's own loops, in a fixed order. The band stays the solver for every structure
//! it can hold ([`LinearStructure`]); this one takes those it refuses.

use super::{LinearStructure, StructureError, UpperTriangle};
use crate::modal::{self, Modes, StiffnessSolve, SymmetricOperator};
use crate::structure::ModelError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use std::collections::HashMap;
use std::sync::Arc;
use stickslip_formats::structure_file::{DofLabel, StructureMatrices};

/// A symmetric matrix stored as its upper triangle (row <= column) by columns, rows
/// ascending in each column, duplicates summed.
#[derive(Clone, Debug)]
pub struct SymSparseMatrix {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
}

impl SymSparseMatrix {
    /// The matrix of size `n` on the pattern `pattern` (from [`Pattern`]) with the entries
    /// `entries` (row, column, value), each (i, j) with i <= j and in the pattern.
    fn assemble(pattern: &Pattern, entries: impl Iterator<Item = (usize, usize, f64)>) -> Self {
        let mut values = vec![0.0; pattern.row_idx.len()];
        for (i, j, v) in entries {
            values[pattern.position(i, j)] += v;
        }
        Self {
            n: pattern.n,
            col_ptr: pattern.col_ptr.clone(),
            row_idx: pattern.row_idx.clone(),
            values,
        }
    }

    /// The stored entries (the upper triangle with the diagonal).
    pub fn nonzeros(&self) -> usize {
        self.values.len()
    }

    /// a_ij (either triangle).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = (i.min(j), i.max(j));
        let rows = &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]];
        rows.binary_search(&i)
            .map(|k| self.values[self.col_ptr[j] + k])
            .unwrap_or(0.0)
    }

    /// The diagonal.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n).map(|j| self.get(j, j)).collect()
    }

    /// y = A x from the upper triangle: column j adds a_ij x_j to y_i and, off the
    /// diagonal, a_ij x_i to y_j; one fixed order, so the same bits everywhere.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|e| *e = 0.0);
        for j in 0..self.n {
            let mut column = 0.0;
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[k];
                let a = self.values[k];
                if i == j {
                    column += a * x[j];
                } else {
                    y[i] += a * x[j];
                    column += a * x[i];
                }
            }
            y[j] += column;
        }
    }

    fn as_faer(&self) -> SparseColMatRef<'_, usize, f64> {
        let symbolic = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        SparseColMatRef::new(symbolic, &self.values)
    }
}

impl SymmetricOperator for SymSparseMatrix {
    fn size(&self) -> usize {
        self.n
    }

    fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        SymSparseMatrix::mul_vec(self, x, y);
    }
}

/// The union of the upper-triangle patterns of the matrices, by columns.
struct Pattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl Pattern {
    /// The pattern of the (row, column) pairs `entries` (i <= j) and the diagonal, which
    /// the factorisation needs even where a file has no entry.
    fn new(n: usize, entries: impl Iterator<Item = (usize, usize)>) -> Self {
        let mut columns: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
        for (i, j) in entries {
            columns[j].push(i);
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for mut rows in columns {
            rows.sort_unstable();
            rows.dedup();
            row_idx.extend(rows);
            col_ptr.push(row_idx.len());
        }
        Self {
            n,
            col_ptr,
            row_idx,
        }
    }

    fn position(&self, i: usize, j: usize) -> usize {
        let start = self.col_ptr[j];
        start
            + self.row_idx[start..self.col_ptr[j + 1]]
                .binary_search(&i)
                .expect("the entry is in the pattern it was built from")
    }
}

/// faer's sparse Cholesky factor of a [`SymSparseMatrix`], solved sequentially.
#[derive(Debug)]
pub struct SparseCholesky {
    symbolic: Arc<SymbolicCholesky<usize>>,
    values: Vec<f64>,
}

/// Where faer's sparse Cholesky met a pivot that is not positive: the column in the
/// matrix's own numbering (before faer's ordering).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FailedColumn(pub usize);

impl SparseCholesky {
    /// The symbolic analysis of a pattern (faer's AMD ordering, its supernodal choice).
    fn analyse(pattern: &SymSparseMatrix) -> Result<Arc<SymbolicCholesky<usize>>, ModelError> {
        factorize_symbolic_cholesky(
            pattern.as_faer().symbolic(),
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map(Arc::new)
        .map_err(|e| ModelError::UserStructure(format!("faer's symbolic Cholesky: {e:?}")))
    }

    /// The numeric factor of `a` on the analysis `symbolic` of its pattern, or the column
    /// (in `a`'s numbering) whose pivot is not positive.
    fn factor(
        symbolic: Arc<SymbolicCholesky<usize>>,
        a: &SymSparseMatrix,
    ) -> Result<Self, FailedColumn> {
        let mut values = vec![0.0; symbolic.len_val()];
        let scratch = symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let mut buffer = MemBuffer::new(scratch);
        let result = symbolic.factorize_numeric_llt(
            &mut values,
            a.as_faer(),
            Side::Upper,
            Default::default(),
            Par::Seq,
            MemStack::new(&mut buffer),
            Default::default(),
        );
        if let Err(LltError::NonPositivePivot { index }) = result {
            // faer 0.22 counts the failing pivot from 1 in its simplicial kernel and
            // from 0 in its supernodal one (sparse/linalg/cholesky.rs); either is a
            // position in its fill-reducing order, which `perm` maps back.
            let position = match symbolic.raw() {
                SymbolicCholeskyRaw::Simplicial(_) => index - 1,
                SymbolicCholeskyRaw::Supernodal(_) => index,
            };
            let column = match symbolic.perm() {
                Some(p) => p.arrays().0[position],
                None => position,
            };
            return Err(FailedColumn(column));
        }
        Ok(Self { symbolic, values })
    }

    /// The entries of the factor L (with its supernodes' padding).
    pub fn stored_values(&self) -> usize {
        self.values.len()
    }

    /// Whether faer chose its supernodal kernel (3D solids) over its simplicial one.
    pub fn is_supernodal(&self) -> bool {
        matches!(self.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_))
    }
}

impl StiffnessSolve for SparseCholesky {
    fn solve_in_place(&self, x: &mut [f64]) {
        SparseCholesky::solve_in_place(self, x);
    }
}

impl SparseCholesky {
    /// x <- A^-1 x, sequentially (`Par::Seq`).
    pub fn solve_in_place(&self, x: &mut [f64]) {
        let n = x.len();
        let scratch = self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq);
        let mut buffer = MemBuffer::new(scratch);
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(x, n, 1),
            Par::Seq,
            MemStack::new(&mut buffer),
        );
    }
}

/// Whether the symmetric matrix `m` is positive definite, checked exactly and cheaply: by
/// the connected components of the graph of its nonzero entries, each a diagonal block of
/// `m` up to a permutation, so that `m` is positive definite exactly when each block is.
/// A block of one DOF (a lumped mass) is checked by its sign, a larger one by faer's
/// sparse Cholesky on its own pattern. Err: `refuse` of the column (in `m`'s numbering)
/// of a pivot that is not positive, in the first failing block (blocks in the order of
/// their first DOF).
///
///
/// Why: a consistent mass matrix of a 3D solid couples only DOFs of one direction
/// (ccx's C3D8 `.mas` has the stiffness' pattern, the cross-direction entries explicit
/// zeros), so it is three blocks of a third of the DOFs, each with a ninth of K's
/// entries: their factorisations cost about a ninth of K's where M factorised on K's
/// pattern cost as much as K (docs/structures.md, "The 50,000-DOF claim": 14 of the
/// 28 s at 50,700 DOFs).
fn mass_definite(
    m: &SymSparseMatrix,
    refuse: impl Fn(FailedColumn) -> StructureError,
) -> Result<(), StructureError> {
    let n = m.n;
    // Union-find over the nonzero off-diagonal entries.
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for j in 0..n {
        for k in m.col_ptr[j]..m.col_ptr[j + 1] {
            let i = m.row_idx[k];
            if i != j && m.values[k] != 0.0 {
                let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                // The smaller index is the root: a component is named by its first DOF.
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); n];
    for j in 0..n {
        let r = root(&mut parent, j);
        members[r].push(j);
    }
    // Each DOF's index in its block (DOFs ascending within a block, so a block's upper
    // triangle stays upper).
    let mut local = vec![0; n];
    for block in &members {
        for (k, &j) in block.iter().enumerate() {
            local[j] = k;
        }
    }
    for block in members.iter().filter(|b| !b.is_empty()) {
        if let [j] = block[..] {
            // NaN is refused too (data not from a reader may hold one).
            let diagonal = m.get(j, j);
            if diagonal <= 0.0 || diagonal.is_nan() {
                return Err(refuse(FailedColumn(j)));
            }
            continue;
        }
        let local = &local;
        let entries = block.iter().flat_map(|&j| {
            let rows = m.col_ptr[j]..m.col_ptr[j + 1];
            rows.filter(|&k| m.values[k] != 0.0)
                .map(move |k| (local[m.row_idx[k]], local[j], m.values[k]))
        });
        let entries: Vec<(usize, usize, f64)> = entries.collect();
        let pattern = Pattern::new(block.len(), entries.iter().map(|&(i, j, _)| (i, j)));
        let sub = SymSparseMatrix::assemble(&pattern, entries.into_iter());
        let symbolic = SparseCholesky::analyse(&sub).map_err(StructureError::Modes)?;
        SparseCholesky::factor(symbolic, &sub)
            .map_err(|FailedColumn(k)| refuse(FailedColumn(block[k])))?;
    }
    Ok(())
}

/// A checked linear structure on its free DOFs in file order, stored sparse, with the
/// sparse factor of K: [`LinearStructure`]'s counterpart for structures too wide for the
/// band.
#[derive(Debug)]
pub struct SparseStructure {
    /// The label of each free DOF, in solver order (the file's).
    labels: Vec<DofLabel>,
    index: HashMap<DofLabel, usize>,
    /// M (kg, kg m2), K (N/m, ...), C (N s/m, ...) on the free DOFs.
    mass: SymSparseMatrix,
    stiffness: SymSparseMatrix,
    damping: Option<SymSparseMatrix>,
    factor: SparseCholesky,
}

impl SparseStructure {
    /// Checks `matrices` as [`LinearStructure::new`] does and removes the DOFs `clamped`
    /// (each must be in the DOF map).
    pub fn new(matrices: &StructureMatrices, clamped: &[DofLabel]) -> Result<Self, StructureError> {
        let dofs = &matrices.dofs;
        let row_of = LinearStructure::row_of_labels(dofs)?;
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
        let upper = LinearStructure::checked_upper_triangles(matrices, &free)?;
        let file_rows: Vec<usize> = (0..dofs.len()).filter(|&r| free[r]).collect();
        if file_rows.is_empty() {
            return Err(StructureError::NothingFree);
        }
        let mut solver_row = vec![usize::MAX; dofs.len()];
        for (k, &r) in file_rows.iter().enumerate() {
            solver_row[r] = k;
        }
        let kept = |u: &UpperTriangle| -> Vec<(usize, usize, f64)> {
            u.iter()
                .filter(|&&(i, j, _)| free[i] && free[j])
                .map(|&(i, j, v)| {
                    let (a, b) = (solver_row[i], solver_row[j]);
                    (a.min(b), a.max(b), v)
                })
                .collect()
        };
        let (k_entries, m_entries) = (kept(&upper[0]), kept(&upper[1]));
        let n = file_rows.len();
        // K and M on one pattern: one symbolic analysis factorises both.
        let pattern = Pattern::new(
            n,
            k_entries.iter().chain(&m_entries).map(|&(i, j, _)| (i, j)),
        );
        let stiffness = SymSparseMatrix::assemble(&pattern, k_entries.into_iter());
        let mass = SymSparseMatrix::assemble(&pattern, m_entries.into_iter());
        let damping = upper.get(2).map(|u| {
            let c = kept(u);
            let own = Pattern::new(n, c.iter().map(|&(i, j, _)| (i, j)));
            SymSparseMatrix::assemble(&own, c.into_iter())
        });
        drop(pattern);
        let labels: Vec<DofLabel> = file_rows.iter().map(|&r| dofs[r]).collect();
        let symbolic = SparseCholesky::analyse(&stiffness).map_err(StructureError::Modes)?;
        let refused = |name: &'static str| {
            let labels = &labels;
            let row_of = &row_of;
            move |FailedColumn(k): FailedColumn| {
                let label = labels[k];
                StructureError::NotPositiveDefiniteSparse {
                    matrix: name,
                    label,
                    row: row_of[&label] + 1,
                    reason: super::not_definite_reason(name),
                }
            }
        };
        mass_definite(&mass, refused("mass"))?;
        let factor = SparseCholesky::factor(symbolic, &stiffness).map_err(refused("stiffness"))?;
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

    /// The number of free DOFs.
    pub fn dofs(&self) -> usize {
        self.labels.len()
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

    pub fn mass(&self) -> &SymSparseMatrix {
        &self.mass
    }

    pub fn stiffness(&self) -> &SymSparseMatrix {
        &self.stiffness
    }

    pub fn damping(&self) -> Option<&SymSparseMatrix> {
        self.damping.as_ref()
    }

    pub fn factor(&self) -> &SparseCholesky {
        &self.factor
    }

    /// The static displacement K u = f under the load f given as (label, force) pairs
    /// (N, or N m for rotations), in solver order, with one step of iterative refinement
    /// as [`LinearStructure::static_displacement`] does.
    pub fn static_displacement(
        &self,
        load: &[(DofLabel, f64)],
    ) -> Result<Vec<f64>, StructureError> {
        let mut f = vec![0.0; self.dofs()];
        for &(label, force) in load {
            f[self.index_of(label)?] += force;
        }
        Ok(self.refined_solve(&f))
    }

    /// u = K^-1 f with one step of iterative refinement: u += K^-1 (f - K u).
    pub(crate) fn refined_solve(&self, f: &[f64]) -> Vec<f64> {
        let mut u = f.to_vec();
        self.factor.solve_in_place(&mut u);
        let mut residual = vec![0.0; self.dofs()];
        self.stiffness.mul_vec(&u, &mut residual);
        residual.iter_mut().zip(f).for_each(|(r, fi)| *r = fi - *r);
        self.factor.solve_in_place(&mut residual);
        u.iter_mut().zip(&residual).for_each(|(a, d)| *a += d);
        u
    }

    /// The value of a solver-order vector at `label`.
    pub fn value_at(&self, u: &[f64], label: DofLabel) -> Result<f64, StructureError> {
        Ok(u[self.index_of(label)?])
    }

    /// The lowest `count` modes by shift-invert Lanczos on the sparse factor
    /// (`modal::lanczos`, the band structure's solver): omega^2 ascending (rad^2/s^2),
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

    /// [`Self::lowest_modes`] at each of `counts`, from one Lanczos recurrence
    /// (`modal::lanczos_counts`): each the same bits as `lowest_modes` of its count.
    pub fn lowest_modes_at(&self, counts: &[usize]) -> Result<Vec<Modes>, StructureError> {
        if let Some(&count) = counts.iter().find(|&&c| c == 0 || c > self.dofs()) {
            return Err(StructureError::Modes(ModelError::TooManyModes {
                asked: count,
                available: self.dofs(),
            }));
        }
        modal::lanczos_counts(&self.mass, &self.factor, counts)
            .into_iter()
            .collect::<Result<Vec<_>, _>>()
            .map_err(StructureError::Modes)
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

#[cfg(test)]
mod tests {
    use super::super::tests::chain;
    use super::*;
    use stickslip_formats::structure_file::Triplet;

    fn label(node: u64, direction: u8) -> DofLabel {
        DofLabel { node, direction }
    }

    #[test]
    fn a_spring_chain_has_the_band_structures_answers() {
        let (n, k, m) = (30, 1.0e6, 2.0);
        let matrices = chain(n, k, m);
        let sparse = SparseStructure::new(&matrices, &[label(1, 1)]).unwrap();
        let band = LinearStructure::new(&matrices, &[label(1, 1)]).unwrap();
        // A chain is too sparse for faer's supernodes: the simplicial kernel, whose
        // failing pivot is counted differently (`SparseCholesky::factor`).
        assert!(!sparse.factor().is_supernodal());
        let end = label(n as u64 + 1, 1);
        let u = sparse.static_displacement(&[(end, 1.0)]).unwrap();
        // n springs in series: u = n / k, round-off only.
        let expected = n as f64 / k;
        assert!((sparse.value_at(&u, end).unwrap() - expected).abs() < 1e-13 * expected);
        let (fs, fb) = (
            sparse.natural_frequencies(3).unwrap(),
            band.natural_frequencies(3).unwrap(),
        );
        for (a, b) in fs.iter().zip(&fb) {
            // Both Lanczos runs stop at 1e-10 on the Ritz residual.
            assert!((a - b).abs() < 1e-10 * b, "{a} vs {b}");
        }
        // The product with the upper triangle is the full symmetric one.
        let x: Vec<f64> = (0..n).map(|i| i as f64 - 7.5).collect();
        let mut y = vec![0.0; n];
        sparse.stiffness().mul_vec(&x, &mut y);
        for (i, yi) in y.iter().enumerate() {
            let row: f64 = (0..n).map(|j| sparse.stiffness().get(i, j) * x[j]).sum();
            assert_eq!(*yi, row, "row {i}");
        }
    }

    #[test]
    fn an_indefinite_mass_is_refused_by_its_block() {
        // Every diagonal positive, but nodes 3 and 4 (file rows 5 and 2) coupled by 3 kg
        // between masses of 2 kg: the 2 x 2 block [[2, 3], [3, 2]] has the eigenvalue -1
        // (its second pivot is 2 - 9/2 < 0), which no diagonal check sees.
        let mut matrices = chain(4, 1.0e6, 2.0);
        let (a, b) = (5 - 1, 2 - 1);
        assert_eq!(
            (matrices.dofs[a], matrices.dofs[b]),
            (label(3, 1), label(4, 1))
        );
        matrices.mass.entries.push(Triplet {
            row: b,
            col: a,
            value: 3.0,
        });
        match SparseStructure::new(&matrices, &[label(1, 1)]).unwrap_err() {
            StructureError::NotPositiveDefiniteSparse { matrix, label, .. } => {
                assert_eq!(matrix, "mass");
                assert!(label.node == 3 || label.node == 4, "{label}");
            }
            other => panic!("{other}"),
        }
        // At 1.9 kg the block is positive definite (4 - 3.61 > 0): accepted, and the
        // coupling is in the mass the modes see (the check reads M, it does not change it).
        matrices.mass.entries.last_mut().unwrap().value = 1.9;
        let s = SparseStructure::new(&matrices, &[label(1, 1)]).unwrap();
        let (i, j) = (
            s.index_of(label(3, 1)).unwrap(),
            s.index_of(label(4, 1)).unwrap(),
        );
        assert_eq!(s.mass().get(i, j), 1.9);
    }

    #[test]
    fn a_failing_simplicial_pivot_names_its_dof() {
        let mut massless = chain(4, 1.0e6, 2.0);
        massless.mass.entries[2].value = 0.0;
        // The band's message names the same DOF and row (mod.rs's test).
        assert_eq!(
            SparseStructure::new(&massless, &[label(1, 1)]).unwrap_err().to_string(),
            "the mass matrix is not positive definite on the free DOFs: the sparse Cholesky's pivot at node 3 direction 1 (row 5 of the file) is not positive, so some motion there has no mass"
        );
    }
}
