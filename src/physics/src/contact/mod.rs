//! Stick/slip contact of the beam tip on the belt, for both integration schemes: the
//! stick reaction, the slip solve and the switch all live here. A time step reads: the
//! integrator's trial step without tip force, then [`Contact::resolve`] on it, then the
//! integrator's finish with the force resolved here.
//!
//! The tip responds linearly to the tip force F (see `integrator`), so the trial step
//! tells the contact everything: u_tip,n+1(F) = u_free + F du/dF and
//! v_tip,n+1(F) = v_free + F dv/dF.
//!
//! - **Stick reaction.** F is the reaction that makes the tip move with the belt, a
//!   Schur complement of the constrained system through the one factorisation. The
//!   holding force F_hold compared with mu_s F_n is that reaction, or, with
//!   `holding_force = "euler-bernoulli"`, the paper's literal rule
//!   P = E h^3 delta / (4 L^3) = 3 EI delta / L^3 (b = 1) at the deflection stick gives.
//! - **Slip solve.** F = F_law(x(F)) is implicit, since the law's argument x (v_rel at
//!   the law's time level) depends on F, affinely: x = x_0 + x' F. It is solved by a
//!   safeguarded Newton iteration on r(F) = F - F_law(x(F)), with the law's exact slope
//!   dF_law/dv from the same evaluation ([`FrictionLaw::sliding_force_and_slope`](crate::friction::FrictionLaw::sliding_force_and_slope)):
//!   r' = 1 - F_law' x'. Where the problem is well posed (|F_law' x'| < 1, the
//!   condition under which the implicit step has one solution) r increases with F, so
//!   every evaluated F also brackets the root, and a Newton step that leaves the
//!   bracket is replaced by bisection. The law jumps at x = 0 (sign(v) times a
//!   magnitude): there r jumps up by twice the force at v -> 0, and when zero lies in
//!   that jump the equation has no solution on either side. The slip force is then the
//!   F at which x = 0, inside [F_law(0-), F_law(0+)]: the solution of the set-valued law
//!   (Filippov), and the switch decides (`jump`; either side's force instead put a
//!   spurious -mu_s F_n on the tip for a step, issue 37). Newton converges quadratically, 2 evaluations
//!   for a typical slip step, 3 at the reversals, where the fixed-point iteration
//!   F <- F_law(x(F)) of earlier versions ([`SlipSolver::FixedPoint`], kept as the
//!   reference) took 6 to 7 with the analytical law at the paper's step and did not
//!   converge where |F_law' x'| > 1 (the plain network's steep zero crossing).
//! - **Switch.** Which of the two forces the step takes.
//!
//! The contact is posed the way the integrator's scheme is, chosen once at construction:
//!
//! - **Generalised-alpha: Karnopp's model with Leine's switch logic** (Karnopp, J. Dyn.
//!   Syst. Meas. Control 107 (1985) 100; Leine, van Campen, de Kraker, van den Steen,
//!   Nonlinear Dynamics 16 (1998) 41). Stick holds the tip displacement on the belt,
//!   u_tip,n+1 = u_tip,n + v_b dt (the paper's Eq. 4). The law is evaluated at
//!   v_rel(t_{n+1-alpha_f}), the time level at which the scheme's balance holds and F
//!   acts. Stick -> slip when |F_hold| > mu_s F_n. Slip -> stick when (|v_rel| < eps or
//!   v_rel changed sign) and |F_hold| <= mu_s F_n, with v_rel at t_{n+1} as the slip
//!   solution of this step gives it.
//!   Two options follow the paper authors' script (docs/paper-authors-scene.md):
//!   `first_slip_step = "free"` takes F = 0 over the step that leaves stick, and
//!   `slip_force = "lagged"` takes F_n+1 = F_law(x_n), the law at the argument the
//!   previous step ended with, instead of the implicit solve, on every step that starts
//!   in slip (a loaded first slip step stays implicit: before it there is no slip
//!   velocity to lag). The switch is the same: re-stick looks at v_rel,n+1 under the
//!   force the step takes, lagged or not.
//! - **Moreau-Jean: impulse level** (Jean, Comput. Methods Appl. Mech. Eng. 177 (1999)
//!   235; Acary, ZAMM 96 (2016) 585). Stick holds the tip velocity at the belt's,
//!   v_tip,n+1 = v_b, with the impulse P = F dt. Stick when the impulse stick needs lies
//!   in [-mu_s F_n dt, mu_s F_n dt], whatever the state before; otherwise slip with the
//!   law's impulse, evaluated at t_{n+1}. No threshold eps. The clamp acts on the
//!   reaction impulse itself: `holding_force = "euler-bernoulli"` changes the reported
//!   holding force only.
//!
//! Traps of the switch (see the project's physics notes):
//! - **One holding force for both switches**, the reaction of the same discrete balance
//!   the integrator uses. If stick -> slip used K u and slip -> stick the full dynamic
//!   reaction (inertia and damping included), the two thresholds would differ and the
//!   contact would chatter between stick and slip every step.
//! - **eps against |a| dt.** A velocity threshold eps below the change of v_rel over one
//!   step, |a| dt, lets v_rel jump across the band |v_rel| < eps and the slip -> stick
//!   crossing is missed. The sign-change test removes that dependence (eps = 0 works).
//! - **Re-stick must be admissible.** Without |F_hold| <= mu_s F_n the contact re-sticks
//!   the very step after breakaway, when v_rel is still ~0, and never really slips: it
//!   switches every step (the paper's literal rule "stick when |v_s| < eps"; in a 1-DOF
//!   run, 3 908 switches that dragged the tip to 23.5 mm).
//!
//! **Laws with state** (`crate::friction::state`: LuGre, rate-and-state) have no set-valued stick
//! and take neither switch: every step is a slip solve with the law's trial step over dt
//! (its state advanced inside, the exact total slope), and the state is committed at the
//! accepted velocity; `stick` then means |v_rel,n+1| < eps (`state_law`,
//! docs/friction-with-memory.md).
//!
//! Here: the `Contact` of a scene and its two formulations. Its parts: `state` (stick or
//! slip between steps), `stick` (the reaction and F_hold), `switch` (the two schemes'
//! rules), `kinetic` (where the kinetic force comes from), `slip` (the solve and its
//! choice of solver) with `argument` (x(F)), `limits`, `newton`, `fixed_point` and
//! `tangent` (the solvers), `jump` (the force where the equation has no solution), and
//! `state_law` (the step of a law with state). Imports run one way, from here down to
//! those parts.

