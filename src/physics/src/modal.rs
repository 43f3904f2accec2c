//! Natural modes of a structural model and the reduced (modal) model.
//!
//! Eigenpairs K phi = omega^2 M phi come from subspace iteration with Rayleigh-Ritz
//! (Bathe, Finite Element Procedures, 2nd ed., Sec. 11.6), using the banded factor of K
//! that the model has anyway. That scales to fine plane-stress meshes where a dense
//! eigen solver would not.
//!
//! The reduced model spans the lowest `modes` eigenvectors plus, with static correction,
//! the static tip-load shape psi = K^-1 c. With psi in the basis, the reduced static
//! tip compliance c^T T (T^T K T)^-1 T^T c equals the full model's c^T K^-1 c exactly
//! (the Ritz projection is exact for any load whose static answer lies in the basis).
//! A final Rayleigh-Ritz step on the basis makes the reduced M = I and
//! K = diag(omega_i^2), so its matrices are diagonal.

use crate::banded::{dot, dots, BandCholesky, SymBandMatrix};
use crate::elementary;
use crate::scene::FidelityLevel;
use crate::structure::{observe, ModelError, Observation, StructuralModel};
use nalgebra::{DMatrix, Dyn, SymmetricEigen};

/// The lowest eigenpairs, ascending; vectors are M-normalised (phi^T M phi = 1).
#[derive(Clone, Debug)]
pub struct Modes {
    /// omega^2 (rad^2/s^2).
    pub eigenvalues: Vec<f64>,
    /// Eigenvectors, one `Vec` per mode.
    pub vectors: Vec<Vec<f64>>,
}

/// Solves the dense generalized problem A q = lambda B q for symmetric A and SPD B;
/// returns eigenvalues ascending and B-orthonormal eigenvectors as columns.
fn dense_generalized(a: &DMatrix<f64>, b: &DMatrix<f64>) -> Option<(Vec<f64>, DMatrix<f64>)> {
    let chol = b.clone().cholesky()?;
    let l = chol.l();
    let l_inv = l.clone().try_inverse()?;
    let l_inv_t = l_inv.transpose();
    let mut c = product(&product(&l_inv, a), &l_inv_t);
    c = (&c + c.transpose()) * 0.5;
    let eig = SymmetricEigen::new(c);
    let q = product(&l_inv_t, &eig.eigenvectors);
    let mut order: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let values = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    let vectors = DMatrix::from_fn(q.nrows(), order.len(), |r, c| q[(r, order[c])]);
    Some((values, vectors))
}

/// A B, each entry summed over k in ascending order with separate products and sums.
/// Not nalgebra's `*`: above a few rows that calls matrixmultiply, which picks an FMA
/// kernel at run time, so the modes (and every modal run) had different last bits on a
/// CPU without FMA (tests/physics/reproducible.rs). These matrices are the subspace's,
/// at most 2 q x 2 q, so the plain loop costs nothing that shows.
fn product(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    assert_eq!(a.ncols(), b.nrows());
    DMatrix::from_fn(a.nrows(), b.ncols(), |i, j| {
        (0..a.ncols()).fold(0.0, |s, k| s + a[(i, k)] * b[(k, j)])
    })
}

/// Gram matrix X^T A Y of column sets.
fn gram(a: &SymBandMatrix, x: &[Vec<f64>], y: &[Vec<f64>]) -> DMatrix<f64> {
    let mut ay = vec![0.0; a.size()];
    let mut g = DMatrix::zeros(x.len(), y.len());
    for (j, yj) in y.iter().enumerate() {
        a.mul_vec(yj, &mut ay);
        for (i, d) in dots(&ay, x).into_iter().enumerate() {
            g[(i, j)] = d;
        }
    }
    g
}

