//! Structural models behind one interface: mass M, stiffness K (symmetric banded, clamp
//! eliminated) and the tip observation vector c.
//!
//! The tip's transverse displacement is u_tip = c . u, and a tip force F enters the
//! equations as c F. Because the two use the same vector, the force and the displacement
//! are work-conjugate, and the contact and the integrator never need to know which model
//! they drive.
//!
//! - `beam`: c picks the transverse displacement of the last node.
//! - `plane-stress`: c is the mean transverse displacement of the end face (Simpson
//!   weights on each quadratic edge). Its conjugate is a uniform shear traction on the end
//!   face with resultant F. We use it rather than one node, because a point force on a
//!   continuum has a singular displacement under it: the mid-height node would then
//!   report a deflection that grows without bound as the mesh is refined.
//! - `modal`: c is projected onto the reduced basis (see `modal`).
//!
//! `fidelity` builds the model a scene asks for; `modal` reduces one of these.

use crate::banded::{BandCholesky, NotPositiveDefinite, SymBandMatrix};
use crate::element::{hermite_beam, q8_plane_stress};
use crate::mesh::StripMesh;
use crate::scene::{plane_stress_divisions, CheckedScene, Clamp, FidelityLevel};

/// A linear structural model M u'' + C u' + K u = c F(t).
#[derive(Clone, Debug)]
pub struct StructuralModel {
    /// Fidelity level this model represents.
    pub level: FidelityLevel,
    /// Human-readable resolution, for summaries ("beam, 100 elements").
    pub label: String,
    /// Mass matrix M (kg, or kg m2 for rotations).
    pub mass: SymBandMatrix,
    /// Stiffness matrix K (N/m, ...), same size and bandwidth as M.
    pub stiffness: SymBandMatrix,
    /// Sparse tip observation vector c: (dof, weight) pairs, u_tip = sum w u_dof.
    pub tip: Vec<(usize, f64)>,
    /// A damping matrix C0 from the `[structure]`'s files (N s/m, ...), same size and
    /// bandwidth as M, acting with the scene's Rayleigh damping: C = C0 + a M + b K
    /// (`integrator`). None for every built-in and reduced model.
    pub damping: Option<SymBandMatrix>,
    /// Observation vectors of a `[structure]`'s sensors (`user_structure::Sensor`), in
    /// the section's order, as `tip`: u_sensor = sum w u_dof. Empty for the built-in
    /// models.
    pub sensors: Vec<Observation>,
}

/// A sparse observation vector: (dof, weight) pairs, the value sum w x_dof.
pub type Observation = Vec<(usize, f64)>;

/// The value sum w x_dof of `observation` on `x` (the tip's and the sensors' one rule,
/// so that a sensor at the contact DOF reads the tip's bits).
#[inline]
pub fn observe(observation: &[(usize, f64)], x: &[f64]) -> f64 {
    observation.iter().map(|&(i, w)| w * x[i]).sum()
}

/// A model that could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A matrix that must be positive definite is not.
    #[error("{matrix} matrix is singular: {source}")]
    Singular {
        matrix: &'static str,
        source: NotPositiveDefinite,
    },
    /// The subspace iteration's vectors became linearly dependent, so that the reduced
    /// mass matrix (their Gram matrix in M) is singular.
    #[error("reduced mass matrix is singular: subspace vectors became linearly dependent")]
    DependentSubspace,
    /// More modes were asked for than the full model has.
    #[error(
        "fidelity.modes = {asked} exceeds the {available} degrees of freedom of the full model"
    )]
    TooManyModes { asked: usize, available: usize },
    /// The eigen solver did not converge.
    #[error("eigen solver did not converge in {iterations} iterations")]
    NoConvergence { iterations: usize },
    /// The scene's fidelity level is still `auto`, a request that `auto::resolve` turns
    /// into a concrete level; it names no model.
    #[error("fidelity.level = auto names no model: it must be resolved (stickslip::auto::resolve, which the command line and the FMU call) into modal, beam or plane-stress before a model is built")]
    UnresolvedAuto,
    /// A scene's `[structure]` whose files or DOFs were refused (the message names the
    /// file, the line or the DOF).
    #[error("[structure]: {0}")]
    UserStructure(String),
}