mod argument;
mod fixed_point;
mod jump;
mod kinetic;
mod limits;
mod newton;
mod slip;
mod state;
mod state_law;
mod stick;
mod switch;
mod tangent;

pub use kinetic::{Direction, Kinetic};
pub use limits::{SLIP_ITERATIONS, SLIP_TOLERANCE};
pub use slip::{SlipSolve, SlipSolver};
pub use state::{ContactState, Previous, Transition};
pub use switch::{impulse_clamp, next_state};

use crate::integrator::{Coefficients, TrialStep};
use crate::scene::{CheckedScene, FirstSlipStep, SlipForce};
use slip::SlipOptions;
use stick::{Holding, StickReaction};

/// What the contact decided for one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolution {
    /// Contact state at the end of the step.
    pub state: ContactState,
    /// Tip force F (N) to finish the step with: the stick reaction in stick, the kinetic
    /// friction force in slip (at generalised-alpha's level t_{n+1-alpha_f}).
    pub force: f64,
    /// Holding force F_hold (N): what stick needs this step, the quantity compared with
    /// mu_s F_n (for Moreau-Jean, see the module notes).
    pub holding_force: f64,
    /// The slip solve, if the step needed one (whatever state it then took).
    pub slip: Option<SlipSolve>,
}

/// How the contact is posed, fixed by the integrator's scheme.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Formulation {
    /// Stick at displacement level, Leine's switch, the law at t_{n+1-alpha_f}.
    GeneralizedAlpha { alpha_f: f64 },
    /// Stick at velocity level, the impulse clamp, the law at t_{n+1}.
    MoreauJean,
}

/// The tip contact of one scene under one integration scheme.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    formulation: Formulation,
    holding: Holding,
    slip: SlipOptions,
    /// The tip force over the step that leaves stick.
    first_slip_step: FirstSlipStep,
    /// eps (m/s).
    stick_threshold: f64,
}

impl Contact {
    /// The contact options of `scene` posed for the scheme of `coefficients` (those of
    /// the integrator that will step it).
    pub fn new(scene: &CheckedScene, coefficients: Coefficients) -> Self {
        let formulation = match coefficients {
            Coefficients::GeneralizedAlpha { alpha_f, .. } => {
                Formulation::GeneralizedAlpha { alpha_f }
            }
            Coefficients::MoreauJean { .. } => Formulation::MoreauJean,
        };
        Self {
            formulation,
            holding: Holding {
                kind: scene.contact.holding_force,
                euler_bernoulli_stiffness: scene.euler_bernoulli_tip_stiffness(),
            },
            slip: SlipOptions {
                sliding_velocity: scene.contact.sliding_velocity,
                solver: SlipSolver::default(),
                force: scene.contact.slip_force,
            },
            first_slip_step: scene.contact.first_slip_step,
            stick_threshold: scene.friction.stick_threshold,
        }
    }