/// Columns X Q.
fn combine(x: &[Vec<f64>], q: &DMatrix<f64>, columns: usize) -> Vec<Vec<f64>> {
    (0..columns)
        .map(|c| {
            let mut v = vec![0.0; x[0].len()];
            for (r, xr) in x.iter().enumerate() {
                let s = q[(r, c)];
                v.iter_mut().zip(xr).for_each(|(vi, xi)| *vi += s * xi);
            }
            v
        })
        .collect()
}

/// Relative change of omega^2 between iterations at which subspace iteration stops;
/// round-off stalls it near 1e-13, and 1e-10 on omega^2 is 5e-11 on frequency.
const EIGENVALUE_TOLERANCE: f64 = 1e-10;

/// The number of dofs and the factor of K, for a request of `count` modes: between 1
/// and the number of dofs.
fn checked_count(
    model: &StructuralModel,
    count: usize,
) -> Result<(usize, BandCholesky), ModelError> {
    let n = model.dofs();
    if count == 0 || count > n {
        return Err(ModelError::TooManyModes {
            asked: count,
            available: n,
        });
    }
    Ok((n, model.stiffness_factor()?))
}

/// The lowest `count` eigenpairs of (K, M) by subspace iteration.
pub fn lowest_modes(model: &StructuralModel, count: usize) -> Result<Modes, ModelError> {
    let (n, factor) = checked_count(model, count)?;
    // Bathe's subspace size: p = min(2q, q + 8), at most n.
    let p = (2 * count).min(count + 8).max(count).min(n);
    // Deterministic start: M's diagonal plus smooth oscillating patterns, so that results
    // are reproducible run to run.
    let mdiag = model.mass.diagonal();
    let mut x: Vec<Vec<f64>> = (0..p)
        .map(|c| {
            (0..n)
                .map(|i| {
                    let s = elementary::sin(
                        (i as f64 + 1.0) * (c as f64 + 1.0) * 0.618_033_988_749_895,
                    );
                    mdiag[i] * if c == 0 { 1.0 } else { s }
                })
                .collect()
        })
        .collect();
    let mut previous = vec![f64::INFINITY; count];
    let mut scratch = vec![0.0; n];
    const MAX_ITERATIONS: usize = 300;
    // Eigenvalues converge at twice the rate of eigenvectors: when the eigenvalues have
    // settled after k iterations the vectors still carry errors ~ sqrt(tolerance), so
    // iterate k more times (the reduced model relies on K phi = omega^2 M phi).
    let mut settled_at: Option<usize> = None;
    for iteration in 1..=MAX_ITERATIONS {
        // Y = K^-1 M X. K_r = Y^T K Y is formed as Y^T (M X), since K Y = M X: the direct
        // product cancels catastrophically (K holds axial stiffness ~1e11 against bending
        // eigenvalues ~1e3) and leaves ~1e-7 noise on omega^2.
        let mut mx = Vec::with_capacity(p);
        let mut y = Vec::with_capacity(p);
        for xc in &x {
            let mut m_x = vec![0.0; n];
            model.mass.mul_vec(xc, &mut m_x);
            let mut v = m_x.clone();
            factor.solve_in_place(&mut v);
            // Columns shrink like 1 / omega_i^2; equal M-norms keep the reduced mass
            // matrix well conditioned.
            let norm = model.mass.bilinear(&v, &v, &mut scratch).sqrt();
            v.iter_mut().for_each(|e| *e /= norm);
            m_x.iter_mut().for_each(|e| *e /= norm);
            mx.push(m_x);
            y.push(v);
        }
        let rows: Vec<Vec<f64>> = y.iter().map(|yi| dots(yi, &mx)).collect();
        let cross = DMatrix::from_fn(p, p, |i, j| rows[i][j]);
        let kr = DMatrix::from_fn(p, p, |i, j| 0.5 * (cross[(i, j)] + cross[(j, i)]));
        let mr = gram(&model.mass, &y, &y);
        let (values, q) = dense_generalized(&kr, &mr).ok_or(ModelError::DependentSubspace)?;
        x = combine(&y, &q, p);
        let converged = values[..count]
            .iter()
            .zip(&previous)
            .all(|(v, w)| ((v - w) / v).abs() < EIGENVALUE_TOLERANCE);
        previous.copy_from_slice(&values[..count]);
        if converged && settled_at.is_none() {
            settled_at = Some(iteration);
        }
        if settled_at.is_some_and(|k| iteration >= 2 * k) {
            x.truncate(count);
            for v in &mut x {
                let norm = model.mass.bilinear(v, v, &mut scratch).sqrt();
                v.iter_mut().for_each(|e| *e /= norm);
            }
            return Ok(Modes {
                eigenvalues: previous,
                vectors: x,
            });
        }
    }
    Err(ModelError::NoConvergence {
        iterations: MAX_ITERATIONS,
    })
}

