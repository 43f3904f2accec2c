//! Limited-memory BFGS with a strong-Wolfe line search, for full-batch training.
//!
//! Nocedal & Wright, Numerical Optimization (2nd ed., 2006): the two-loop recursion
//! (Alg. 7.4) with the initial inverse Hessian gamma I, gamma = s'y / y'y (Eq. 7.20),
//! and the line search of Alg. 3.5 / 3.6 (bracketing, then zoom with safeguarded cubic
//! interpolation). Strong Wolfe conditions for a step alpha along d:
//!   f(x + alpha d) <= f(x) + c1 alpha g'd           (sufficient decrease)
//!   |g(x + alpha d)'d| <= c2 |g'd|                   (curvature)
//! which keep s'y > 0, so the quasi-Newton matrix stays positive definite.
//!
//! Written here rather than taken from `argmin` because training needs a deterministic,
//! allocation-light loop over one flat `Vec<f64>` with a per-iteration callback (history,
//! progress, test loss) and no extra dependency tree; the algorithm is short.
//!
//! And kept because it reproduces the shipped weights byte for byte: retraining with the
//! defaults writes `weights/paper-plain.json` and `weights/paper-signed.json` exactly
//! (tests `training_with_defaults_regenerates_the_shipped_plain_weights` and
//! `training_the_signed_variant_regenerates_the_shipped_signed_weights` in
//! `tests/neural/training.rs`, opt-in with `--ignored`). argmin's L-BFGS would change
//! those weights: its line searches are More-Thuente, Hager-Zhang or backtracking (not
//! the Alg. 3.5 / 3.6 zoom used here), it has its own stopping rules, and its vector
//! arithmetic (argmin-math) sums the two-loop dot products in its own order; any one of
//! these moves the iterates by an ulp at first, and 200 to 1000 iterations of a
//! non-convex loss carry that into different weights.

use std::collections::VecDeque;

use crate::error::TrainError;

/// Settings of `minimize`.
#[derive(Clone, Debug, PartialEq)]
pub struct LbfgsOptions {
    /// Number of (s, y) pairs kept, m.
    pub history: usize,
    /// Stop after this many iterations (line searches).
    pub max_iterations: usize,
    /// Stop after this many objective evaluations.
    pub max_evaluations: usize,
    /// Stop when max_i |g_i| <= this.
    pub gradient_tolerance: f64,
    /// Stop when (f_{k-1} - f_k) <= this * max(|f_{k-1}|, |f_k|).
    pub relative_loss_tolerance: f64,
    /// c1 of the sufficient-decrease condition.
    pub sufficient_decrease: f64,
    /// c2 of the curvature condition.
    pub curvature: f64,
    /// Evaluations allowed in one line search.
    pub max_line_search_evaluations: usize,
}

impl Default for LbfgsOptions {
    fn default() -> Self {
        LbfgsOptions {
            history: 10,
            max_iterations: 1000,
            max_evaluations: 15_000,
            gradient_tolerance: 1e-9,
            relative_loss_tolerance: 1e-12,
            sufficient_decrease: 1e-4,
            curvature: 0.9,
            max_line_search_evaluations: 25,
        }
    }
}

pub use stickslip::neural::weights::StopReason;

/// State after an iteration, handed to the callback (iteration 0 = starting point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationInfo {
    pub iteration: usize,
    pub value: f64,
    /// max_i |g_i|.
    pub gradient_norm: f64,
    /// Objective evaluations so far.
    pub evaluations: usize,
    /// Accepted step length alpha (0 at iteration 0).
    pub step: f64,
}

/// Outcome of `minimize`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LbfgsResult {
    pub value: f64,
    pub iterations: usize,
    pub evaluations: usize,
    pub stop: StopReason,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// Minimises `objective(x, gradient) -> value` from the start `x` (updated in place).
