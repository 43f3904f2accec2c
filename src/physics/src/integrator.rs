//! Implicit time integration of M u'' + C u' + K u = c F with Rayleigh damping
//! C = a M + b K, plus a damping matrix C0 from a user's structure's files where the
//! model has one (C = C0 + a M + b K), and one scalar tip force F decided by the
//! contact each step.
//!
//! Both schemes reduce a step to one solve with a constant effective matrix S:
//! x = x_free + F z with S x_free = r (the step without tip force) and z = S^-1 c, both
//! from the one factorisation, which is computed once per (model, dt). The contact then
//! picks F knowing exactly how the tip responds to it (the tip "compliance" c . z): the
//! stick reaction is a Schur complement of the constrained system, with no second
//! factorisation and no reassembly.
//!
//! - Generalised-alpha (Chung and Hulbert, J. Appl. Mech. 60 (1993) 371), unknown
//!   u_{n+1}; the balance holds at t_{n+1-alpha_f} and F is the force at that level.
//!   alpha_m = (2 rho - 1) / (rho + 1), alpha_f = rho / (rho + 1),
//!   gamma = 1/2 - alpha_m + alpha_f, beta = (1 - alpha_m + alpha_f)^2 / 4.
//!   rho_inf = 1 gives alpha_m = alpha_f = 1/2, gamma = 1/2, beta = 1/4: the
//!   trapezoidal rule in the balance at the midpoint, which conserves energy for linear
//!   undamped systems.
//! - Moreau-Jean (Jean, Comput. Methods Appl. Mech. Eng. 177 (1999) 235; Acary, ZAMM
//!   96 (2016) 585), unknown v_{n+1}, theta-method on
//!   M (v_{n+1} - v_n) = h (f - C v - K u)_{n+theta} + c P,
//!   u_{n+1} = u_n + h v_{n+theta}; the tip force acts as an impulse P = h F.

use crate::banded::{BandCholesky, BandPairProduct, SymBandMatrix};
use crate::scene::{CheckedScene, Scheme};
use crate::structure::{singular, ModelError, StructuralModel};

/// Constants of one scheme at one time step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Coefficients {
    GeneralizedAlpha {
        alpha_m: f64,
        alpha_f: f64,
        gamma: f64,
        beta: f64,
    },
    MoreauJean {
        theta: f64,
    },
}

impl Coefficients {
    /// Generalised-alpha coefficients for spectral radius `rho_inf` in [0, 1].
    pub fn generalized_alpha(rho_inf: f64) -> Self {
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        let beta = 0.25 * (1.0 - alpha_m + alpha_f).powi(2);
        Coefficients::GeneralizedAlpha {
            alpha_m,
            alpha_f,
            gamma,
            beta,
        }
    }

    pub fn from_scene(scene: &CheckedScene) -> Self {
        match scene.integrator.scheme {
            Scheme::GeneralizedAlpha => Self::generalized_alpha(scene.integrator.rho_inf),
            Scheme::MoreauJean => Coefficients::MoreauJean {
                theta: scene.integrator.theta,
            },
        }
    }
}

/// Kinematic state of the structure.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Kinematics {
    /// Displacements u (m).
    pub displacement: Vec<f64>,
    /// Velocities u' (m/s).
    pub velocity: Vec<f64>,
    /// Accelerations u'' (m/s2); used by generalised-alpha only.
    pub acceleration: Vec<f64>,
}

impl Kinematics {
    pub fn at_rest(n: usize) -> Self {
        Self {
            displacement: vec![0.0; n],
            velocity: vec![0.0; n],
            acceleration: vec![0.0; n],
        }
    }
}

/// One scheme set up for one model and one time step: the factorised effective matrix
/// and the tip response z = S^-1 c.
pub struct Integrator {
    coefficients: Coefficients,
    dt: f64,
    mass_damping: f64,
    stiffness_damping: f64,
    factor: BandCholesky,
    tip_response: Vec<f64>,
    /// c . z: the tip's unknown (displacement or velocity) per unit tip force.
    tip_compliance: f64,
    /// M p + K q in one fused pass; p and q are written straight into its inputs.
    product: BandPairProduct,
    free: Vec<f64>,
    /// The model's damping matrix C0 with its input and product buffers, when it has one
    /// and this integrator damps.
    matrix_damping: Option<MatrixDamping>,
}

/// A damping matrix C0 in the step: its input x and the product C0 x.
struct MatrixDamping {
    matrix: SymBandMatrix,
    input: Vec<f64>,
    product: Vec<f64>,
}

/// The step without tip force, and how the tip responds to a force: what the contact
/// resolves the step's tip force from (`contact::Contact::resolve`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrialStep {
    /// Length of the step (s).
    pub dt: f64,
    /// Tip displacement at t_n, the start of the step (m).
    pub start_tip_displacement: f64,
    /// Tip velocity at t_n (m/s).
    pub start_tip_velocity: f64,
    /// Tip displacement at t_{n+1} with F = 0 (m).
    pub free_tip_displacement: f64,
    /// Tip velocity at t_{n+1} with F = 0 (m/s).
    pub free_tip_velocity: f64,
    /// d(tip displacement_{n+1}) / dF (m/N).
    pub displacement_per_force: f64,
    /// d(tip velocity_{n+1}) / dF (m/(s N)).
    pub velocity_per_force: f64,
}