    /// Solves the slip force with `solver` from now on (the default is Newton).
    pub fn set_slip_solver(&mut self, solver: SlipSolver) {
        self.slip.solver = solver;
    }

    /// Decides the tip force of the step whose force-free `trial` the integrator just
    /// made, from the contact `previous` left, at belt speed `belt_speed` (m/s), with
    /// the static limit `static_limit` = mu_s F_n (N) and the kinetic friction `kinetic`.
    pub fn resolve(
        &self,
        trial: &TrialStep,
        previous: Previous,
        belt_speed: f64,
        static_limit: f64,
        kinetic: Kinetic<'_>,
    ) -> Resolution {
        match self.formulation {
            Formulation::GeneralizedAlpha { alpha_f } => self.resolve_generalized_alpha(
                trial,
                previous,
                belt_speed,
                static_limit,
                kinetic,
                alpha_f,
            ),
            Formulation::MoreauJean => {
                self.resolve_moreau_jean(trial, previous, belt_speed, static_limit, kinetic)
            }
        }
    }

    /// Karnopp/Leine at displacement level. In slip the slip solve comes first, since
    /// re-stick looks at the v_rel it gives; in stick it is needed only on breakaway.
    fn resolve_generalized_alpha(
        &self,
        trial: &TrialStep,
        previous: Previous,
        belt_speed: f64,
        static_limit: f64,
        mut kinetic: Kinetic<'_>,
        alpha_f: f64,
    ) -> Resolution {
        let stick = StickReaction::displacement_level(trial, belt_speed);
        let holding_force = self.holding.force(&stick);
        let (state, force, slip) = match previous.state {
            ContactState::Stick => {
                match next_state(
                    ContactState::Stick,
                    holding_force,
                    static_limit,
                    0.0,
                    0.0,
                    0.0,
                ) {
                    ContactState::Stick => (ContactState::Stick, stick.force, None),
                    ContactState::Slip if self.first_slip_step == FirstSlipStep::Free => {
                        (ContactState::Slip, 0.0, None)
                    }
                    ContactState::Slip => {
                        // The step that leaves stick has no slip velocity before it to
                        // lag the force behind (v_rel,n ~ 0 in stick, its sign
                        // rounding), so a loaded first step is solved implicitly.
                        let first = SlipOptions {
                            force: SlipForce::Implicit,
                            ..self.slip
                        };
                        let slip = first.solve(trial, previous, belt_speed, &mut kinetic, alpha_f);
                        (ContactState::Slip, slip.force, Some(slip.solve))
                    }
                }
            }
            ContactState::Slip => {
                let slip = self
                    .slip
                    .solve(trial, previous, belt_speed, &mut kinetic, alpha_f);
                match next_state(
                    ContactState::Slip,
                    holding_force,
                    static_limit,
                    previous.relative_velocity,
                    slip.relative_velocity,
                    self.stick_threshold,
                ) {
                    ContactState::Stick => (ContactState::Stick, stick.force, Some(slip.solve)),
                    ContactState::Slip => (ContactState::Slip, slip.force, Some(slip.solve)),
                }
            }
        };
        Resolution {
            state,
            force,
            holding_force,
            slip,
        }
    }

    /// Acary's impulse-level contact: the clamp decides from the reaction alone.
    fn resolve_moreau_jean(
        &self,
        trial: &TrialStep,
        previous: Previous,
        belt_speed: f64,
        static_limit: f64,
        mut kinetic: Kinetic<'_>,
    ) -> Resolution {
        let stick = StickReaction::velocity_level(trial, belt_speed);
        let holding_force = self.holding.force(&stick);
        let (state, force, slip) = match impulse_clamp(stick.force, static_limit) {
            ContactState::Stick => (ContactState::Stick, stick.force, None),
            ContactState::Slip => {
                // Moreau-Jean's law level is t_{n+1}: no weight on t_n.
                let slip = self
                    .slip
                    .solve(trial, previous, belt_speed, &mut kinetic, 0.0);
                (ContactState::Slip, slip.force, Some(slip.solve))
            }
        };
        Resolution {
            state,
            force,
            holding_force,
            slip,
        }
    }
}
