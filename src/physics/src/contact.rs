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
//!   dF_law/dv from the same evaluation ([`FrictionLaw::sliding_force_and_slope`]):
//!   r' = 1 - F_law' x'. Where the problem is well posed (|F_law' x'| < 1, the
//!   condition under which the implicit step has one solution) r increases with F, so
//!   every evaluated F also brackets the root, and a Newton step that leaves the
//!   bracket is replaced by bisection. The law jumps at x = 0 (sign(v) times a
//!   magnitude): there r jumps up by twice the force at v -> 0, and when zero lies in
//!   that jump the equation has no solution on either side. The slip force is then the
//!   F at which x = 0, inside [F_law(0-), F_law(0+)]: the solution of the set-valued law
//!   (Filippov), and the switch decides. Newton converges quadratically, 2 evaluations
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

use crate::friction::{signum_or_zero, FrictionLaw};
use crate::integrator::{Coefficients, TrialStep};
use crate::scene::{CheckedScene, HoldingForce, SlidingVelocity};
use serde::{Deserialize, Serialize};

/// Most law evaluations of one slip solve: Newton needs 1 to 3 and the fixed-point
/// reference 6 to 15 where it converges; a guard, not a tuning knob.
const SLIP_ITERATIONS: usize = 50;

/// Convergence of the slip force: the last correction |dF| <= SLIP_TOLERANCE (1 + |F|)
/// (N). For Newton the correction estimates the error of the iterate it starts from, and
/// the iterate it gives is closer still (quadratic convergence).
pub const SLIP_TOLERANCE: f64 = 1e-12;

/// How the slip force F = F_law(x(F)) is solved (see the module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SlipSolver {
    /// Safeguarded Newton with the law's exact slope: 1 to 3 evaluations per slip step.
    #[default]
    Newton,
    /// The fixed-point iteration F <- F_law(x(F)) of earlier versions, kept as the
    /// reference the Newton solve is tested against (tests/physics/slip_solve.rs).
    FixedPoint,
}

/// Contact state of the tip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactState {
    Stick,
    Slip,
}

/// A change of contact state at time `time` (s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Transition {
    pub time: f64,
    pub to: ContactState,
}

/// The contact as the last step left it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Previous {
    pub state: ContactState,
    /// v_rel = v_b - v_tip at t_n (m/s), as the last step ended.
    pub relative_velocity: f64,
    /// Tip force of the last step (N); the slip iteration starts from it.
    pub force: f64,
}

/// Where the kinetic friction force of a step comes from.
pub enum Kinetic<'a> {
    /// The scene's law F_law(v, F_n) at normal force `normal_force` (N).
    Law {
        law: &'a mut dyn FrictionLaw,
        normal_force: f64,
    },
    /// A coupled friction model: magnitude `force` (N), held over the step, in the
    /// direction of the sliding velocity.
    External { force: f64 },
    /// A coupled friction model with a signed law F(v), known by its value `force` (N)
    /// and slope `slope` = dF/dv (N s/m) at the sliding velocity `velocity` (m/s) it was
    /// evaluated at, all held over the step. The step's force is the law's tangent
    /// F(v) ~ force + slope (v - velocity) at the step's own sliding velocity, solved
    /// implicitly like the scene's law, and acting along v_rel where the tangent points
    /// against it (see `Contact::slip_tangent`). With slope 0 it is the held force, or
    /// its magnitude along v_rel.
    ExternalSigned {
        force: f64,
        slope: f64,
        velocity: f64,
    },
}

impl Kinetic<'_> {
    /// Signed kinetic force (N) at sliding velocity `v` (m/s).
    fn force(&mut self, v: f64) -> f64 {
        match self {
            Kinetic::Law { law, normal_force } => law.sliding_force(v, *normal_force),
            Kinetic::External { force } => signum_or_zero(v) * *force,
            Kinetic::ExternalSigned {
                force,
                slope,
                velocity,
            } => *force + *slope * (v - *velocity),
        }
    }

    /// The law's resolution (N, see [`FrictionLaw::resolution`]).
    fn resolution(&self) -> f64 {
        match self {
            Kinetic::Law { law, .. } => law.resolution(),
            Kinetic::External { .. } | Kinetic::ExternalSigned { .. } => 0.0,
        }
    }

    /// The force (N) and its slope dF/dv (N s/m) at `v` (m/s).
    fn force_and_slope(&mut self, v: f64) -> (f64, f64) {
        match self {
            Kinetic::Law { law, normal_force } => law.sliding_force_and_slope(v, *normal_force),
            Kinetic::External { force } => (signum_or_zero(v) * *force, 0.0),
            Kinetic::ExternalSigned {
                force,
                slope,
                velocity,
            } => (*force + *slope * (v - *velocity), *slope),
        }
    }
}

/// The kinetic force of one slip solve, counting its evaluations.
struct CountedLaw<'a, 'k> {
    kinetic: &'a mut Kinetic<'k>,
    evaluations: usize,
}

impl CountedLaw<'_, '_> {
    fn force(&mut self, v: f64) -> f64 {
        self.evaluations += 1;
        self.kinetic.force(v)
    }

    fn force_and_slope(&mut self, v: f64) -> (f64, f64) {
        self.evaluations += 1;
        self.kinetic.force_and_slope(v)
    }
}

/// How the slip solve of a step went.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SlipSolve {
    /// Evaluations of the law (value, or value and slope: one pass each).
    pub evaluations: usize,
    /// Whether F = F_law(x(F)) was solved. False when it has no solution (zero in the
    /// law's jump; the force is then the fixed-point iteration's, see the module notes)
    /// or the solver stopped at its limit of evaluations.
    pub solved: bool,
}

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
    holding_force: HoldingForce,
    /// 3 EI / L^3 (N/m), for `HoldingForce::EulerBernoulli`.
    euler_bernoulli_stiffness: f64,
    sliding_velocity: SlidingVelocity,
    /// eps (m/s).
    stick_threshold: f64,
    solver: SlipSolver,
}