impl Integrator {
    /// Factorises the effective matrix of `model` for time step `dt` (s) with Rayleigh
    /// coefficients a = `mass_damping` (1/s), b = `stiffness_damping` (s), and the
    /// model's damping matrix C0 when it has one.
    pub fn new(
        model: &StructuralModel,
        coefficients: Coefficients,
        dt: f64,
        mass_damping: f64,
        stiffness_damping: f64,
    ) -> Result<Self, ModelError> {
        Self::build(
            model,
            coefficients,
            dt,
            (mass_damping, stiffness_damping),
            model.damping.as_ref(),
        )
    }

    /// [`Self::new`] without any damping: no Rayleigh terms and the model's damping
    /// matrix left out (the stick phase of `contact.damping_phase = slip`).
    pub fn undamped(
        model: &StructuralModel,
        coefficients: Coefficients,
        dt: f64,
    ) -> Result<Self, ModelError> {
        Self::build(model, coefficients, dt, (0.0, 0.0), None)
    }

    fn build(
        model: &StructuralModel,
        coefficients: Coefficients,
        dt: f64,
        (a, b): (f64, f64),
        damping_matrix: Option<&SymBandMatrix>,
    ) -> Result<Self, ModelError> {
        // The factor of C0 in the effective matrix: that of C in it, whose Rayleigh
        // part is folded into the factors of M and K.
        let c_scale = match coefficients {
            Coefficients::GeneralizedAlpha {
                alpha_f,
                gamma,
                beta,
                ..
            } => (1.0 - alpha_f) * gamma / (beta * dt),
            Coefficients::MoreauJean { theta } => dt * theta,
        };
        let (s_mass, s_stiffness) = match coefficients {
            Coefficients::GeneralizedAlpha {
                alpha_m,
                alpha_f,
                gamma,
                beta,
            } => {
                // S = (1 - am)/(beta dt^2) M + (1 - af) gamma/(beta dt) C + (1 - af) K
                let c_damp = (1.0 - alpha_f) * gamma / (beta * dt);
                (
                    (1.0 - alpha_m) / (beta * dt * dt) + a * c_damp,
                    (1.0 - alpha_f) + b * c_damp,
                )
            }
            // W = M + h theta C + h^2 theta^2 K
            Coefficients::MoreauJean { theta } => (
                1.0 + dt * theta * a,
                dt * theta * b + dt * dt * theta * theta,
            ),
        };
        let mut effective: SymBandMatrix =
            model
                .mass
                .linear_combination(s_mass, &model.stiffness, s_stiffness);
        if let Some(c0) = damping_matrix {
            effective = effective.linear_combination(1.0, c0, c_scale);
        }
        let factor = effective.cholesky().map_err(singular("effective"))?;
        let n = model.dofs();
        let mut tip_response = vec![0.0; n];
        model.add_tip_force(1.0, &mut tip_response);
        factor.solve_in_place(&mut tip_response);
        let tip_compliance = model.tip_value(&tip_response);
        Ok(Self {
            coefficients,
            dt,
            mass_damping: a,
            stiffness_damping: b,
            factor,
            tip_response,
            tip_compliance,
            product: BandPairProduct::new(&model.mass, &model.stiffness),
            free: vec![0.0; n],
            matrix_damping: damping_matrix.map(|c0| MatrixDamping {
                matrix: c0.clone(),
                input: vec![0.0; n],
                product: vec![0.0; n],
            }),
        })
    }

