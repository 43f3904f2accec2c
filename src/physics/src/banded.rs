//! Symmetric banded matrices and their Cholesky factorisation.
//!
//! Every structural model here is a strip (a beam or a structured mesh numbered along its
//! length), so its mass and stiffness matrices are banded with a half-bandwidth `b` that
//! does not grow with the length. A banded Cholesky then costs O(n b^2) once and
//! O(n b) per solve, with no fill outside the band and no allocation after construction
//! (Golub and Van Loan, Matrix Computations, 4th ed., Alg. 4.3.5).
//!
//! Why our own rather than a crate's:
//! - Measured (`cargo bench -p stickslip-tests --bench paper_scene`, banded against
//!   nalgebra's dense Cholesky on the same plane-stress effective matrix, 1002 dofs,
//!   b = 15, in one run): 332x faster to factorise and 12x faster per solve
//!   (docs/decisions.md, "Solver"); the ratio grows with the length, O(n b^2) against
//!   O(n^3).
//! - The step loop's results are shipped and tested bit for bit. The contiguous row and
//!   column sweeps of [`BandCholesky`] and the fused band product ([`BandPairProduct`])
//!   keep the textbook operation order, which fixes those bits; a library
//!   factorisation with its own blocking or summation order would change the last bits,
//!   which grow after breakaway (1e-8 to 1e-5 relative, docs/measurements.md, "Wall
//!   time").
//! - None offers this kind: nalgebra has dense `Cholesky` and, in nalgebra-sparse, a CSC
//!   `CscCholesky` without fill-reducing ordering that its docs do not recommend for
//!   serious use; faer has dense `Llt` and sparse (CSC) simplicial and supernodal LL^T
//!   with fill-reducing orderings, but no symmetric band storage or band factorisation
//!   (LAPACK's `dpbtrf` is the classic one, and would need a BLAS/LAPACK binding).

/// A symmetric n x n matrix with half-bandwidth `b`: a_ij = 0 when |i - j| > b.
/// Only the lower band is stored, row by row: row i holds a_{i, i-b} ... a_{i, i}.
#[derive(Clone, Debug, PartialEq)]
pub struct SymBandMatrix {
    n: usize,
    half_bandwidth: usize,
    /// (b + 1) entries per row; entry (i, j) with i - b <= j <= i at i (b + 1) + j + b - i.
    lower: Vec<f64>,
}

/// Error of a factorisation: the matrix is not positive definite.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("matrix is not positive definite: pivot {pivot:e} at row {row}")]
pub struct NotPositiveDefinite {
    /// Row at which a non-positive pivot appeared.
    pub row: usize,
    /// The pivot.
    pub pivot: f64,
}

impl SymBandMatrix {
    /// The zero matrix of size `n` with half-bandwidth `half_bandwidth`.
    pub fn zeros(n: usize, half_bandwidth: usize) -> Self {
        let half_bandwidth = half_bandwidth.min(n.saturating_sub(1));
        Self {
            n,
            half_bandwidth,
            lower: vec![0.0; n * (half_bandwidth + 1)],
        }
    }

    /// A diagonal matrix.
    pub fn from_diagonal(diagonal: &[f64]) -> Self {
        let mut m = Self::zeros(diagonal.len(), 0);
        m.lower.copy_from_slice(diagonal);
        m
    }

    pub fn size(&self) -> usize {
        self.n
    }

    pub fn half_bandwidth(&self) -> usize {
        self.half_bandwidth
    }

    #[inline]
    fn index(&self, i: usize, j: usize) -> usize {
        debug_assert!(j <= i && i - j <= self.half_bandwidth);
        i * (self.half_bandwidth + 1) + j + self.half_bandwidth - i
    }