/// Relative residual b_m |s_mi| / theta_i of a Ritz pair (module doc of
/// [`lanczos_modes`]) at which shift-invert Lanczos accepts it. The eigenvalue error is
/// about its square, the eigenvector error about it over the relative gap: 1e-10 gives
/// vectors as accurate as [`lowest_modes`]' doubled iteration count does.
const RITZ_TOLERANCE: f64 = 1e-10;

/// A deterministic start vector with components of every sign and size (SplitMix64,
/// Steele, Lea and Flood 2014, mapped to [-1, 1)): no low mode is orthogonal to it, and
/// integer arithmetic makes it the same on every platform.
fn start_vector(n: usize) -> Vec<f64> {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    (0..n)
        .map(|_| {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        })
        .collect()
}

/// The lowest `count` eigenpairs of (K, M) by shift-invert Lanczos with full
/// reorthogonalisation (Ericsson and Ruhe, Math. Comp. 35, 1980; Bathe, Sec. 11.5).
///
/// The operator A = K^-1 M is self-adjoint in the M inner product and its largest
/// eigenvalues theta = 1 / omega^2 are the structure's lowest modes, so each Lanczos step
/// is one banded solve with the factor of K. After m steps, A Q_m = Q_m T_m + b_m q_{m+1}
/// e_m^T with T_m tridiagonal; a Ritz pair (theta_i, Q_m s_i) has the M-norm residual
/// b_m |s_mi|, and steps are added until that is below [`RITZ_TOLERANCE`] theta_i for
/// every wanted pair. Like the subspace iteration, it never multiplies by K (whose
/// axial entries, ~1e11, cancel against bending eigenvalues ~1e3).
///
/// Used for the plane-stress mesh, where subspace iteration converges slowly: its
/// closely spaced bending and axial modes make the ratio omega_q^2 / omega_(p+1)^2 that
/// sets its rate close to 1 (measured in `reduce`'s doc).
pub fn lanczos_modes(model: &StructuralModel, count: usize) -> Result<Modes, ModelError> {
    let (_, factor) = checked_count(model, count)?;
    lanczos(&model.mass, &factor, count)
}

/// A symmetric matrix as the eigen solvers use it: its size and its product with a vector.
/// The band matrix and `linear_structure::sparse`'s matrix both are one.
pub(crate) trait SymmetricOperator {
    fn size(&self) -> usize;
    /// y = A x.
    fn mul_vec(&self, x: &[f64], y: &mut [f64]);
    /// x^T A y, with `scratch` (the size) for A y.
    fn bilinear(&self, x: &[f64], y: &[f64], scratch: &mut [f64]) -> f64 {
        self.mul_vec(y, scratch);
        dot(x, scratch)
    }
}

/// The factor of K as shift-invert uses it: x <- K^-1 x.
pub(crate) trait StiffnessSolve {
    fn solve_in_place(&self, x: &mut [f64]);
}

impl SymmetricOperator for SymBandMatrix {
    fn size(&self) -> usize {
        SymBandMatrix::size(self)
    }
    fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        SymBandMatrix::mul_vec(self, x, y);
    }
    fn bilinear(&self, x: &[f64], y: &[f64], scratch: &mut [f64]) -> f64 {
        SymBandMatrix::bilinear(self, x, y, scratch)
    }
}