    pub fn coefficients(&self) -> Coefficients {
        self.coefficients
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The Rayleigh coefficients (a in 1/s, b in s) this integrator was factorised with.
    pub fn damping(&self) -> (f64, f64) {
        (self.mass_damping, self.stiffness_damping)
    }

    /// The step from `state` without tip force, kept internally for [`Self::finish`].
    /// No allocation.
    pub fn trial(&mut self, model: &StructuralModel, state: &Kinematics) -> TrialStep {
        let dt = self.dt;
        let (a, b) = (self.mass_damping, self.stiffness_damping);
        let (u, v, acc) = (&state.displacement, &state.velocity, &state.acceleration);
        let (p, q) = self.product.inputs();
        match self.coefficients {
            Coefficients::GeneralizedAlpha {
                alpha_m,
                alpha_f,
                gamma,
                beta,
            } => {
                // r = M (m~ + a c~) + K (b c~ - af u_n), with
                // m~ = (1-am)/(beta dt^2)(u + dt v) + ((1-am)(1/2-beta)/beta - am) a_n,
                // c~ = (1-af) gamma/(beta dt) u - ((1-af)(1 - gamma/beta) + af) v
                //      - (1-af) dt (1 - gamma/(2 beta)) a_n.
                let m1 = (1.0 - alpha_m) / (beta * dt * dt);
                let m2 = (1.0 - alpha_m) * (0.5 - beta) / beta - alpha_m;
                let c0 = (1.0 - alpha_f) * gamma / (beta * dt);
                let c1 = (1.0 - alpha_f) * (1.0 - gamma / beta) + alpha_f;
                let c2 = (1.0 - alpha_f) * dt * (1.0 - gamma / (2.0 * beta));
                for ((pi, qi), ((ui, vi), ai)) in
                    p.iter_mut().zip(q.iter_mut()).zip(u.iter().zip(v).zip(acc))
                {
                    let c_tilde = c0 * ui - c1 * vi - c2 * ai;
                    *pi = m1 * (ui + dt * vi) + m2 * ai + a * c_tilde;
                    *qi = b * c_tilde - alpha_f * ui;
                }
                // ... + C0 c~.
                if let Some(d) = &mut self.matrix_damping {
                    for (xi, ((ui, vi), ai)) in d.input.iter_mut().zip(u.iter().zip(v).zip(acc)) {
                        *xi = c0 * ui - c1 * vi - c2 * ai;
                    }
                }
            }
            Coefficients::MoreauJean { theta } => {
                // r = M v (1 - h (1-theta) a) + K (-h u - (h (1-theta) b + h^2 theta (1-theta)) v)
                let mv = 1.0 - dt * (1.0 - theta) * a;
                let kv = dt * (1.0 - theta) * b + dt * dt * theta * (1.0 - theta);
                for ((pi, qi), (ui, vi)) in p.iter_mut().zip(q.iter_mut()).zip(u.iter().zip(v)) {
                    *pi = mv * vi;
                    *qi = -dt * ui - kv * vi;
                }
                // ... - h (1 - theta) C0 v.
                if let Some(d) = &mut self.matrix_damping {
                    for (xi, vi) in d.input.iter_mut().zip(v) {
                        *xi = -dt * (1.0 - theta) * vi;
                    }
                }
            }
        }
        self.product.apply(&mut self.free);
        if let Some(d) = &mut self.matrix_damping {
            d.matrix.mul_vec(&d.input, &mut d.product);
            self.free
                .iter_mut()
                .zip(&d.product)
                .for_each(|(f, c)| *f += c);
        }
        self.factor.solve_in_place(&mut self.free);
        let tip_free = model.tip_value(&self.free);
        let tip_u = model.tip_value(u);
        let tip_v = model.tip_value(v);
        let tip_a = model.tip_value(acc);
        match self.coefficients {
            Coefficients::GeneralizedAlpha { gamma, beta, .. } => {
                let g = gamma / (beta * dt);
                TrialStep {
                    dt,
                    start_tip_displacement: tip_u,
                    start_tip_velocity: tip_v,
                    free_tip_displacement: tip_free,
                    free_tip_velocity: g * (tip_free - tip_u)
                        + (1.0 - gamma / beta) * tip_v
                        + dt * (1.0 - gamma / (2.0 * beta)) * tip_a,
                    displacement_per_force: self.tip_compliance,
                    velocity_per_force: g * self.tip_compliance,
                }
            }
            Coefficients::MoreauJean { theta } => TrialStep {
                dt,
                start_tip_displacement: tip_u,
                start_tip_velocity: tip_v,
                free_tip_displacement: tip_u + dt * ((1.0 - theta) * tip_v + theta * tip_free),
                free_tip_velocity: tip_free,
                // P = dt F, so the velocity moves by (c . z) dt per newton.
                displacement_per_force: dt * dt * theta * self.tip_compliance,
                velocity_per_force: dt * self.tip_compliance,
            },
        }
    }

    /// Completes the step of the last [`Self::trial`] with tip force `force` (N),
    /// updating `state` in place. No allocation.
    pub fn finish(&mut self, state: &mut Kinematics, force: f64) {
        let dt = self.dt;
        let impulse_scale = match self.coefficients {
            Coefficients::GeneralizedAlpha { .. } => force,
            Coefficients::MoreauJean { .. } => force * dt,
        };
        for (x, z) in self.free.iter_mut().zip(&self.tip_response) {
            *x += impulse_scale * z;
        }
        let k = state;
        match self.coefficients {
            Coefficients::GeneralizedAlpha { gamma, beta, .. } => {
                for (&u_new, ((u, v), a)) in self.free.iter().zip(
                    k.displacement
                        .iter_mut()
                        .zip(k.velocity.iter_mut())
                        .zip(k.acceleration.iter_mut()),
                ) {
                    let a_new =
                        (u_new - *u - dt * *v) / (beta * dt * dt) - (0.5 - beta) / beta * *a;
                    *v += dt * ((1.0 - gamma) * *a + gamma * a_new);
                    *a = a_new;
                    *u = u_new;
                }
            }
            Coefficients::MoreauJean { theta } => {
                for (&v_new, ((u, v), a)) in self.free.iter().zip(
                    k.displacement
                        .iter_mut()
                        .zip(k.velocity.iter_mut())
                        .zip(k.acceleration.iter_mut()),
                ) {
                    *u += dt * ((1.0 - theta) * *v + theta * v_new);
                    *a = (v_new - *v) / dt;
                    *v = v_new;
                }
            }
        }
    }
}