    /// Entry (i, j); zero outside the band.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if j > i { (j, i) } else { (i, j) };
        if i - j > self.half_bandwidth {
            0.0
        } else {
            self.lower[self.index(i, j)]
        }
    }

    /// Adds `value` to entries (i, j) and (j, i). Panics outside the band, which is a
    /// programming error of the assembly (the bandwidth is computed from the same
    /// connectivity before assembly).
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let (i, j) = if j > i { (j, i) } else { (i, j) };
        assert!(
            i - j <= self.half_bandwidth,
            "entry ({i}, {j}) outside half-bandwidth {}",
            self.half_bandwidth
        );
        let k = self.index(i, j);
        self.lower[k] += value;
    }

    /// alpha * self + beta * other, for matrices of equal size and bandwidth.
    pub fn linear_combination(&self, alpha: f64, other: &SymBandMatrix, beta: f64) -> Self {
        assert_eq!(self.n, other.n);
        assert_eq!(self.half_bandwidth, other.half_bandwidth);
        Self {
            n: self.n,
            half_bandwidth: self.half_bandwidth,
            lower: self
                .lower
                .iter()
                .zip(&other.lower)
                .map(|(a, b)| alpha * a + beta * b)
                .collect(),
        }
    }

    /// y = A x, overwriting y.
    ///
    /// Row by row, y_i = a_ii x_i + sum_{j<i} a_ij x_j + sum_{j>i} a_ji x_j with each
    /// sum in ascending j: a gather per row, with no scatter into earlier rows (whose
    /// store-to-load chains made the former scatter form slow). [`BandPairProduct`]
    /// keeps this order exactly.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.n);
        assert_eq!(y.len(), self.n);
        let n = self.n;
        let b = self.half_bandwidth;
        let w = b + 1;
        for i in 0..n {
            let j0 = i.saturating_sub(b);
            let row = &self.lower[i * w + j0 + b - i..(i + 1) * w];
            let (off, diag) = row.split_at(row.len() - 1);
            let mut acc = diag[0] * x[i];
            for (a, xj) in off.iter().zip(&x[j0..i]) {
                acc += a * xj;
            }
            for k in 1..=b.min(n - 1 - i) {
                acc += self.lower[(i + k) * w + b - k] * x[i + k];
            }
            y[i] = acc;
        }
    }

    /// x^T A y.
    pub fn bilinear(&self, x: &[f64], y: &[f64], scratch: &mut [f64]) -> f64 {
        self.mul_vec(y, scratch);
        dot(x, scratch)
    }

    /// The diagonal.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.lower[self.index(i, i)]).collect()
    }

    /// Cholesky factorisation A = L L^T.
    pub fn cholesky(&self) -> Result<BandCholesky, NotPositiveDefinite> {
        BandCholesky::new(self)
    }
}

/// The Cholesky factor L of a symmetric positive definite banded matrix (A = L L^T),
/// stored twice for the two sweeps of a solve: by rows of L for the forward sweep, by
/// rows of L^T (columns of L) for the backward one, so that both read contiguously.
#[derive(Clone, Debug)]
pub struct BandCholesky {
    n: usize,
    half_bandwidth: usize,
    /// Row i holds L_{i, i-b} ... L_{i, i-1} (b entries, zero before column 0).
    forward: Vec<f64>,
    /// Row j holds L_{j+1, j} ... L_{j+b, j} (b entries, zero past row n - 1).
    backward: Vec<f64>,
    /// L_ii.
    diagonal: Vec<f64>,
}

impl BandCholesky {
    fn new(a: &SymBandMatrix) -> Result<Self, NotPositiveDefinite> {
        let n = a.n;
        let b = a.half_bandwidth;
        let w = b + 1;
        let mut l = a.lower.clone();
        for i in 0..n {
            let j0 = i.saturating_sub(b);
            for j in j0..=i {
                // L_ij = (A_ij - sum_k L_ik L_jk) / L_jj over k in [max(i, j) - b, j).
                let k0 = j0.max(j.saturating_sub(b));
                let mut s = l[i * w + j + b - i];
                for k in k0..j {
                    s -= l[i * w + k + b - i] * l[j * w + k + b - j];
                }
                if j == i {
                    if s <= 0.0 || !s.is_finite() {
                        return Err(NotPositiveDefinite { row: i, pivot: s });
                    }
                    l[i * w + b] = s.sqrt();
                } else {
                    l[i * w + j + b - i] = s / l[j * w + b];
                }
            }
        }
        let mut forward = vec![0.0; n * b];
        let mut backward = vec![0.0; n * b];
        for i in 0..n {
            for j in i.saturating_sub(b)..i {
                forward[i * b + j + b - i] = l[i * w + j + b - i];
                backward[j * b + i - j - 1] = l[i * w + j + b - i];
            }
        }
        Ok(Self {
            n,
            half_bandwidth: b,
            forward,
            backward,
            diagonal: (0..n).map(|i| l[i * w + b]).collect(),
        })
    }

    pub fn size(&self) -> usize {
        self.n
    }