impl StiffnessSolve for BandCholesky {
    fn solve_in_place(&self, x: &mut [f64]) {
        BandCholesky::solve_in_place(self, x);
    }
}

/// [`lanczos_modes`] on a mass matrix and the factor of a stiffness matrix of the same
/// size, for any structure (`linear_structure`'s band and sparse ones too); `count` is
/// between 1 and the size.
pub(crate) fn lanczos<M: SymmetricOperator, F: StiffnessSolve>(
    mass: &M,
    factor: &F,
    count: usize,
) -> Result<Modes, ModelError> {
    lanczos_counts(mass, factor, &[count])
        .pop()
        .expect("one result per count")
}

/// [`lanczos`] for each of `counts` from one Lanczos recurrence: the Lanczos vectors do
/// not depend on the count (it only decides when to stop), so the result for each count
/// is the one `lanczos` gives for it alone, bit for bit, at the cost of the largest.
/// (`auto::structure` reduces a structure too wide for the band at every mode count of
/// its ladder this way.)
pub(crate) fn lanczos_counts<M: SymmetricOperator, F: StiffnessSolve>(
    mass: &M,
    factor: &F,
    counts: &[usize],
) -> Vec<Result<Modes, ModelError>> {
    let n = mass.size();
    let mut results: Vec<Option<Result<Modes, ModelError>>> = counts.iter().map(|_| None).collect();
    let mut scratch = vec![0.0; n];
    let mut q = start_vector(n);
    let norm = mass.bilinear(&q, &q, &mut scratch).sqrt();
    q.iter_mut().for_each(|e| *e /= norm);
    // Lanczos vectors and their products with M (for the M inner products).
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut m_basis: Vec<Vec<f64>> = Vec::new();
    let mut alpha: Vec<f64> = Vec::new();
    let mut beta: Vec<f64> = Vec::new();
    loop {
        let mut mq = vec![0.0; n];
        mass.mul_vec(&q, &mut mq);
        let mut w = mq.clone();
        factor.solve_in_place(&mut w);
        basis.push(q);
        m_basis.push(mq);
        let j = basis.len() - 1;
        alpha.push(dot(&w, &m_basis[j]));
        reorthogonalise(&mut w, &basis, &m_basis);
        let b = mass.bilinear(&w, &w, &mut scratch).sqrt();
        let steps = basis.len();
        // A NaN b (a broken factor) counts as exhausted too.
        let exhausted = steps == n || b.is_nan() || b <= 1e-14 * alpha[0].abs();
        let mut ritz = None;
        for (result, &count) in results.iter_mut().zip(counts) {
            if result.is_some() {
                continue;
            }
            if steps >= count {
                let (eig, order) = ritz.get_or_insert_with(|| ritz_values(&alpha, &beta));
                let converged = order[..count].iter().all(|&i| {
                    b * eig.eigenvectors[(steps - 1, i)].abs()
                        <= RITZ_TOLERANCE * eig.eigenvalues[i].abs()
                });
                if converged {
                    *result = Some(ritz_modes(mass, &basis, eig, &order[..count]));
                } else if exhausted {
                    *result = Some(Err(ModelError::NoConvergence { iterations: steps }));
                }
            } else if exhausted {
                *result = Some(Err(ModelError::NoConvergence { iterations: steps }));
            }
        }
        if results.iter().all(Option::is_some) {
            return results.into_iter().flatten().collect();
        }
        beta.push(b);
        w.iter_mut().for_each(|e| *e /= b);
        q = w;
    }
}