pub(crate) fn singular(matrix: &'static str) -> impl Fn(NotPositiveDefinite) -> ModelError {
    move |source| ModelError::Singular { matrix, source }
}

impl StructuralModel {
    /// Euler-Bernoulli cantilever of `elements` Hermite elements, clamped at x = 0.
    /// Free dofs (w_k, theta_k) for nodes k = 1..=elements.
    pub fn beam(scene: &CheckedScene, elements: usize) -> Self {
        let l = scene.geometry.length / elements as f64;
        let (ke, me) = hermite_beam(l, scene.bending_stiffness(), scene.mass_per_length());
        let n = 2 * elements;
        let mut k = SymBandMatrix::zeros(n, 3);
        let mut m = SymBandMatrix::zeros(n, 3);
        for e in 0..elements {
            // Element dofs 2e..2e+4 in the unconstrained numbering; the clamp removes 0, 1.
            let dof = |a: usize| (2 * e + a).checked_sub(2);
            for a in 0..4 {
                for b in 0..=a {
                    if let (Some(i), Some(j)) = (dof(a), dof(b)) {
                        k.add(i, j, ke[a][b]);
                        m.add(i, j, me[a][b]);
                    }
                }
            }
        }
        Self {
            level: FidelityLevel::Beam,
            label: format!("beam, {elements} elements"),
            mass: m,
            stiffness: k,
            tip: vec![(n - 2, 1.0)],
            damping: None,
            sensors: Vec::new(),
        }
    }

    /// The paper's plane-stress continuum: Q8 mesh with edges no longer than
    /// `element_size`, clamped at x = 0 as the scene says.
    pub fn plane_stress(scene: &CheckedScene, element_size: f64) -> Self {
        Self::plane_stress_clamped(scene, element_size, scene.fidelity.clamp)
    }

    /// Plane-stress model with the given clamp.
    pub fn plane_stress_clamped(scene: &CheckedScene, element_size: f64, clamp: Clamp) -> Self {
        let g = &scene.geometry;
        let mat = &scene.material;
        let (along, through) = plane_stress_divisions(g, element_size);
        let mesh = StripMesh::new(g.length, g.height, along, through);
        // The clamped nodes are the first column and are numbered first. Equation
        // numbers follow node numbers, with the fixed components left out.
        let fixed = |node: usize, comp: usize| match clamp {
            Clamp::Full => mesh.clamped_nodes.contains(&node),
            Clamp::NeutralAxis => {
                mesh.clamped_nodes.contains(&node)
                    && (comp == 0 || node == mesh.clamped_nodes[mesh.clamped_nodes.len() / 2])
            }
        };
        let mut equation = vec![None; 2 * mesh.nodes.len()];
        let mut n = 0;
        for node in 0..mesh.nodes.len() {
            for comp in 0..2 {
                if !fixed(node, comp) {
                    equation[2 * node + comp] = Some(n);
                    n += 1;
                }
            }
        }
        let dof = |node: usize, comp: usize| equation[2 * node + comp];
        let half_bandwidth = mesh
            .elements
            .iter()
            .map(|e| {
                let lo = e.iter().min().unwrap();
                let hi = e.iter().max().unwrap();
                2 * (hi - lo) + 1
            })
            .max()
            .unwrap();
        let mut k = SymBandMatrix::zeros(n, half_bandwidth);
        let mut m = SymBandMatrix::zeros(n, half_bandwidth);
        for conn in &mesh.elements {
            let xy = conn.map(|node| mesh.nodes[node]);
            let (ke, me) = q8_plane_stress(
                &xy,
                g.width,
                mat.youngs_modulus,
                mat.poisson_ratio,
                mat.density,
            );
            for a in 0..16 {
                for b in 0..=a {
                    let i = dof(conn[a / 2], a % 2);
                    let j = dof(conn[b / 2], b % 2);
                    if let (Some(i), Some(j)) = (i, j) {
                        k.add(i, j, ke[a][b]);
                        m.add(i, j, me[a][b]);
                    }
                }
            }
        }
        let tip = mesh
            .tip_face
            .iter()
            .map(|&(node, w)| (dof(node, 1).expect("tip is not clamped"), w))
            .collect();
        Self {
            level: FidelityLevel::PlaneStress,
            label: format!("plane-stress Q8, {along} x {through} elements, {n} dofs"),
            mass: m,
            stiffness: k,
            tip,
            damping: None,
            sensors: Vec::new(),
        }
    }

