//! The modal slip phase of the paper authors' transient algorithm (issue 26): in slip
//! the structure moves on its natural modes below a cut-off frequency, in stick on the
//! full model.
//!
//! With an M-orthonormal basis Phi = [phi_1 .. phi_m] (phi_i^T M phi_j = delta_ij,
//! K phi_i = omega_i^2 M phi_i, omega_i < omega_cut) the change of phase maps the state:
//!
//! - stick -> slip, projection: q = Phi^T M u, q' = Phi^T M v (the M-orthogonal
//!   projection; exact for a state in the span of Phi);
//! - slip -> stick, expansion: u = Phi q, v = Phi q'.
//!
//! In modal coordinates M = I, K = diag(omega_i^2) and the tip vector is Phi^T c, so the
//! energy of a projected state is (1/2) |q'|^2 + (1/2) sum omega_i^2 q_i^2 (J), which
//! equals the full model's (1/2) v^T M v + (1/2) u^T K u of the state restricted to the
//! basis (Phi Phi^T M u, Phi Phi^T M v). The modes of higher frequency are dropped at
//! the projection: their energy is lost to the slip phase.
//!
//! The modes come from the same eigen solver as the `modal` fidelity level
//! (`modal::modes_of`: shift-invert Lanczos for the plane-stress mesh).

use crate::banded::{dots, SymBandMatrix};
use crate::integrator::Kinematics;
use crate::modal::{modes_of, Modes};
use crate::scene::FidelityLevel;
use crate::structure::{ModelError, StructuralModel};

/// The natural modes of a full model below a cut-off, and the model they span.
#[derive(Clone, Debug)]
pub struct SlipBasis {
    /// Cut-off (rad/s): every mode kept has omega_i < omega_cut.
    cutoff: f64,
    /// omega_i^2 (rad^2/s^2) ascending, and the M-normalised phi_i.
    modes: Modes,
    /// M phi_i, so that a projection is m dot products.
    mass_modes: Vec<Vec<f64>>,
    /// The modal model: M = I, K = diag(omega_i^2), tip weights c . phi_i.
    model: StructuralModel,
}

/// Why a slip basis cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SlipBasisError {
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The cut-off is not a positive finite frequency.
    #[error("the modal slip cut-off must be a positive finite angular frequency (rad/s), got {0}")]
    InvalidCutoff(f64),
    /// Even the lowest mode is at or above the cut-off: slip would have no structure.
    #[error("no mode lies below the cut-off {cutoff} rad/s: the lowest is at {lowest} rad/s")]
    NoModeBelow { cutoff: f64, lowest: f64 },
}

/// Modes asked for first; doubled until one lies at or above the cut-off.
const FIRST_REQUEST: usize = 8;

impl SlipBasis {
    /// Every mode of `full` with omega < `cutoff` (rad/s). The eigen solver is asked for
    /// a growing number of modes until the highest one found reaches the cut-off (or the
    /// model has no more), so that none below it is missed.
    pub fn below(full: &StructuralModel, cutoff: f64) -> Result<Self, SlipBasisError> {
        if !(cutoff.is_finite() && cutoff > 0.0) {
            return Err(SlipBasisError::InvalidCutoff(cutoff));
        }
        let n = full.dofs();
        let limit = cutoff * cutoff;
        let mut count = FIRST_REQUEST.min(n);
        let mut modes = modes_of(full, count)?;
        while modes.eigenvalues.last().is_some_and(|&w2| w2 < limit) && count < n {
            count = (2 * count).min(n);
            modes = modes_of(full, count)?;
        }
        let kept = modes.eigenvalues.iter().filter(|&&w2| w2 < limit).count();
        if kept == 0 {
            return Err(SlipBasisError::NoModeBelow {
                cutoff,
                lowest: modes.eigenvalues[0].sqrt(),
            });
        }
        modes.eigenvalues.truncate(kept);
        modes.vectors.truncate(kept);
        let mass_modes = modes
            .vectors
            .iter()
            .map(|phi| {
                let mut m_phi = vec![0.0; n];
                full.mass.mul_vec(phi, &mut m_phi);
                m_phi
            })
            .collect();
        let model = StructuralModel {
            level: FidelityLevel::Modal,
            label: format!(
                "modal slip, {kept} modes below {cutoff} rad/s of {}",
                full.label
            ),
            mass: SymBandMatrix::from_diagonal(&vec![1.0; kept]),
            stiffness: SymBandMatrix::from_diagonal(&modes.eigenvalues),
            tip: modes
                .vectors
                .iter()
                .enumerate()
                .map(|(i, phi)| (i, full.tip_value(phi)))
                .collect(),
            damping: None,
            // The steps on the slip modes are expanded to the full kinematics, which
            // the sensors read.
            sensors: Vec::new(),
        };
        Ok(Self {
            cutoff,
            modes,
            mass_modes,
            model,
        })
    }