/// Full reorthogonalisation of the next Lanczos vector `w` against the `basis` (with
/// `m_basis` its products with M), by classical Gram-Schmidt in the M inner product,
/// twice: it subtracts the three-term recurrence's alpha_j q_j + beta_(j-1) q_(j-1) and
/// the round-off components along every earlier vector, which would otherwise bring back
/// copies of converged modes.
fn reorthogonalise(w: &mut [f64], basis: &[Vec<f64>], m_basis: &[Vec<f64>]) {
    for _ in 0..2 {
        let projections = dots(w, m_basis);
        for (p, v) in projections.iter().zip(basis) {
            w.iter_mut().zip(v).for_each(|(wi, vi)| *wi -= p * vi);
        }
    }
}

/// The eigenpairs (theta_i, s_i) of the Lanczos tridiagonal T_m (diagonal `alpha`,
/// off-diagonal `beta`), and their indices largest theta first: the lowest omega^2.
fn ritz_values(alpha: &[f64], beta: &[f64]) -> (SymmetricEigen<f64, Dyn>, Vec<usize>) {
    let steps = alpha.len();
    let t = DMatrix::from_fn(steps, steps, |r, c| {
        if r == c {
            alpha[r]
        } else if r.abs_diff(c) == 1 {
            beta[r.min(c)]
        } else {
            0.0
        }
    });
    let eig = SymmetricEigen::new(t);
    let mut order: Vec<usize> = (0..steps).collect();
    order.sort_by(|&a, &c| eig.eigenvalues[c].total_cmp(&eig.eigenvalues[a]));
    (eig, order)
}

/// The modes of the converged Ritz pairs `wanted` (indices into `eig`): eigenvalue
/// omega^2 = 1 / theta_i, vector Q_m s_i normalised in M. A theta that is not positive
/// (no mode of a clamped structure) is no convergence.
fn ritz_modes<M: SymmetricOperator>(
    mass: &M,
    basis: &[Vec<f64>],
    eig: &SymmetricEigen<f64, Dyn>,
    wanted: &[usize],
) -> Result<Modes, ModelError> {
    let n = basis[0].len();
    let mut scratch = vec![0.0; n];
    let mut eigenvalues = Vec::with_capacity(wanted.len());
    let mut vectors = Vec::with_capacity(wanted.len());
    for &i in wanted {
        let theta = eig.eigenvalues[i];
        if theta.is_nan() || theta <= 0.0 {
            return Err(ModelError::NoConvergence {
                iterations: basis.len(),
            });
        }
        let mut x = vec![0.0; n];
        for (r, v) in basis.iter().enumerate() {
            let s = eig.eigenvectors[(r, i)];
            x.iter_mut().zip(v).for_each(|(xi, vi)| *xi += s * vi);
        }
        let norm = mass.bilinear(&x, &x, &mut scratch).sqrt();
        x.iter_mut().for_each(|e| *e /= norm);
        eigenvalues.push(1.0 / theta);
        vectors.push(x);
    }
    Ok(Modes {
        eigenvalues,
        vectors,
    })
}

/// The eigen solver for a model: shift-invert Lanczos for the plane-stress mesh, and
/// subspace iteration for the beam, whose modal runs are shipped and tested bit for bit
/// and so keep the solver they were made with.
pub fn modes_of(model: &StructuralModel, count: usize) -> Result<Modes, ModelError> {
    match model.level {
        FidelityLevel::PlaneStress => lanczos_modes(model, count),
        _ => lowest_modes(model, count),
    }
}

impl StructuralModel {
    /// The lowest `count` natural frequencies (Hz) of the clamped structure.
    pub fn natural_frequencies(&self, count: usize) -> Result<Vec<f64>, ModelError> {
        let modes = lowest_modes(self, count)?;
        Ok(modes
            .eigenvalues
            .iter()
            .map(|w2| w2.sqrt() / (2.0 * std::f64::consts::PI))
            .collect())
    }
}

