//! Symmetric banded matrices and their Cholesky factorisation.
//!
//! Every structural model here is a strip (a beam or a structured mesh numbered along its
//! length), so its mass and stiffness matrices are banded with a half-bandwidth `b` that
//! does not grow with the length. A banded Cholesky then costs O(n b^2) once and
//! O(n b) per solve, with no fill outside the band and no allocation after construction
//! (Golub and Van Loan, Matrix Computations, 4th ed., Alg. 4.3.5).

use std::fmt;

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
#[derive(Clone, Debug, PartialEq)]
pub struct NotPositiveDefinite {
    /// Row at which a non-positive pivot appeared.
    pub row: usize,
    /// The pivot.
    pub pivot: f64,
}

impl fmt::Display for NotPositiveDefinite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "matrix is not positive definite: pivot {:e} at row {}",
            self.pivot, self.row
        )
    }
}

impl std::error::Error for NotPositiveDefinite {}

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
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.n);
        assert_eq!(y.len(), self.n);
        let b = self.half_bandwidth;
        y.fill(0.0);
        for i in 0..self.n {
            let j0 = i.saturating_sub(b);
            let row = &self.lower[i * (b + 1) + j0 + b - i..(i + 1) * (b + 1)];
            let (off, diag) = row.split_at(row.len() - 1);
            let mut acc = diag[0] * x[i];
            for (k, &a) in off.iter().enumerate() {
                let j = j0 + k;
                acc += a * x[j];
                y[j] += a * x[i];
            }
            y[i] += acc;
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

/// The Cholesky factor L of a symmetric positive definite banded matrix, stored in the
/// same lower-band layout.
#[derive(Clone, Debug)]
pub struct BandCholesky {
    n: usize,
    half_bandwidth: usize,
    lower: Vec<f64>,
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
        Ok(Self {
            n,
            half_bandwidth: b,
            lower: l,
        })
    }

    pub fn size(&self) -> usize {
        self.n
    }

    /// Solves A x = rhs in place (rhs becomes x). No allocation.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        assert_eq!(x.len(), self.n);
        let b = self.half_bandwidth;
        let w = b + 1;
        // Forward: L y = rhs.
        for i in 0..self.n {
            let j0 = i.saturating_sub(b);
            let row = &self.lower[i * w + j0 + b - i..i * w + b];
            let mut s = x[i];
            for (k, &lik) in row.iter().enumerate() {
                s -= lik * x[j0 + k];
            }
            x[i] = s / self.lower[i * w + b];
        }
        // Backward: L^T x = y, sweeping rows of L so that memory access stays contiguous.
        for i in (0..self.n).rev() {
            let xi = x[i] / self.lower[i * w + b];
            x[i] = xi;
            let j0 = i.saturating_sub(b);
            let row = &self.lower[i * w + j0 + b - i..i * w + b];
            for (k, &lik) in row.iter().enumerate() {
                x[j0 + k] -= lik * xi;
            }
        }
    }
}

/// Dot product.
#[inline]
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

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
            let x_true: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
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