    /// Solves A x = rhs in place (rhs becomes x). No allocation.
    ///
    /// Forward L y = rhs: y_i = (rhs_i - sum_{j<i} L_ij y_j) / L_ii, j ascending.
    /// Backward L^T x = y: x_j = (y_j - sum_{i>j} L_ij x_i) / L_jj, i descending.
    /// Both sweeps gather along a stored row and carry the unknown just computed in a
    /// register, so the chain from one unknown to the next is its multiply, subtract and
    /// divide, with no store-to-load round trip. The operations and their order are
    /// those of the textbook sweeps, so the result does not depend on this layout.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        assert_eq!(x.len(), self.n);
        let n = self.n;
        let b = self.half_bandwidth;
        if b == 0 {
            for (xi, d) in x.iter_mut().zip(&self.diagonal) {
                *xi = *xi / d / d;
            }
            return;
        }
        let mut prev = 0.0;
        for i in 0..n {
            let j0 = i.saturating_sub(b);
            let row = &self.forward[(i + 1) * b - (i - j0)..(i + 1) * b];
            let mut s = x[i];
            if let Some((&latest, older)) = row.split_last() {
                for (l, y) in older.iter().zip(&x[j0..i - 1]) {
                    s -= l * y;
                }
                s -= latest * prev;
            }
            s /= self.diagonal[i];
            x[i] = s;
            prev = s;
        }
        let mut next = 0.0;
        for j in (0..n).rev() {
            let count = b.min(n - 1 - j);
            let row = &self.backward[j * b..j * b + count];
            let mut s = x[j];
            if let Some((&latest, older)) = row.split_first() {
                for (l, y) in older.iter().rev().zip(x[j + 2..j + 1 + count].iter().rev()) {
                    s -= l * y;
                }
                s -= latest * next;
            }
            s /= self.diagonal[j];
            x[j] = s;
            next = s;
        }
    }
}

/// Rows per block of [`BandPairProduct`]: one AVX-512 or two AVX2 registers.
const BLOCK: usize = 8;

/// y = A x + B z for two symmetric band matrices of equal size and bandwidth (the mass
/// and stiffness products of a time step), fused in one pass.
///
/// The matrices are stored diagonal by diagonal, so that one block of rows takes each
/// term with the same operations and vectorises across rows; every row still sums its
/// terms in the order of [`SymBandMatrix::mul_vec`], so the result is bit for bit that
/// of two `mul_vec` calls and an addition, whatever the vector width. The inputs live in
/// zero-padded buffers (see [`Self::inputs`]) so that no row needs a bounds branch.
#[derive(Clone, Debug)]
pub struct BandPairProduct {
    n: usize,
    half_bandwidth: usize,
    /// Length of one stored diagonal: n rounded up to whole blocks, plus b.
    stride: usize,
    /// Diagonal k of A at [k stride, (k + 1) stride): entry i is a_{i, i-k}, zero where
    /// that lies outside the matrix.
    a: Vec<f64>,
    b: Vec<f64>,
    /// x and z with b zeros before and (rounded n - n + b) zeros after.
    x: Vec<f64>,
    z: Vec<f64>,
    /// Whether the CPU runs the AVX2 build of the kernel (same results, twice the width).
    /// Only x86_64 has that build; elsewhere the field would be dead.
    #[cfg(target_arch = "x86_64")]
    wide: bool,
}

impl BandPairProduct {
    pub fn new(a: &SymBandMatrix, b: &SymBandMatrix) -> Self {
        assert_eq!(a.n, b.n);
        assert_eq!(a.half_bandwidth, b.half_bandwidth);
        let n = a.n;
        let hb = a.half_bandwidth;
        let rows = n.div_ceil(BLOCK) * BLOCK;
        let stride = rows + hb;
        let diagonals = |m: &SymBandMatrix| {
            let mut d = vec![0.0; (hb + 1) * stride];
            for k in 0..=hb {
                for i in k..n {
                    d[k * stride + i] = m.lower[m.index(i, i - k)];
                }
            }
            d
        };
        Self {
            n,
            half_bandwidth: hb,
            stride,
            a: diagonals(a),
            b: diagonals(b),
            x: vec![0.0; stride + hb],
            z: vec![0.0; stride + hb],
            #[cfg(target_arch = "x86_64")]
            wide: std::arch::is_x86_feature_detected!("avx2"),
        }
    }

    /// The inputs x and z (n entries each) to fill before [`Self::apply`].
    pub fn inputs(&mut self) -> (&mut [f64], &mut [f64]) {
        let (hb, n) = (self.half_bandwidth, self.n);
        (&mut self.x[hb..hb + n], &mut self.z[hb..hb + n])
    }