/// `callback` sees every accepted iterate. Fails only if the objective is not finite at
/// the starting point.
pub fn minimize<F, C>(
    mut objective: F,
    x: &mut [f64],
    options: &LbfgsOptions,
    mut callback: C,
) -> Result<LbfgsResult, TrainError>
where
    F: FnMut(&[f64], &mut [f64]) -> f64,
    C: FnMut(&IterationInfo, &[f64]),
{
    let n = x.len();
    let mut gradient = vec![0.0; n];
    let mut value = objective(x, &mut gradient);
    let mut evaluations = 1;
    if !value.is_finite() || gradient.iter().any(|g| !g.is_finite()) {
        return Err(TrainError::Training(format!(
            "the loss at the initial weights is {value}; check the data for extreme values"
        )));
    }
    callback(&IterationInfo::at(0, value, &gradient, evaluations, 0.0), x);

    let mut pairs = CurvaturePairs::new(options.history);
    let mut direction = vec![0.0; n];
    let mut x_trial = vec![0.0; n];
    let mut g_trial = vec![0.0; n];
    let mut iterations = 0;
    let stop = loop {
        if let Some(stop) = budget_or_gradient_stop(options, &gradient, iterations, evaluations) {
            break stop;
        }
        let slope = descent_direction(&mut pairs, &gradient, &mut direction);
        let initial_step = pairs.initial_step(&gradient);

        let budget = options
            .max_line_search_evaluations
            .min(options.max_evaluations.saturating_sub(evaluations).max(1));
        let search = line_search(
            &mut objective,
            x,
            &direction,
            value,
            slope,
            initial_step,
            options,
            budget,
            &mut x_trial,
            &mut g_trial,
        );
        evaluations += search.evaluations;
        let Some((step, new_value)) = search.accepted else {
            break StopReason::LineSearchFailed;
        };
        iterations += 1;

        pairs.remember(&x_trial, x, &g_trial, &gradient);
        x.copy_from_slice(&x_trial);
        gradient.copy_from_slice(&g_trial);
        let previous = value;
        value = new_value;
        callback(
            &IterationInfo::at(iterations, value, &gradient, evaluations, step),
            x,
        );
        if previous - value <= options.relative_loss_tolerance * previous.abs().max(value.abs()) {
            break StopReason::LossTolerance;
        }
    };
    Ok(LbfgsResult {
        value,
        iterations,
        evaluations,
        stop,
    })
}

impl IterationInfo {
    fn at(iteration: usize, value: f64, gradient: &[f64], evaluations: usize, step: f64) -> Self {
        IterationInfo {
            iteration,
            value,
            gradient_norm: max_abs(gradient),
            evaluations,
            step,
        }
    }
}

/// The stop before an iteration: the gradient small enough (max_i |g_i|), or the
/// iterations or evaluations spent; `None` goes on.
fn budget_or_gradient_stop(
    options: &LbfgsOptions,
    gradient: &[f64],
    iterations: usize,
    evaluations: usize,
) -> Option<StopReason> {
    if max_abs(gradient) <= options.gradient_tolerance {
        return Some(StopReason::GradientTolerance);
    }
    if iterations >= options.max_iterations {
        return Some(StopReason::MaxIterations);
    }
    if evaluations >= options.max_evaluations {
        return Some(StopReason::MaxEvaluations);
    }
    None
}

/// The limited memory of L-BFGS: the last `history` pairs s = x_new - x,
/// y = g_new - g with rho = 1 / s'y, newest last, which stand for the inverse Hessian H.
struct CurvaturePairs {
    /// (s, y, rho), newest last.
    pairs: VecDeque<(Vec<f64>, Vec<f64>, f64)>,
    history: usize,
    /// Scratch of the two-loop recursion, one per pair.
    alphas: Vec<f64>,
}

impl CurvaturePairs {
    fn new(history: usize) -> Self {
        CurvaturePairs {
            pairs: VecDeque::with_capacity(history),
            history,
            alphas: vec![0.0; history.max(1)],
        }
    }

    fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    fn clear(&mut self) {
        self.pairs.clear();
    }