/// Why a structure with a damping matrix from a file has no modal model yet: Phi^T C0
/// Phi is a full matrix, where the modal model is diagonal, and dropping C0 would run
/// another structure than the user's.
pub(crate) fn damping_not_projected() -> ModelError {
    ModelError::UserStructure(
        "structure.damping: a damping matrix from a file is not projected onto modes yet (Phi^T C Phi is a full matrix; the modal model is diagonal); use fidelity.level = plane-stress (the full model) or the scene's Rayleigh damping".to_string(),
    )
}

/// The modal model of `full` with its lowest `modes` modes, plus the static tip-load
/// shape when `static_correction` is set.
pub fn reduce(
    full: &StructuralModel,
    modes: usize,
    static_correction: bool,
) -> Result<StructuralModel, ModelError> {
    if full.damping.is_some() {
        return Err(damping_not_projected());
    }
    let eigen = modes_of(full, modes)?;
    let static_shape = if static_correction {
        Some(full.static_displacement(1.0)?)
    } else {
        None
    };
    reduced_model(
        eigen,
        static_shape,
        &full.mass,
        (&full.tip, &full.sensors),
        &full.label,
    )
}

/// The modal model spanned by the M-normalised `eigen` modes of a structure with mass
/// matrix `mass`, tip vector and sensors' observation vectors `(tip, sensors)` (the full
/// model's, u_tip = sum w u_dof), plus the static tip-load shape psi = K^-1 c
/// (`static_shape`) when given; `label` names the full model. Each observation vector
/// is projected on the basis T as the tip's is: w_j = c . T_j. Shared by [`reduce`] (a band model) and `linear_structure::sparse_modal`
/// (a structure too wide for the band).
pub(crate) fn reduced_model<M: SymmetricOperator>(
    eigen: Modes,
    static_shape: Option<Vec<f64>>,
    mass: &M,
    (tip, sensors): (&[(usize, f64)], &[Observation]),
    label: &str,
) -> Result<StructuralModel, ModelError> {
    let tip_value = |x: &[f64]| -> f64 { observe(tip, x) };
    let n = mass.size();
    let q = eigen.vectors.len();
    let modes = q;
    let mut basis = eigen.vectors;
    // Reduced stiffness from exact identities rather than T^T K T (which cancels, see
    // `lowest_modes`): phi_i^T K phi_j = omega_i^2 delta_ij, and K psi = c.
    let mut kr = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(eigen.eigenvalues.clone()));
    if let Some(mut psi) = static_shape {
        // psi = K^-1 c, M-orthogonalised against the modes: psi' = psi - sum p_i phi_i
        // with p_i = phi_i^T M psi. Then phi_i^T K psi' = c . phi_i - p_i omega_i^2 and
        // psi'^T K psi' = c . psi'. Skipped when the modes already span psi.
        let mut scratch = vec![0.0; n];
        let psi_norm = mass.bilinear(&psi, &psi, &mut scratch).sqrt();
        let mut projections = Vec::with_capacity(q);
        for phi in &basis {
            let proj = mass.bilinear(phi, &psi, &mut scratch);
            psi.iter_mut().zip(phi).for_each(|(p, f)| *p -= proj * f);
            projections.push(proj);
        }
        let rest = mass.bilinear(&psi, &psi, &mut scratch).sqrt();
        if rest > 1e-8 * psi_norm {
            psi.iter_mut().for_each(|p| *p /= rest);
            let mut extended = DMatrix::zeros(q + 1, q + 1);
            extended.view_mut((0, 0), (q, q)).copy_from(&kr);
            for i in 0..q {
                let coupling =
                    tip_value(&basis[i]) / rest - projections[i] * eigen.eigenvalues[i] / rest;
                extended[(i, q)] = coupling;
                extended[(q, i)] = coupling;
            }
            extended[(q, q)] = tip_value(&psi) / rest;
            kr = extended;
            basis.push(psi);
        }
    }
    // The basis is M-orthonormal, so the reduced problem is a standard symmetric one.
    let eig = SymmetricEigen::new(kr);
    let mut order: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let values: Vec<f64> = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    let rotation = DMatrix::from_fn(basis.len(), basis.len(), |r, c| {
        eig.eigenvectors[(r, order[c])]
    });
    let t = combine(&basis, &rotation, basis.len());
    let project = |c: &[(usize, f64)]| -> Observation {
        t.iter()
            .enumerate()
            .map(|(j, tj)| (j, observe(c, tj)))
            .collect()
    };
    let tip = project(tip);
    let sensors = sensors.iter().map(|s| project(s)).collect();
    Ok(StructuralModel {
        level: FidelityLevel::Modal,
        label: format!(
            "modal, {modes} modes{} of {}",
            if t.len() > modes {
                " + static correction"
            } else {
                ""
            },
            label
        ),
        mass: SymBandMatrix::from_diagonal(&vec![1.0; t.len()]),
        stiffness: SymBandMatrix::from_diagonal(&values),
        tip,
        damping: None,
        sensors,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::CheckedScene;

    /// ||x - lambda K^-1 M x||_M of an M-normalised eigenpair: the residual in the
    /// form the solvers work with. The direct K x - lambda M x cancels (the mesh's axial
    /// stiffness, ~1e11, against bending eigenvalues ~1e3) and measures only round-off.
    fn residual(model: &StructuralModel, lambda: f64, x: &[f64]) -> f64 {
        let n = x.len();
        let mut y = vec![0.0; n];
        model.mass.mul_vec(x, &mut y);
        model.stiffness_factor().unwrap().solve_in_place(&mut y);
        let r: Vec<f64> = x.iter().zip(&y).map(|(a, b)| a - lambda * b).collect();
        model.mass.bilinear(&r, &r, &mut vec![0.0; n]).sqrt()
    }

    #[test]
    fn lanczos_and_subspace_iteration_find_the_same_modes() {
        let scene = CheckedScene::paper();
        for model in [
            StructuralModel::beam(&scene, 40),
            StructuralModel::plane_stress(&scene, 0.04),
        ] {
            let count = 12;
            let lanczos = lanczos_modes(&model, count).unwrap();
            let subspace = lowest_modes(&model, count).unwrap();
            for (k, (a, b)) in lanczos
                .eigenvalues
                .iter()
                .zip(&subspace.eigenvalues)
                .enumerate()
            {
                // Both solvers stop at ~1e-10 relative on omega^2 or better.
                assert!(
                    (a - b).abs() < 1e-9 * b,
                    "{}: mode {k}: {a} vs {b}",
                    model.label
                );
            }
            let mut scratch = vec![0.0; model.dofs()];
            for (k, x) in lanczos.vectors.iter().enumerate() {
                // M-normalised, M-orthogonal to the others, and an eigenvector to the
                // solver's tolerance.
                let norm = model.mass.bilinear(x, x, &mut scratch);
                assert!((norm - 1.0).abs() < 1e-12, "{norm}");
                for y in &lanczos.vectors[..k] {
                    assert!(model.mass.bilinear(x, y, &mut scratch).abs() < 1e-9);
                }
                let r = residual(&model, lanczos.eigenvalues[k], x);
                assert!(r < 1e-8, "{}: mode {k}: residual {r}", model.label);
            }
        }
    }

    #[test]
    fn lanczos_refuses_more_modes_than_dofs() {
        let scene = CheckedScene::paper();
        let model = StructuralModel::beam(&scene, 2);
        assert!(matches!(
            lanczos_modes(&model, 5),
            Err(ModelError::TooManyModes {
                asked: 5,
                available: 4
            })
        ));
        // All of a small model's modes: the Krylov space is the whole space.
        let all = lanczos_modes(&model, 4).unwrap();
        let reference = lowest_modes(&model, 4).unwrap();
        for (a, b) in all.eigenvalues.iter().zip(&reference.eigenvalues) {
            assert!((a - b).abs() < 1e-9 * b, "{a} vs {b}");
        }
    }
}