    /// y = A x + B z, overwriting y (n entries).
    pub fn apply(&self, y: &mut [f64]) {
        assert_eq!(y.len(), self.n);
        #[cfg(target_arch = "x86_64")]
        if self.wide {
            // SAFETY: `wide` is set only when the CPU reports AVX2.
            unsafe { pair_product_avx2(self, y) };
            return;
        }
        pair_product(self, y);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn pair_product_avx2(p: &BandPairProduct, y: &mut [f64]) {
    pair_product(p, y);
}

#[inline(always)]
fn pair_product(p: &BandPairProduct, y: &mut [f64]) {
    let (hb, stride) = (p.half_bandwidth, p.stride);
    let block = |v: &[f64], at: usize| -> [f64; BLOCK] { v[at..at + BLOCK].try_into().unwrap() };
    for (c, out) in (0..p.n).step_by(BLOCK).zip(y.chunks_mut(BLOCK)) {
        let (da, db) = (block(&p.a, c), block(&p.b, c));
        let (xa, xb) = (block(&p.x, c + hb), block(&p.z, c + hb));
        let mut sa = [0.0; BLOCK];
        let mut sb = [0.0; BLOCK];
        for t in 0..BLOCK {
            sa[t] = da[t] * xa[t];
            sb[t] = db[t] * xb[t];
        }
        // Lower part, a_ij x_j for j = i - b ... i - 1.
        for k in (1..=hb).rev() {
            let (da, db) = (block(&p.a, k * stride + c), block(&p.b, k * stride + c));
            let (xa, xb) = (block(&p.x, c + hb - k), block(&p.z, c + hb - k));
            for t in 0..BLOCK {
                sa[t] += da[t] * xa[t];
                sb[t] += db[t] * xb[t];
            }
        }
        // Upper part, a_ji x_j for j = i + 1 ... i + b.
        for k in 1..=hb {
            let (da, db) = (
                block(&p.a, k * stride + c + k),
                block(&p.b, k * stride + c + k),
            );
            let (xa, xb) = (block(&p.x, c + hb + k), block(&p.z, c + hb + k));
            for t in 0..BLOCK {
                sa[t] += da[t] * xa[t];
                sb[t] += db[t] * xb[t];
            }
        }
        for (o, (a, b)) in out.iter_mut().zip(sa.iter().zip(&sb)) {
            *o = a + b;
        }
    }
}

/// Dot product.
#[inline]
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// The dot products of `x` with each of `ys`, each bit for bit equal to [`dot`]. Four
/// products advance together, one per vector lane: a single running sum is bound by the
/// latency of its additions, four independent ones are not, and each lane still adds
/// its terms in the same order.
pub fn dots(x: &[f64], ys: &[Vec<f64>]) -> Vec<f64> {
    let mut out = Vec::with_capacity(ys.len());
    let mut groups = ys.chunks_exact(4);
    for g in &mut groups {
        let (y0, y1, y2, y3) = (
            &g[0][..x.len()],
            &g[1][..x.len()],
            &g[2][..x.len()],
            &g[3][..x.len()],
        );
        let mut acc = [0.0; 4];
        for k in 0..x.len() {
            let terms = [x[k] * y0[k], x[k] * y1[k], x[k] * y2[k], x[k] * y3[k]];
            for t in 0..4 {
                acc[t] += terms[t];
            }
        }
        out.extend_from_slice(&acc);
    }
    out.extend(groups.remainder().iter().map(|y| dot(x, y)));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elementary;

    /// A random-ish SPD band matrix: diagonally dominant.
    fn sample(n: usize, b: usize) -> SymBandMatrix {
        let mut a = SymBandMatrix::zeros(n, b);
        for i in 0..n {
            for j in i.saturating_sub(b)..i {
                a.add(i, j, ((i * 7 + j * 3) % 11) as f64 / 11.0 - 0.5);
            }
            a.add(i, i, 2.0 * b as f64 + 1.0);
        }
        a
    }

    #[test]
    fn cholesky_solves_to_round_off() {
        for &(n, b) in &[(1, 0), (5, 0), (10, 3), (50, 7), (40, 39)] {
            let a = sample(n, b);
            let x_true: Vec<f64> = (0..n).map(|i| elementary::sin(i as f64 * 0.37)).collect();
            let mut rhs = vec![0.0; n];
            a.mul_vec(&x_true, &mut rhs);
            let f = a.cholesky().unwrap();
            f.solve_in_place(&mut rhs);
            let err = rhs
                .iter()
                .zip(&x_true)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-12, "n={n} b={b} err={err}");
        }
    }

    #[test]
    fn mul_vec_matches_dense_symmetric_product() {
        let a = sample(12, 4);
        let x: Vec<f64> = (0..12).map(|i| i as f64 - 3.0).collect();
        let mut y = vec![0.0; 12];
        a.mul_vec(&x, &mut y);
        for (i, yi) in y.iter().enumerate() {
            let dense: f64 = x.iter().enumerate().map(|(j, xj)| a.get(i, j) * xj).sum();
            assert!((dense - yi).abs() < 1e-12);
        }
    }

    #[test]
    fn indefinite_matrix_is_reported() {
        let a = SymBandMatrix::from_diagonal(&[1.0, -2.0, 3.0]);
        let err = a.cholesky().unwrap_err();
        assert_eq!(err.row, 1);
    }
}