    /// The line search's first trial step alpha: 1, the quasi-Newton step, once a pair
    /// scales H; without one a step of unit length along -g, since the gradient's scale
    /// says nothing about curvature.
    fn initial_step(&self, gradient: &[f64]) -> f64 {
        if self.is_empty() {
            1.0 / dot(gradient, gradient).sqrt()
        } else {
            1.0
        }
    }

    /// d = -H g by the two-loop recursion (N&W Alg. 7.4) with H_0 = gamma I,
    /// gamma = s'y / y'y of the newest pair (Eq. 7.20); d = -g with no pair.
    fn direction(&mut self, gradient: &[f64], direction: &mut [f64]) {
        direction.copy_from_slice(gradient);
        for (k, (s, y, rho)) in self.pairs.iter().enumerate().rev() {
            let a = rho * dot(s, direction);
            self.alphas[k] = a;
            direction.iter_mut().zip(y).for_each(|(q, yi)| *q -= a * yi);
        }
        if let Some((s, y, _)) = self.pairs.back() {
            let gamma = dot(s, y) / dot(y, y);
            direction.iter_mut().for_each(|q| *q *= gamma);
        }
        for (k, (s, y, rho)) in self.pairs.iter().enumerate() {
            let b = rho * dot(y, direction);
            let a = self.alphas[k];
            direction
                .iter_mut()
                .zip(s)
                .for_each(|(r, si)| *r += (a - b) * si);
        }
        direction.iter_mut().for_each(|r| *r = -*r);
    }

    /// Keeps the step's pair (the oldest's vectors reused once `history` are held) if
    /// s'y > eps y'y: a pair without positive curvature would break H's definiteness.
    fn remember(&mut self, x_new: &[f64], x: &[f64], g_new: &[f64], g: &[f64]) {
        let n = x.len();
        let (mut s, mut y) = match self.pairs.len() == self.history.max(1) {
            true => {
                let (s, y, _) = self.pairs.pop_front().unwrap_or_default();
                (s, y)
            }
            false => (vec![0.0; n], vec![0.0; n]),
        };
        for i in 0..n {
            s[i] = x_new[i] - x[i];
            y[i] = g_new[i] - g[i];
        }
        let sy = dot(&s, &y);
        if sy > f64::EPSILON * dot(&y, &y) {
            self.pairs.push_back((s, y, 1.0 / sy));
        }
    }
}

/// Writes the quasi-Newton direction into `direction` and returns its slope g'd; if
/// that is not a descent direction (rounding), forgets the pairs and restarts from
/// steepest descent.
fn descent_direction(pairs: &mut CurvaturePairs, gradient: &[f64], direction: &mut [f64]) -> f64 {
    pairs.direction(gradient, direction);
    let slope = dot(gradient, direction);
    // Also catches NaN: a NaN slope is not a descent direction either.
    if slope.is_nan() || slope >= 0.0 || !slope.is_finite() {
        pairs.clear();
        direction
            .iter_mut()
            .zip(gradient)
            .for_each(|(d, g)| *d = -g);
        return -dot(gradient, gradient);
    }
    slope
}

struct LineSearch {
    /// (alpha, f(x + alpha d)); `x_trial` and `g_trial` hold that point and its gradient.
    accepted: Option<(f64, f64)>,
    evaluations: usize,
}

#[derive(Clone, Copy)]
struct Point {
    alpha: f64,
    value: f64,
    slope: f64,
}

/// Minimiser of the cubic through (a, f_a, f'_a) and (b, f_b, f'_b) (N&W Eq. 3.59),
/// kept inside the middle 80 % of [a, b]; bisection when the cubic has no minimiser.
fn cubic_step(a: Point, b: Point) -> f64 {
    let (lo, hi) = (a.alpha.min(b.alpha), a.alpha.max(b.alpha));
    let margin = 0.1 * (hi - lo);
    let bisection = 0.5 * (lo + hi);
    if !b.value.is_finite() || !b.slope.is_finite() {
        return bisection;
    }
    let d1 = a.slope + b.slope - 3.0 * (a.value - b.value) / (a.alpha - b.alpha);
    let discriminant = d1 * d1 - a.slope * b.slope;
    if discriminant < 0.0 {
        return bisection;
    }
    let d2 = (b.alpha - a.alpha).signum() * discriminant.sqrt();
    let t = b.alpha - (b.alpha - a.alpha) * (b.slope + d2 - d1) / (b.slope - a.slope + 2.0 * d2);
    if t.is_finite() {
        t.clamp(lo + margin, hi - margin)
    } else {
        bisection
    }
}