    /// The cut-off (rad/s).
    pub fn cutoff(&self) -> f64 {
        self.cutoff
    }

    /// Number of modes kept.
    pub fn len(&self) -> usize {
        self.modes.vectors.len()
    }

    /// Never true: a basis holds at least one mode.
    pub fn is_empty(&self) -> bool {
        self.modes.vectors.is_empty()
    }

    /// Natural angular frequencies omega_i (rad/s) of the kept modes, ascending.
    pub fn frequencies(&self) -> Vec<f64> {
        self.modes.eigenvalues.iter().map(|w2| w2.sqrt()).collect()
    }

    /// The modal model (M = I, K = diag(omega_i^2), tip c . phi_i) slip runs on.
    pub fn model(&self) -> &StructuralModel {
        &self.model
    }

    /// q = Phi^T M x: modal coordinates of a full displacement, velocity or
    /// acceleration.
    pub fn project(&self, x: &[f64]) -> Vec<f64> {
        dots(x, &self.mass_modes)
    }

    /// x = Phi q: the full vector of modal coordinates `q`.
    pub fn expand(&self, q: &[f64]) -> Vec<f64> {
        let mut x = vec![0.0; self.mass_modes[0].len()];
        self.expand_into(q, &mut x);
        x
    }

    /// x = Phi q into `x` (no allocation).
    pub fn expand_into(&self, q: &[f64], x: &mut [f64]) {
        x.iter_mut().for_each(|e| *e = 0.0);
        for (qi, phi) in q.iter().zip(&self.modes.vectors) {
            x.iter_mut().zip(phi).for_each(|(e, p)| *e += qi * p);
        }
    }

    /// q = Phi^T M x into `q` (no allocation).
    pub fn project_into(&self, x: &[f64], q: &mut [f64]) {
        for (qi, m_phi) in q.iter_mut().zip(&self.mass_modes) {
            *qi = crate::banded::dot(x, m_phi);
        }
    }

    /// Projects displacement, velocity and acceleration of a full state into `modal`.
    pub fn project_kinematics(&self, full: &Kinematics, modal: &mut Kinematics) {
        self.project_into(&full.displacement, &mut modal.displacement);
        self.project_into(&full.velocity, &mut modal.velocity);
        self.project_into(&full.acceleration, &mut modal.acceleration);
    }

    /// Expands a modal state into the full state `full`.
    pub fn expand_kinematics(&self, modal: &Kinematics, full: &mut Kinematics) {
        self.expand_into(&modal.displacement, &mut full.displacement);
        self.expand_into(&modal.velocity, &mut full.velocity);
        self.expand_into(&modal.acceleration, &mut full.acceleration);
    }

    /// Energy (J) of a modal state: (1/2) |q'|^2 + (1/2) sum omega_i^2 q_i^2.
    pub fn energy(&self, q: &[f64], q_dot: &[f64]) -> f64 {
        let kinetic: f64 = q_dot.iter().map(|v| v * v).sum();
        let strain: f64 = q
            .iter()
            .zip(&self.modes.eigenvalues)
            .map(|(qi, w2)| w2 * qi * qi)
            .sum();
        0.5 * (kinetic + strain)
    }
}