    /// Number of degrees of freedom.
    pub fn dofs(&self) -> usize {
        self.mass.size()
    }

    /// Tip transverse displacement (or velocity, acceleration) c . x.
    #[inline]
    pub fn tip_value(&self, x: &[f64]) -> f64 {
        observe(&self.tip, x)
    }

    /// Each sensor's value on `x` (displacement, velocity, ...), in the sensors' order.
    pub fn sensor_values(&self, x: &[f64]) -> Vec<f64> {
        self.sensors.iter().map(|s| observe(s, x)).collect()
    }

    /// rhs += c force.
    #[inline]
    pub fn add_tip_force(&self, force: f64, rhs: &mut [f64]) {
        for &(i, w) in &self.tip {
            rhs[i] += w * force;
        }
    }

    /// The vector c as a dense vector.
    pub fn tip_vector(&self) -> Vec<f64> {
        let mut c = vec![0.0; self.dofs()];
        self.add_tip_force(1.0, &mut c);
        c
    }

    /// Factorisation of K.
    pub fn stiffness_factor(&self) -> Result<BandCholesky, ModelError> {
        self.stiffness.cholesky().map_err(singular("stiffness"))
    }

    /// Static displacement under a tip force `force` (N): K u = c F.
    pub fn static_displacement(&self, force: f64) -> Result<Vec<f64>, ModelError> {
        let factor = self.stiffness_factor()?;
        let mut u = vec![0.0; self.dofs()];
        self.add_tip_force(force, &mut u);
        factor.solve_in_place(&mut u);
        // One step of iterative refinement: K is ill-conditioned (cond ~ (L/l)^4), and
        // the residual correction brings the tip deflection to round-off of the answer.
        let mut residual = vec![0.0; self.dofs()];
        self.stiffness.mul_vec(&u, &mut residual);
        residual.iter_mut().for_each(|r| *r = -*r);
        self.add_tip_force(force, &mut residual);
        factor.solve_in_place(&mut residual);
        u.iter_mut().zip(&residual).for_each(|(a, d)| *a += d);
        Ok(u)
    }

    /// Static tip deflection (m) under a tip force `force` (N).
    pub fn static_tip_deflection(&self, force: f64) -> Result<f64, ModelError> {
        Ok(self.tip_value(&self.static_displacement(force)?))
    }
}

/// Euler-Bernoulli tip deflection of the cantilever under tip force `force` (N):
/// delta = P L^3 / (3 EI) = 4 P L^3 / (E b h^3) (the paper's Eq. 2 with b = 1) (m).
pub fn euler_bernoulli_tip_deflection(scene: &CheckedScene, force: f64) -> f64 {
    force / scene.euler_bernoulli_tip_stiffness()
}

/// Timoshenko tip deflection: Euler-Bernoulli plus shear, P L / (kappa G A) with
/// kappa = 5/6 for a rectangle and G = E / (2 (1 + nu)) (m). The plane-stress model with
/// the neutral-axis clamp converges to this value.
pub fn timoshenko_tip_deflection(scene: &CheckedScene, force: f64) -> f64 {
    let g = &scene.geometry;
    let shear_modulus =
        scene.material.youngs_modulus / (2.0 * (1.0 + scene.material.poisson_ratio));
    let area = g.width * g.height;
    euler_bernoulli_tip_deflection(scene, force)
        + force * g.length / (5.0 / 6.0 * shear_modulus * area)
}

/// Number of nodes of the plane-stress Q8 mesh for the scene and element size.
pub fn plane_stress_nodes(scene: &CheckedScene, element_size: f64) -> usize {
    let (nx, ny) = plane_stress_divisions(&scene.geometry, element_size);
    (2 * nx + 1) * (ny + 1) + (nx + 1) * ny
}