/// Trial points x + alpha d along the search line, evaluated into `x_trial` and
/// `g_trial` (which then hold the last one), counted.
struct LineProbe<'a, F> {
    objective: &'a mut F,
    x: &'a [f64],
    direction: &'a [f64],
    x_trial: &'a mut [f64],
    g_trial: &'a mut [f64],
    evaluations: usize,
}

impl<F> LineProbe<'_, F>
where
    F: FnMut(&[f64], &mut [f64]) -> f64,
{
    fn at(&mut self, alpha: f64) -> Point {
        for ((xt, xi), di) in self.x_trial.iter_mut().zip(self.x).zip(self.direction) {
            *xt = xi + alpha * di;
        }
        let value = (self.objective)(self.x_trial, self.g_trial);
        self.evaluations += 1;
        Point {
            alpha,
            value,
            slope: dot(self.g_trial, self.direction),
        }
    }
}

/// The strong Wolfe conditions for a step from the start (value0, slope0).
struct Wolfe {
    value0: f64,
    slope0: f64,
    c1: f64,
    c2: f64,
}

impl Wolfe {
    /// Sufficient decrease fails (or the value is not finite).
    fn armijo_fails(&self, p: Point) -> bool {
        !p.value.is_finite() || p.value > self.value0 + self.c1 * p.alpha * self.slope0
    }

    fn curvature_holds(&self, p: Point) -> bool {
        p.slope.abs() <= -self.c2 * self.slope0
    }
}

/// What bracketing found: a point that already satisfies the conditions (or the last
/// Armijo point when the budget ran out still descending), or an interval (lo, hi)
/// that contains one.
enum Bracket {
    Accepted(Point),
    Interval(Point, Point),
}

/// Bracketing phase (N&W Alg. 3.5): doubles alpha from `initial_step` until a Wolfe
/// point is found or bracketed.
fn bracket<F>(
    probe: &mut LineProbe<'_, F>,
    wolfe: &Wolfe,
    initial_step: f64,
    budget: usize,
) -> Bracket
where
    F: FnMut(&[f64], &mut [f64]) -> f64,
{
    let mut previous = Point {
        alpha: 0.0,
        value: wolfe.value0,
        slope: wolfe.slope0,
    };
    let mut alpha = initial_step;
    loop {
        let p = probe.at(alpha);
        if wolfe.armijo_fails(p) || (probe.evaluations > 1 && p.value >= previous.value) {
            return Bracket::Interval(previous, p);
        }
        if wolfe.curvature_holds(p) {
            return Bracket::Accepted(p);
        }
        if p.slope >= 0.0 {
            return Bracket::Interval(p, previous);
        }
        if probe.evaluations >= budget {
            // Still descending after the budget: take the last (Armijo) point.
            return Bracket::Accepted(p);
        }
        previous = p;
        alpha *= 2.0;
    }
}

/// Zoom phase (N&W Alg. 3.6) on (lo, hi), lo satisfying sufficient decrease with the
/// lowest value: the Wolfe point, or (budget spent, interval collapsed) the last lo.
fn zoom<F>(
    probe: &mut LineProbe<'_, F>,
    wolfe: &Wolfe,
    mut lo: Point,
    mut hi: Point,
    budget: usize,
) -> Result<Point, Point>
where
    F: FnMut(&[f64], &mut [f64]) -> f64,
{
    while probe.evaluations < budget
        && (hi.alpha - lo.alpha).abs() > 1e-14 * lo.alpha.abs().max(1e-300)
    {
        let p = probe.at(cubic_step(lo, hi));
        if wolfe.armijo_fails(p) || p.value >= lo.value {
            hi = p;
        } else {
            if wolfe.curvature_holds(p) {
                return Ok(p);
            }
            if p.slope * (hi.alpha - lo.alpha) >= 0.0 {
                hi = lo;
            }
            lo = p;
        }
    }
    Err(lo)
}