/// The stick reaction of a step: the force that keeps the tip with the belt (N) and the
/// tip displacement at t_{n+1} under it (m).
struct StickReaction {
    force: f64,
    tip_displacement: f64,
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
            holding_force: scene.contact.holding_force,
            euler_bernoulli_stiffness: scene.euler_bernoulli_tip_stiffness(),
            sliding_velocity: scene.contact.sliding_velocity,
            stick_threshold: scene.friction.stick_threshold,
            solver: SlipSolver::default(),
        }
    }

    /// Solves the slip force with `solver` from now on (the default is Newton).
    pub fn set_slip_solver(&mut self, solver: SlipSolver) {
        self.solver = solver;
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
        // u_tip,n+1 = u_tip,n + v_b dt.
        let target = trial.start_tip_displacement + belt_speed * trial.dt;
        let stick = StickReaction {
            force: (target - trial.free_tip_displacement) / trial.displacement_per_force,
            tip_displacement: target,
        };
        let holding_force = self.holding(&stick);
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
                    ContactState::Slip => {
                        let slip = self.slip(trial, previous, belt_speed, &mut kinetic, alpha_f);
                        (ContactState::Slip, slip.force, Some(slip.solve))
                    }
                }
            }
            ContactState::Slip => {
                let slip = self.slip(trial, previous, belt_speed, &mut kinetic, alpha_f);
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
        // v_tip,n+1 = v_b; the displacement follows through u_{n+1} = u_n + h v_{n+theta}.
        let force = (belt_speed - trial.free_tip_velocity) / trial.velocity_per_force;
        let stick = StickReaction {
            force,
            tip_displacement: trial.free_tip_displacement + force * trial.displacement_per_force,
        };
        let holding_force = self.holding(&stick);
        let (state, force, slip) = match impulse_clamp(stick.force, static_limit) {
            ContactState::Stick => (ContactState::Stick, stick.force, None),
            ContactState::Slip => {
                // Moreau-Jean's law level is t_{n+1}: no weight on t_n.
                let slip = self.slip(trial, previous, belt_speed, &mut kinetic, 0.0);
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

    /// F_hold (N) of a stick reaction, as the scene's `holding_force` asks.
    fn holding(&self, stick: &StickReaction) -> f64 {
        match self.holding_force {
            HoldingForce::Reaction => stick.force,
            // The paper's rule, P = E h^3 delta / (4 L^3) = 3 EI delta / L^3 for b = 1.
            HoldingForce::EulerBernoulli => self.euler_bernoulli_stiffness * stick.tip_displacement,
        }
    }

    /// The slip force F = F_law(x(F)), solved from the last step's force, and v_rel at
    /// t_{n+1} under it.
    ///
    /// The law sees v_rel at t_{n+1-alpha_f}, (1 - alpha_f) v_rel,n+1 + alpha_f v_rel,n;
    /// with `sliding_velocity = "tip"` it sees |v_tip| at that level instead, in the
    /// direction of v_rel (otherwise there is no stick-slip).
    fn slip(
        &self,
        trial: &TrialStep,
        previous: Previous,
        belt_speed: f64,
        kinetic: &mut Kinetic<'_>,
        alpha_f: f64,
    ) -> Slip {
        let argument = SlipArgument {
            belt_speed,
            free_tip_velocity: trial.free_tip_velocity,
            velocity_per_force: trial.velocity_per_force,
            alpha_f,
            previous_relative_velocity: previous.relative_velocity,
            start_tip_velocity: trial.start_tip_velocity,
            sliding_velocity: self.sliding_velocity,
        };
        let mut law = CountedLaw {
            kinetic,
            evaluations: 0,
        };
        let (force, solved) = match (&*law.kinetic, self.solver) {
            (
                Kinetic::ExternalSigned {
                    force,
                    slope,
                    velocity,
                },
                _,
            ) => {
                let tangent = Tangent {
                    force: *force,
                    slope: *slope,
                    velocity: *velocity,
                };
                tangent_newton(&argument, tangent, &mut law)
            }
            (_, SlipSolver::Newton) => newton(&argument, previous.force, &mut law),
            (_, SlipSolver::FixedPoint) => fixed_point(&argument, previous.force, &mut law),
        };
        Slip {
            force,
            relative_velocity: argument.relative_velocity(force),
            solve: SlipSolve {
                evaluations: law.evaluations,
                solved,
            },
        }
    }
}

/// The result of a slip solve.
struct Slip {
    /// Tip force F (N).
    force: f64,
    /// v_rel at t_{n+1} (m/s) under it.
    relative_velocity: f64,
    solve: SlipSolve,
}

/// The law's argument x during one slip step as a function of the tip force F: the
/// tip responds linearly, v_tip,n+1 = v_free + F dv/dF.
struct SlipArgument {
    belt_speed: f64,
    free_tip_velocity: f64,
    velocity_per_force: f64,
    alpha_f: f64,
    /// v_rel,n (m/s).
    previous_relative_velocity: f64,
    /// v_tip,n (m/s).
    start_tip_velocity: f64,
    sliding_velocity: SlidingVelocity,
}

impl SlipArgument {
    /// v_rel at t_{n+1} (m/s) under the tip force `force` (N).
    fn relative_velocity(&self, force: f64) -> f64 {
        self.belt_speed - (self.free_tip_velocity + force * self.velocity_per_force)
    }

    /// The law's argument under `force` (N).
    fn at(&self, force: f64) -> Point {
        let alpha_f = self.alpha_f;
        let v_tip = self.free_tip_velocity + force * self.velocity_per_force;
        let v_rel = self.belt_speed - v_tip;
        let rel_eval = (1.0 - alpha_f) * v_rel + alpha_f * self.previous_relative_velocity;
        let direction = signum_or_zero(rel_eval);
        match self.sliding_velocity {
            SlidingVelocity::Relative => Point {
                force,
                x: rel_eval,
                slope: -(1.0 - alpha_f) * self.velocity_per_force,
                direction,
            },
            SlidingVelocity::Tip => {
                let tip = (1.0 - alpha_f) * v_tip + alpha_f * self.start_tip_velocity;
                Point {
                    force,
                    x: direction * tip.abs(),
                    slope: direction
                        * signum_or_zero(tip)
                        * (1.0 - alpha_f)
                        * self.velocity_per_force,
                    direction,
                }
            }
        }
    }

    /// The direction of sliding, sign(v_rel) at the law's level, where F is above the
    /// reversal force: d v_rel / dF = -(1 - alpha_f) dv/dF.
    fn direction_above(&self) -> f64 {
        -((1.0 - self.alpha_f) * self.velocity_per_force).signum()
    }

    /// The force (N) at which the direction of sliding reverses (v_rel at the law's
    /// level is 0), where the law jumps; None if the direction does not depend on F.
    fn reversal(&self) -> Option<f64> {
        let alpha_f = self.alpha_f;
        let rate = (1.0 - alpha_f) * self.velocity_per_force;
        let force = ((1.0 - alpha_f) * (self.belt_speed - self.free_tip_velocity)
            + alpha_f * self.previous_relative_velocity)
            / rate;
        (rate != 0.0 && force.is_finite()).then_some(force)
    }

    /// The argument just beside the reversal force `reversal` (N), on the side where F
    /// is `above` it or below: the magnitude the law sees there (0 for the relative
    /// velocity, as the smallest normal number so that the law sees the direction),
    /// with that side's direction.
    fn beside_reversal(&self, reversal: f64, above: bool) -> Point {
        let alpha_f = self.alpha_f;
        let rate = (1.0 - alpha_f) * self.velocity_per_force;
        let direction = if above {
            self.direction_above()
        } else {
            -self.direction_above()
        };
        match self.sliding_velocity {
            SlidingVelocity::Relative => Point {
                force: reversal,
                x: direction * f64::MIN_POSITIVE,
                slope: -rate,
                direction,
            },
            SlidingVelocity::Tip => {
                let v_tip = self.free_tip_velocity + reversal * self.velocity_per_force;
                let tip = (1.0 - alpha_f) * v_tip + alpha_f * self.start_tip_velocity;
                Point {
                    force: reversal,
                    x: direction * tip.abs().max(f64::MIN_POSITIVE),
                    slope: direction * signum_or_zero(tip) * rate,
                    direction,
                }
            }
        }
    }
}

/// The law's argument at one tip force.
#[derive(Clone, Copy, Debug)]
struct Point {
    /// Tip force F (N).
    force: f64,
    /// x (m/s).
    x: f64,
    /// dx/dF (m/(s N)) where x is differentiable.
    slope: f64,
    /// Direction of sliding, sign(v_rel) at the law's level (0 exactly at the reversal).
    direction: f64,
}

/// One evaluation of r(F) = F - F_law(x(F)): the residual (N), its slope r' (1) and the
/// Newton iterate F - r / r' (N).
struct Residual {
    force: f64,
    direction: f64,
    law: f64,
    value: f64,
    slope: f64,
}

impl Residual {
    fn new(point: Point, law: &mut CountedLaw<'_, '_>) -> Self {
        let (law, law_slope) = law.force_and_slope(point.x);
        Self {
            force: point.force,
            direction: point.direction,
            law,
            value: point.force - law,
            slope: 1.0 - law_slope * point.slope,
        }
    }

    fn newton(&self) -> f64 {
        self.force - self.value / self.slope
    }
}

/// Safeguarded Newton on r(F) = F - F_law(x(F)) from `start` (N); see the module notes.
/// Returns the force (N) and whether it solves the equation.
///
/// r increases with F where the problem is well posed, so each evaluation narrows the
/// bracket (below, above) of the root: r(below) < 0 < r(above). A Newton iterate outside
/// it, or from a non-positive slope, is replaced by bisection (or, while one end is still
/// open, by the fixed-point step). The first iterate that would change the direction of
/// sliding, where the law jumps, is replaced by a look at both sides of the reversal
/// force F_j: r(F_j-) <= r(F_j+), so the root lies below (r(F_j-) > 0), above
/// (r(F_j+) < 0) or in the jump, where the equation has no solution and the fixed-point
/// iteration's answer is kept (see the module notes).
///
/// Converged when the Newton correction is below [`SLIP_TOLERANCE`] (or the law's
/// resolution, if coarser: [`FrictionLaw::resolution`]), or when two
/// successive Newton corrections shrink by q < 1/2 and the bound on the error of a
/// sequence converging at rate q, q / (1 - q) |correction|, is below it: Newton
/// converges faster than that bound assumes, and the test saves the evaluation that
/// would only confirm convergence.
fn newton(argument: &SlipArgument, start: f64, law: &mut CountedLaw<'_, '_>) -> (f64, bool) {
    let reversal = argument.reversal();
    let mut reversal_seen = false;
    let (mut below, mut above) = (f64::NEG_INFINITY, f64::INFINITY);
    let resolution = law.kinetic.resolution();
    let mut current = Residual::new(argument.at(start), law);
    // The Newton correction that led to `current`, if a Newton step did.
    let mut last_correction: Option<f64> = None;
    for _ in 1..SLIP_ITERATIONS {
        if !current.law.is_finite() {
            // The simulation reports the non-finite force.
            return (current.law, false);
        }
        if current.value == 0.0 {
            return (current.force, true);
        }
        if current.value < 0.0 {
            below = below.max(current.force);
        } else {
            above = above.min(current.force);
        }
        let newton = current.newton();
        let newton_valid = current.slope > 0.0 && newton.is_finite();
        if newton_valid {
            let correction = (newton - current.force).abs();
            let tolerance = (SLIP_TOLERANCE * (1.0 + newton.abs())).max(resolution);
            let rate = last_correction.map_or(1.0, |last| correction / last);
            if correction <= tolerance
                || (rate < 0.5 && rate / (1.0 - rate) * correction <= tolerance)
            {
                return (newton, true);
            }
        }
        let next = if newton_valid && below < newton && newton < above {
            newton
        } else if below.is_finite() && above.is_finite() {
            0.5 * (below + above)
        } else {
            current.law
        };
        last_correction = (next == newton).then(|| (newton - current.force).abs());
        let next = argument.at(next);
        current = match reversal {
            Some(reversal)
                if !reversal_seen
                    && (current.direction == 0.0 || next.direction != current.direction) =>
            {
                reversal_seen = true;
                last_correction = None;
                // Look first on the side of the current iterate (below if it has none).
                let first_above = current.direction == argument.direction_above();
                let first = Residual::new(argument.beside_reversal(reversal, first_above), law);
                if first.value == 0.0 {
                    return (reversal, true);
                }
                if (first.value < 0.0) == first_above {
                    // r(F_j+) < 0 or r(F_j-) > 0: the root lies on this side.
                    if first_above {
                        below = reversal;
                    } else {
                        above = reversal;
                    }
                    first
                } else {
                    let second =
                        Residual::new(argument.beside_reversal(reversal, !first_above), law);
                    if second.value == 0.0 {
                        return (reversal, true);
                    }
                    if (second.value < 0.0) == first_above || !second.law.is_finite() {
                        // r(F_j-) < 0 < r(F_j+): zero lies in the jump, no solution.
                        return (fixed_point(argument, start, law).0, false);
                    }
                    if first_above {
                        above = reversal;
                    } else {
                        below = reversal;
                    }
                    second
                }
            }
            // (A one-sided evaluation at the jump is the next iterate like any other:
            // its Newton step lies on its side, inside the bracket that now ends there.)
            _ => Residual::new(next, law),
        };
    }
    (current.force, false)
}

/// The fixed-point iteration F <- F_law(x(F)) from `start` (N), stopped when an update
/// is below the slip tolerance or after [`SLIP_ITERATIONS`] passes: the slip solve of
/// earlier versions, bit for bit ([`SlipSolver::FixedPoint`]).
///
/// Where the equation has no solution (zero in the law's jump) the iteration settles on
/// a cycle between the two sides and runs all its passes. The map is deterministic, so
/// once an iterate repeats one p passes before, the sequence repeats with period p and
/// its last value is known; none of the passes in that cycle converged, so none of the
/// repeats would have either. The shortcut gives the number the full run gives.
fn fixed_point(
    argument: &SlipArgument,
    start: f64,
    kinetic: &mut CountedLaw<'_, '_>,
) -> (f64, bool) {
    // Iterate F_i sits at history[i % CYCLE]; cycles of up to CYCLE - 1 passes are seen.
    const CYCLE: usize = 9;
    let mut history = [f64::NAN; CYCLE];
    history[0] = start;
    let mut force = start;
    for pass in 0..SLIP_ITERATIONS {
        let next = kinetic.force(argument.at(force).x);
        if (next - force).abs() <= SLIP_TOLERANCE * (1.0 + next.abs()) {
            return (next, true);
        }
        // next is F_m; F_m = F_{m-p} makes F_N = F_{m-p+((N-m) mod p)}, N the passes.
        let m = pass + 1;
        for period in 2..CYCLE.min(m + 1) {
            if next == history[(m - period) % CYCLE] {
                let rest = (SLIP_ITERATIONS - m) % period;
                return (history[(m - period + rest) % CYCLE], false);
            }
        }
        history[m % CYCLE] = next;
        force = next;
    }
    (force, false)
}

/// A coupled model's tangent: F(v) ~ force + slope (v - velocity) (N, N s/m, m/s).
#[derive(Clone, Copy, Debug)]
struct Tangent {
    force: f64,
    slope: f64,
    velocity: f64,
}

/// The slip force (N) under a coupled model's tangent T(v) = F_k + S (v - v_k): the root
/// of r(F) = F - T(x(F)), x(F) the law's argument at the end of the step under F, by
/// Newton's method. Returns the force and whether the iteration converged.
///
/// - **Implicit, with the slope.** The paper's plain network is steep near v = 0: it
///   rises from -13 N to +50 N within 1 mm/s (dF/dv up to ~1.4e5 N s/m). Held as a
///   constant over a communication step, such a law is an explicit feedback whose gain,
///   S times the tip's velocity change per newton, is far above 1 (~19 over a single
///   internal step of 1e-4 s at beam fidelity, more over a communication step), and the
///   coupled run swings where the embedded law creeps. Its tangent, solved within each
///   internal step, is what the embedded slip solve sees near v_k.
/// - **Along the sliding velocity.** Friction dissipates, F v_rel >= 0, which is why the
///   magnitude coupling applies its magnitude along v_rel. Where the tangent points
///   against the sliding velocity at the step's end, v_rel has crossed 0 since the model
///   was evaluated (a reversal of slip whose re-stick was inadmissible), and the tangent
///   describes the other side of the law's steep zero crossing, which it extrapolates
///   the wrong way (to -190 N within one 1 ms step in the paper scene). There its
///   magnitude acts along v_rel, as in the magnitude coupling. The one place where a law
///   itself pushes against v_rel, the plain network's -13 N on 0 < v < 0.1 mm/s, is an
///   artefact of smoothing the jump, and this rule departs from it there.
///
/// x(F) is affine in F for `sliding_velocity = "relative"` and piecewise affine for
/// "tip", and so is the direction rule: Newton's method ends in one pass on a piece, a
/// few across a kink. Where r'(F) = 1 - T' dx/dF vanishes the tangent gives no step, and
/// the held force F_k is taken as it is.
fn tangent_newton(
    argument: &SlipArgument,
    tangent: Tangent,
    law: &mut CountedLaw<'_, '_>,
) -> (f64, bool) {
    let Tangent {
        force: held,
        slope,
        velocity,
    } = tangent;
    let mut force = held;
    for _ in 0..SLIP_ITERATIONS {
        let point = argument.at(force);
        // One evaluation of the (affine) model per pass, counted like a law's.
        law.evaluations += 1;
        let value = held + slope * (point.x - velocity);
        let (model, model_slope) = if value * point.x < 0.0 {
            (-value, -slope)
        } else {
            (value, slope)
        };
        let residual = force - model;
        let derivative = 1.0 - model_slope * point.slope;
        if derivative.is_nan() || derivative.abs() <= f64::EPSILON {
            return (held, false);
        }
        let next = force - residual / derivative;
        let converged = (next - force).abs() <= 1e-12 * (1.0 + next.abs());
        force = next;
        if converged {
            return (force, true);
        }
    }
    (force, false)
}

/// Leine's switch rule for one step.
///
/// `holding_force` (N) is what stick would need this step, `static_limit` = mu_s F_n (N),
/// `previous_relative_velocity` and `relative_velocity` (m/s) are v_rel at the start of
/// the step and at its end as a slip step would give it, `stick_threshold` = eps (m/s).
pub fn next_state(
    state: ContactState,
    holding_force: f64,
    static_limit: f64,
    previous_relative_velocity: f64,
    relative_velocity: f64,
    stick_threshold: f64,
) -> ContactState {
    let admissible = holding_force.abs() <= static_limit;
    match state {
        ContactState::Stick if admissible => ContactState::Stick,
        ContactState::Stick => ContactState::Slip,
        ContactState::Slip => {
            let slow = relative_velocity.abs() < stick_threshold;
            let reversed = relative_velocity * previous_relative_velocity < 0.0;
            if (slow || reversed) && admissible {
                ContactState::Stick
            } else {
                ContactState::Slip
            }
        }
    }
}

/// Moreau-Jean's switch for one step: stick when the impulse stick needs, P = F dt, lies
/// in [-mu_s F_n dt, mu_s F_n dt], compared here as |F| <= mu_s F_n (`reaction` and
/// `static_limit` in N), whatever the state before.
pub fn impulse_clamp(reaction: f64, static_limit: f64) -> ContactState {
    if reaction.abs() <= static_limit {
        ContactState::Stick
    } else {
        ContactState::Slip
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::friction::{CoulombLaw, ExponentialLaw};
    use crate::scene::Scheme;
    use ContactState::*;

    #[test]
    fn stick_breaks_only_above_the_static_limit() {
        assert_eq!(next_state(Stick, 49.9, 50.0, 0.0, 0.0, 1e-3), Stick);
        assert_eq!(next_state(Stick, 50.0, 50.0, 0.0, 0.0, 1e-3), Stick);
        assert_eq!(next_state(Stick, -50.1, 50.0, 0.0, 0.0, 1e-3), Slip);
    }

    #[test]
    fn slip_resticks_only_when_slow_or_reversed_and_admissible() {
        // Just after breakaway: slow, but the holding force is still above the limit.
        assert_eq!(next_state(Slip, 50.2, 50.0, 0.0, 1e-5, 1e-3), Slip);
        // Fast slip with an admissible force: keeps slipping.
        assert_eq!(next_state(Slip, 10.0, 50.0, 0.05, 0.04, 1e-3), Slip);
        // Slow and admissible: sticks.
        assert_eq!(next_state(Slip, 10.0, 50.0, 2e-3, 5e-4, 1e-3), Stick);
        // Sign change with eps = 0: sticks (the crossing is not missed).
        assert_eq!(next_state(Slip, 10.0, 50.0, 2e-3, -1e-2, 0.0), Stick);
        // Sign change but inadmissible: reverses direction and keeps slipping.
        assert_eq!(next_state(Slip, 80.0, 50.0, 2e-3, -1e-2, 0.0), Slip);
    }

    #[test]
    fn impulse_clamp_holds_up_to_the_limit_in_either_direction() {
        assert_eq!(impulse_clamp(50.0, 50.0), Stick);
        assert_eq!(impulse_clamp(-50.0, 50.0), Stick);
        assert_eq!(impulse_clamp(50.1, 50.0), Slip);
        assert_eq!(impulse_clamp(-50.1, 50.0), Slip);
    }

    // Trial steps with round numbers near the paper's 1-DOF scale: the tip responds to F
    // by du/dF = 1e-9 m/N and dv/dF = 2e-5 m/(s N), dt = 1e-4 s (Moreau-Jean:
    // du/dF = dt theta dv/dF with theta = 1/2).
    const TRIAL: TrialStep = TrialStep {
        dt: 1e-4,
        start_tip_displacement: 7e-3,
        start_tip_velocity: 0.02,
        // u_n + v_b dt - 1e-9 m: the stick reaction is 1 N.
        free_tip_displacement: 7.002e-3 - 1e-9,
        free_tip_velocity: 0.03,
        displacement_per_force: 1e-9,
        velocity_per_force: 2e-5,
    };
    const MJ_TRIAL: TrialStep = TrialStep {
        dt: 1e-4,
        start_tip_displacement: 7e-3,
        start_tip_velocity: 0.02,
        free_tip_displacement: 7.002e-3,
        // v_b + 2e-5 m/s: the stick reaction is -1 N.
        free_tip_velocity: 0.02 + 2e-5,
        displacement_per_force: 1e-9,
        velocity_per_force: 2e-5,
    };
    const BELT: f64 = 0.02;
    const LIMIT: f64 = 50.0;

    fn contact(scheme: Scheme, holding: HoldingForce) -> Contact {
        let mut scene = CheckedScene::paper().into_scene();
        scene.integrator.scheme = scheme;
        scene.contact.holding_force = holding;
        let scene = scene.check().unwrap();
        Contact::new(&scene, Coefficients::from_scene(&scene))
    }

    fn coulomb() -> CoulombLaw {
        CoulombLaw {
            kinetic_coefficient: 0.2,
        }
    }

    fn previous(state: ContactState, relative_velocity: f64, force: f64) -> Previous {
        Previous {
            state,
            relative_velocity,
            force,
        }
    }

    #[test]
    fn generalized_alpha_sticks_with_the_reaction_that_puts_the_tip_on_the_belt() {
        let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
        let mut law = coulomb();
        let kinetic = Kinetic::Law {
            law: &mut law,
            normal_force: 100.0,
        };
        let r = c.resolve(&TRIAL, previous(Stick, 0.0, 0.0), BELT, LIMIT, kinetic);
        // (u_n + v_b dt - u_free) / (du/dF) = 1e-9 m / 1e-9 m/N = 1 N.
        assert_eq!(r.state, Stick);
        assert!((r.force - 1.0).abs() < 1e-6, "{}", r.force);
        assert_eq!(r.holding_force, r.force);
    }

    #[test]
    fn generalized_alpha_breaks_away_with_the_law_force() {
        let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
        let mut law = coulomb();
        // A limit below the 1 N reaction: breakaway, and slip takes mu_k F_n along
        // v_rel = v_b - v_tip < 0 (the tip runs ahead of the belt).
        let kinetic = Kinetic::Law {
            law: &mut law,
            normal_force: 100.0,
        };
        let r = c.resolve(&TRIAL, previous(Stick, 0.0, 0.0), BELT, 0.5, kinetic);
        assert_eq!(r.state, Slip);
        assert_eq!(r.force, -20.0);
        assert!((r.holding_force - 1.0).abs() < 1e-6);
    }

    #[test]
    fn euler_bernoulli_holding_force_is_the_tip_stiffness_times_the_stick_deflection() {
        let scene = CheckedScene::paper();
        let k = scene.euler_bernoulli_tip_stiffness();
        // Generalised-alpha: the stick deflection is u_n + v_b dt = 7.002 mm; 6250 N/m
        // times that is 43.76 N < 50 N, so the tip holds with the 1 N reaction.
        let c = contact(Scheme::GeneralizedAlpha, HoldingForce::EulerBernoulli);
        let mut law = coulomb();
        let kinetic = Kinetic::Law {
            law: &mut law,
            normal_force: 100.0,
        };
        let r = c.resolve(&TRIAL, previous(Stick, 0.0, 0.0), BELT, LIMIT, kinetic);
        assert_eq!(r.holding_force, k * (7e-3 + BELT * 1e-4));
        assert_eq!(r.state, Stick);
        assert!((r.force - 1.0).abs() < 1e-6);
        // ... and breaks away once k delta exceeds the limit, although the reaction is
        // small: the switch compares the Euler-Bernoulli force.
        let r = c.resolve(
            &TRIAL,
            previous(Stick, 0.0, 0.0),
            BELT,
            40.0,
            Kinetic::External { force: 20.0 },
        );
        assert_eq!(r.state, Slip);
    }

    #[test]
    fn slip_force_is_the_fixed_point_of_the_law_at_the_alpha_f_level() {
        let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
        let alpha_f = match Coefficients::from_scene(&CheckedScene::paper()) {
            Coefficients::GeneralizedAlpha { alpha_f, .. } => alpha_f,
            Coefficients::MoreauJean { .. } => unreachable!(),
        };
        let mut law = ExponentialLaw {
            static_coefficient: 0.5,
            kinetic_coefficient: 0.2,
            decay: 5.0,
        };
        // Fast slip (v_rel ~ -0.01 m/s at both ends): no re-stick.
        let kinetic = Kinetic::Law {
            law: &mut law,
            normal_force: 100.0,
        };
        let previous_relative_velocity = -0.012;
        let r = c.resolve(
            &TRIAL,
            previous(Slip, previous_relative_velocity, -40.0),
            BELT,
            LIMIT,
            kinetic,
        );
        assert_eq!(r.state, Slip);
        let v_rel = BELT - (TRIAL.free_tip_velocity + r.force * TRIAL.velocity_per_force);
        let level = (1.0 - alpha_f) * v_rel + alpha_f * previous_relative_velocity;
        let mut check = ExponentialLaw {
            static_coefficient: 0.5,
            kinetic_coefficient: 0.2,
            decay: 5.0,
        };
        let expected = check.sliding_force(level, 100.0);
        assert!(
            (r.force - expected).abs() < 1e-10,
            "{} vs {expected}",
            r.force
        );
    }

    #[test]
    fn slow_slip_resticks_only_when_the_holding_force_is_admissible() {
        let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
        // External kinetic force 0.5 N along v_rel: v_rel,n+1 = 0.02 - (0.03 - 0.5 * 2e-5)
        // < 0 after v_rel,n > 0, a sign change, though |v_rel| stays above eps.
        let kinetic = || Kinetic::External { force: 0.5 };
        let r = c.resolve(&TRIAL, previous(Slip, 1e-4, 0.5), BELT, LIMIT, kinetic());
        assert_eq!(r.state, Stick);
        assert!((r.force - 1.0).abs() < 1e-6);
        // The same crossing with the 1 N reaction above a 0.9 N limit: keeps slipping.
        let r = c.resolve(&TRIAL, previous(Slip, 1e-4, 0.5), BELT, 0.9, kinetic());
        assert_eq!(r.state, Slip);
        assert_eq!(r.force, -0.5);
    }

    #[test]
    fn moreau_jean_sticks_at_belt_velocity_whatever_the_state_before() {
        let c = contact(Scheme::MoreauJean, HoldingForce::Reaction);
        // (v_b - v_free) / (dv/dF) = -2e-5 / 2e-5 = -1 N, inside the clamp: stick, from
        // slip too, with no look at eps or at v_rel before.
        for state in [Stick, Slip] {
            let r = c.resolve(
                &MJ_TRIAL,
                previous(state, 0.5, 3.0),
                BELT,
                LIMIT,
                Kinetic::External { force: 20.0 },
            );
            assert_eq!(r.state, Stick);
            assert!((r.force + 1.0).abs() < 1e-6);
            assert_eq!(r.holding_force, r.force);
            let r = c.resolve(
                &MJ_TRIAL,
                previous(state, 0.5, 3.0),
                BELT,
                0.9,
                Kinetic::External { force: 0.5 },
            );
            assert_eq!(r.state, Slip);
            assert_eq!(r.force, -0.5);
        }
    }

    #[test]
    fn moreau_jean_clamps_the_reaction_and_reports_the_euler_bernoulli_force() {
        let c = contact(Scheme::MoreauJean, HoldingForce::EulerBernoulli);
        let k = CheckedScene::paper().euler_bernoulli_tip_stiffness();
        let r = c.resolve(
            &MJ_TRIAL,
            previous(Stick, 0.0, 0.0),
            BELT,
            LIMIT,
            Kinetic::External { force: 20.0 },
        );
        // The stick deflection is u_free + F du/dF with F = -1 N: 43.76 N reported,
        // while the clamp holds the -1 N reaction.
        let deflection = MJ_TRIAL.free_tip_displacement + r.force * MJ_TRIAL.displacement_per_force;
        assert_eq!(r.state, Stick);
        assert_eq!(r.holding_force, k * deflection);
        let r = c.resolve(
            &MJ_TRIAL,
            previous(Stick, 0.0, 0.0),
            BELT,
            40.0,
            Kinetic::External { force: 20.0 },
        );
        assert_eq!(
            r.state, Stick,
            "the clamp compares the reaction, not k delta"
        );
    }

    /// F(v) = 50 N tanh(v / 1e-4 m/s): continuous, with dF/dv = 5e5 N s/m at v = 0,
    /// steeper than the fixed-point iteration can follow at TRIAL's dv/dF (the safeguarded
    /// Newton iteration solves it).
    struct SteepLaw;

    impl FrictionLaw for SteepLaw {
        fn name(&self) -> &str {
            "steep"
        }

        fn sliding_force(&mut self, v: f64, _normal_force: f64) -> f64 {
            50.0 * (v / 1e-4).tanh()
        }

        fn sliding_force_and_slope(&mut self, v: f64, _normal_force: f64) -> (f64, f64) {
            let t = (v / 1e-4).tanh();
            (50.0 * t, 50.0 / 1e-4 * (1.0 - t * t))
        }
    }

    fn alpha_f() -> f64 {
        match Coefficients::from_scene(&CheckedScene::paper()) {
            Coefficients::GeneralizedAlpha { alpha_f, .. } => alpha_f,
            Coefficients::MoreauJean { .. } => unreachable!(),
        }
    }

    /// TRIAL with the tip 1e-4 m/s ahead of the belt before the force: v_rel(F) =
    /// -1e-4 - 2e-5 F, so the slip force sits where a steep law is steep.
    const NEAR_ZERO: TrialStep = TrialStep {
        free_tip_velocity: 0.02 + 1e-4,
        ..TRIAL
    };
    /// Below TRIAL's 1 N stick reaction: re-stick is inadmissible, the step slips
    /// however slow.
    const LOW_LIMIT: f64 = 0.5;

    /// The law's argument at t_{n+1-alpha_f} after `trial` with tip force `force`.
    fn level(trial: &TrialStep, previous_relative_velocity: f64, force: f64) -> f64 {
        let alpha_f = alpha_f();
        let v_rel = BELT - (trial.free_tip_velocity + force * trial.velocity_per_force);
        (1.0 - alpha_f) * v_rel + alpha_f * previous_relative_velocity
    }

    #[test]
    fn a_steep_continuous_law_gets_its_root_where_the_fixed_point_iteration_diverges() {
        let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
        // Gain |dF/dv| (1 - alpha_f) dv/dF = 5e5 x 0.56 x 2e-5 ~ 5.5 > 1: the plain
        // iteration swings between two forces.
        let gain = 5e5 * (1.0 - alpha_f()) * NEAR_ZERO.velocity_per_force;
        assert!(gain > 5.0, "{gain}");
        let mut law = SteepLaw;
        let kinetic = Kinetic::Law {
            law: &mut law,
            normal_force: 100.0,
        };
        let r = c.resolve(
            &NEAR_ZERO,
            previous(Slip, 0.0, 30.0),
            BELT,
            LOW_LIMIT,
            kinetic,
        );
        assert_eq!(r.state, Slip);
        let expected = SteepLaw.sliding_force(level(&NEAR_ZERO, 0.0, r.force), 100.0);
        // Safeguarded Newton to SLIP_TOLERANCE: the residual is the law's slope times
        // the last correction, times the gain, well below 1e-9 N.
        assert!(
            (r.force - expected).abs() < 1e-9,
            "F = {} N, law at its argument {expected} N",
            r.force
        );
        assert!(r.force.abs() > 1.0 && r.force.abs() < 49.0, "{}", r.force);
    }

    #[test]
    fn a_law_with_a_jump_keeps_the_last_iterate_when_the_step_crosses_it() {
        // Coulomb's law jumps by 2 mu_k F_n = 40 N at v = 0, and the force-free step
        // ends at v_rel = -1e-4 m/s: -20 N gives v_rel > 0, +20 N gives v_rel < 0.
        // There is no root; the iteration swings and its 50th iterate is kept.
        let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
        let start = 20.0;
        let mut law = coulomb();
        let r = c.resolve(
            &NEAR_ZERO,
            previous(Slip, 0.0, start),
            BELT,
            LOW_LIMIT,
            Kinetic::Law {
                law: &mut law,
                normal_force: 100.0,
            },
        );
        let mut check = coulomb();
        let mut force = start;
        for _ in 0..SLIP_ITERATIONS {
            force = check.sliding_force(level(&NEAR_ZERO, 0.0, force), 100.0);
        }
        assert_eq!(r.force, force);
        assert_eq!(r.force.abs(), 20.0);
    }

    #[test]
    fn the_external_tangent_is_solved_implicitly_where_the_held_force_would_overshoot() {
        let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
        // A tangent of the steep law at v_k = 0: F(0) = 0, S = 5e5 N s/m.
        let (held, slope, velocity) = (0.0, 5e5, 0.0);
        let r = c.resolve(
            &NEAR_ZERO,
            previous(Slip, 0.0, 30.0),
            BELT,
            LOW_LIMIT,
            Kinetic::ExternalSigned {
                force: held,
                slope,
                velocity,
            },
        );
        let v = level(&NEAR_ZERO, 0.0, r.force);
        assert!(
            (r.force - (held + slope * (v - velocity))).abs() < 1e-9,
            "F = {} N at v = {v} m/s",
            r.force
        );
        // The root of F = S (1 - alpha_f) (-1e-4 - 2e-5 F): F = -S a 1e-4 / (1 + S a 2e-5)
        // with a = 1 - alpha_f.
        let a = 1.0 - alpha_f();
        let closed_form = -slope * a * 1e-4 / (1.0 + slope * a * 2e-5);
        assert!(
            (r.force - closed_form).abs() < 1e-9,
            "{} vs {closed_form}",
            r.force
        );
    }

    #[test]
    fn the_held_signed_force_acts_as_given_along_the_sliding_velocity_and_as_its_magnitude_against_it(
    ) {
        let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
        // TRIAL in fast slip, v_rel ~ -0.01 m/s: a held -7 N (slope 0) points along it
        // and acts as given.
        let signed = |force| Kinetic::ExternalSigned {
            force,
            slope: 0.0,
            velocity: 0.3,
        };
        let r = c.resolve(
            &TRIAL,
            previous(Slip, -0.012, -40.0),
            BELT,
            LIMIT,
            signed(-7.0),
        );
        assert_eq!((r.state, r.force), (Slip, -7.0));
        // A held +7 N points against it (the model saw the other side of v = 0): its
        // magnitude acts along v_rel, as the magnitude coupling would apply it.
        let r = c.resolve(
            &TRIAL,
            previous(Slip, -0.012, -40.0),
            BELT,
            LIMIT,
            signed(7.0),
        );
        assert_eq!((r.state, r.force), (Slip, -7.0));
        let r = c.resolve(
            &TRIAL,
            previous(Slip, -0.012, -40.0),
            BELT,
            LIMIT,
            Kinetic::External { force: 7.0 },
        );
        assert_eq!(r.force, -7.0);
    }

    #[test]
    fn external_kinetic_force_acts_along_the_sliding_velocity() {
        assert_eq!(Kinetic::External { force: 7.0 }.force(0.3), 7.0);
        assert_eq!(Kinetic::External { force: 7.0 }.force(-0.3), -7.0);
        assert_eq!(Kinetic::External { force: 7.0 }.force(0.0), 0.0);
    }

    /// What the sweep below met, per law.
    #[derive(Default, Debug)]
    struct Met {
        /// Both converged (to each other).
        agreed: usize,
        /// No solution: Newton kept the fixed-point iteration's number.
        jump: usize,
        /// Of these, with sliding_velocity = "relative" (with "tip" the law's argument
        /// jumps from |v_tip| to -|v_tip| at the reversal, whatever the law).
        relative_jump: usize,
        /// The fixed-point iteration did not converge, Newton found the root.
        rescued: usize,
        /// Both converged, to different roots (sliding_velocity = "tip" only).
        ambiguous: usize,
    }

    /// Newton against the fixed-point reference over slip steps near the paper's scale:
    /// tip compliances of the paper's step and of a 10x step, both schemes' law levels,
    /// both sliding velocities, arguments from -0.05 to 0.05 m/s (reversals included)
    /// and starting forces on either side.
    ///
    /// Where the fixed-point iteration converges, both stop within SLIP_TOLERANCE of the
    /// root: the fixed point returns F_law(x(F_k)) with |F_law(x(F_k)) - F_k| <= tol, so
    /// its error is q tol / (1 - q) at contraction q < 1/2, and Newton's correction
    /// bounds its own; they agree to 2 tol (1 + |F|). Where it does not converge, the
    /// equation has no solution (Newton then returns the fixed point's number, bit for
    /// bit, and the residuals just beside the reversal have opposite signs) or Newton
    /// found a root, |r| / r' <= tol.
    fn sweep(law: &mut dyn FrictionLaw) -> Met {
        let mut met = Met::default();
        let alpha_f = match Coefficients::from_scene(&CheckedScene::paper()) {
            Coefficients::GeneralizedAlpha { alpha_f, .. } => alpha_f,
            Coefficients::MoreauJean { .. } => unreachable!(),
        };
        for velocity_per_force in [2e-5, 2e-4] {
            for alpha in [0.0, alpha_f] {
                for sliding_velocity in [SlidingVelocity::Relative, SlidingVelocity::Tip] {
                    for k in -50..=50 {
                        for (start, previous_relative_velocity) in [
                            (-50.0, -1e-3),
                            (-20.0, -0.01),
                            (0.0, 0.0),
                            (30.0, 2e-3),
                            (50.0, 0.02),
                        ] {
                            let argument = SlipArgument {
                                belt_speed: BELT,
                                // x0 = (1 - alpha_f) (v_b - v_free) + ..., from -0.05 to 0.05
                                // m/s, densest near 0.
                                free_tip_velocity: BELT - 0.05 * (k as f64 / 50.0).powi(3),
                                velocity_per_force,
                                alpha_f: alpha,
                                previous_relative_velocity,
                                start_tip_velocity: 0.01,
                                sliding_velocity,
                            };
                            let mut kinetic = Kinetic::Law {
                                law: &mut *law,
                                normal_force: 100.0,
                            };
                            let mut counted = CountedLaw {
                                kinetic: &mut kinetic,
                                evaluations: 0,
                            };
                            let (fixed, fixed_converged) =
                                fixed_point(&argument, start, &mut counted);
                            let (force, solved) = newton(&argument, start, &mut counted);
                            let case = format!(
                                "k {k}, start {start}, dv/dF {velocity_per_force}, alpha_f {alpha}, {sliding_velocity:?}: Newton {force}, fixed point {fixed}"
                            );
                            let bound = 2.0 * SLIP_TOLERANCE * (1.0 + force.abs());
                            if fixed_converged && (force - fixed).abs() <= bound {
                                assert!(solved, "{case}");
                                met.agreed += 1;
                            } else if fixed_converged {
                                // Several solutions: |v_tip| can run against v_rel, and
                                // where the law is steep r' = 1 - F_law' x' < 0.
                                assert!(solved, "{case}");
                                assert_eq!(sliding_velocity, SlidingVelocity::Tip, "{case}");
                                assert!(root_error(&argument, force, &mut counted) <= bound / 2.0);
                                met.ambiguous += 1;
                            } else if !solved {
                                assert_eq!(force.to_bits(), fixed.to_bits(), "{case}");
                                let reversal = argument.reversal().expect(&case);
                                let mut side = |above| {
                                    let x = argument.beside_reversal(reversal, above).x;
                                    reversal - counted.force(x)
                                };
                                assert!(side(false) * side(true) < 0.0, "{case}");
                                met.jump += 1;
                                if sliding_velocity == SlidingVelocity::Relative {
                                    met.relative_jump += 1;
                                }
                            } else {
                                let error = root_error(&argument, force, &mut counted);
                                assert!(error <= bound / 2.0, "{case}: |r| / |r'| = {error}");
                                met.rescued += 1;
                            }
                        }
                    }
                }
            }
        }
        met
    }

    /// |r| / |r'| at `force`, Newton's estimate of its distance to the root (N). A root
    /// at the edge of the jump (F = F_law(0+) or F_law(0-)) solves the equation from
    /// that side.
    fn root_error(argument: &SlipArgument, force: f64, law: &mut CountedLaw<'_, '_>) -> f64 {
        let point = argument.at(force);
        let points = if point.direction == 0.0 {
            vec![
                argument.beside_reversal(force, false),
                argument.beside_reversal(force, true),
            ]
        } else {
            vec![point]
        };
        points
            .into_iter()
            .map(|p| {
                let r = Residual::new(p, law);
                r.value.abs() / r.slope.abs()
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn newton_agrees_with_the_fixed_point_where_it_converges_and_keeps_it_where_nothing_does() {
        let mut exponential = ExponentialLaw {
            static_coefficient: 0.5,
            kinetic_coefficient: 0.2,
            decay: 5.0,
        };
        // Laws with a jump at v = 0 meet steps without solution (the sweep crowds its
        // arguments near 0). The fixed point also cycles across the jump in some steps
        // that have a solution (at the edge of the jump, F = F_law(0-), or with
        // sliding_velocity = "tip" at the larger step), which Newton finds.
        let met = sweep(&mut exponential);
        assert!(
            met.agreed > 1000 && met.jump > 50 && met.ambiguous == 0,
            "{met:?}"
        );
        let met = sweep(&mut coulomb());
        assert!(
            met.agreed > 1000 && met.jump > 50 && met.ambiguous == 0,
            "{met:?}"
        );
        let mut signed = crate::neural::NeuralLaw::paper_signed().unwrap();
        let met = sweep(&mut signed);
        assert!(
            met.agreed > 1000 && met.jump > 50 && met.ambiguous == 0,
            "{met:?}"
        );
        // The plain network is continuous: every step on the relative velocity has a
        // solution, and where the network is steep (|F_law' x'| > 1) only Newton finds
        // it.
        let mut plain = crate::neural::NeuralLaw::paper_default().unwrap();
        let met = sweep(&mut plain);
        assert!(
            met.agreed > 1000 && met.relative_jump == 0 && met.rescued > 10,
            "{met:?}"
        );
    }

    #[test]
    fn a_solution_in_the_continuous_part_takes_newton_two_evaluations_at_most_three() {
        // Slip at the paper's scale away from a reversal, the start the last step's
        // force: F moves by a few N at most per step.
        let mut law = ExponentialLaw {
            static_coefficient: 0.5,
            kinetic_coefficient: 0.2,
            decay: 5.0,
        };
        // |v_b - v_free| > 50 N x dv/dF = 1e-3 m/s: no reversal within the step.
        for v_free in [0.015, 0.025, 0.04, 0.1, -0.05] {
            for shift in [0.0, 0.01, 0.5, 3.0] {
                let argument = SlipArgument {
                    belt_speed: BELT,
                    free_tip_velocity: v_free,
                    velocity_per_force: 2e-5,
                    alpha_f: 0.0,
                    previous_relative_velocity: BELT - v_free,
                    start_tip_velocity: v_free,
                    sliding_velocity: SlidingVelocity::Relative,
                };
                let (root, _, _) = solve(&argument, &mut law, 0.0);
                let (force, solved, evaluations) = solve(&argument, &mut law, root + shift);
                assert!(solved);
                assert!((force - root).abs() <= 2.0 * SLIP_TOLERANCE * (1.0 + root.abs()));
                assert!(
                    (1..=3).contains(&evaluations),
                    "v_free {v_free}, start root + {shift}: {evaluations} evaluations"
                );
            }
        }
    }

    /// Newton's slip force from `start` (N) under F_n = 100 N: the force, whether it
    /// solved, and the law evaluations it took.
    fn solve(argument: &SlipArgument, law: &mut dyn FrictionLaw, start: f64) -> (f64, bool, usize) {
        let mut kinetic = Kinetic::Law {
            law,
            normal_force: 100.0,
        };
        let mut count = CountedLaw {
            kinetic: &mut kinetic,
            evaluations: 0,
        };
        let (force, solved) = newton(argument, start, &mut count);
        (force, solved, count.evaluations)
    }
}