#[allow(clippy::too_many_arguments)]
fn line_search<F>(
    objective: &mut F,
    x: &[f64],
    direction: &[f64],
    value0: f64,
    slope0: f64,
    initial_step: f64,
    options: &LbfgsOptions,
    budget: usize,
    x_trial: &mut [f64],
    g_trial: &mut [f64],
) -> LineSearch
where
    F: FnMut(&[f64], &mut [f64]) -> f64,
{
    let wolfe = Wolfe {
        value0,
        slope0,
        c1: options.sufficient_decrease,
        c2: options.curvature,
    };
    let mut probe = LineProbe {
        objective,
        x,
        direction,
        x_trial,
        g_trial,
        evaluations: 0,
    };
    let accepted = match bracket(&mut probe, &wolfe, initial_step, budget) {
        Bracket::Accepted(p) => Some(p),
        Bracket::Interval(lo, hi) => match zoom(&mut probe, &wolfe, lo, hi, budget) {
            Ok(p) => Some(p),
            // Out of budget: fall back to the best point with sufficient decrease, if
            // any (evaluated again, so that x_trial and g_trial hold it).
            Err(lo) if lo.alpha > 0.0 => {
                Some(probe.at(lo.alpha)).filter(|p| p.value.is_finite() && p.value < value0)
            }
            Err(_) => None,
        },
    };
    LineSearch {
        accepted: accepted.map(|p| (p.alpha, p.value)),
        evaluations: probe.evaluations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rosenbrock(x: &[f64], g: &mut [f64]) -> f64 {
        let mut f = 0.0;
        g.iter_mut().for_each(|v| *v = 0.0);
        for i in 0..x.len() - 1 {
            let a = x[i + 1] - x[i] * x[i];
            let b = 1.0 - x[i];
            f += 100.0 * a * a + b * b;
            g[i] += -400.0 * a * x[i] - 2.0 * b;
            g[i + 1] += 200.0 * a;
        }
        f
    }

    #[test]
    fn minimises_rosenbrock() {
        let mut x = vec![-1.2, 1.0, -1.2, 1.0, -1.2, 1.0];
        let options = LbfgsOptions {
            max_iterations: 500,
            gradient_tolerance: 1e-8,
            ..Default::default()
        };
        let mut values = Vec::new();
        let result = minimize(rosenbrock, &mut x, &options, |info, _| {
            values.push(info.value)
        })
        .unwrap();
        assert_eq!(result.stop, StopReason::GradientTolerance, "{result:?}");
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-6), "{x:?}");
        // Every accepted step decreases the objective (sufficient decrease).
        assert!(values.windows(2).all(|w| w[1] < w[0]));
        assert!(result.iterations < 200);
    }

    #[test]
    fn quadratic_converges_and_non_finite_start_fails() {
        let scales = [1.0, 10.0, 100.0, 1000.0];
        let quadratic = |x: &[f64], g: &mut [f64]| {
            let mut f = 0.0;
            for i in 0..4 {
                g[i] = scales[i] * (x[i] - 1.0);
                f += 0.5 * scales[i] * (x[i] - 1.0).powi(2);
            }
            f
        };
        let mut x = vec![0.0; 4];
        let result = minimize(quadratic, &mut x, &LbfgsOptions::default(), |_, _| {}).unwrap();
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-9), "{x:?} {result:?}");
        let mut y = vec![0.0];
        assert!(minimize(|_, _| f64::NAN, &mut y, &LbfgsOptions::default(), |_, _| {}).is_err());
    }
}
