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
    callback(
        &IterationInfo {
            iteration: 0,
            value,
            gradient_norm: max_abs(&gradient),
            evaluations,
            step: 0.0,
        },
        x,
    );

    // (s, y, 1 / s'y), newest last.
    let mut memory: VecDeque<(Vec<f64>, Vec<f64>, f64)> = VecDeque::with_capacity(options.history);
    let mut direction = vec![0.0; n];
    let mut alphas = vec![0.0; options.history.max(1)];
    let mut x_trial = vec![0.0; n];
    let mut g_trial = vec![0.0; n];
    let mut iterations = 0;
    let stop = loop {
        if max_abs(&gradient) <= options.gradient_tolerance {
            break StopReason::GradientTolerance;
        }
        if iterations >= options.max_iterations {
            break StopReason::MaxIterations;
        }
        if evaluations >= options.max_evaluations {
            break StopReason::MaxEvaluations;
        }

        // d = -H g by the two-loop recursion.
        direction.copy_from_slice(&gradient);
        for (k, (s, y, rho)) in memory.iter().enumerate().rev() {
            let a = rho * dot(s, &direction);
            alphas[k] = a;
            direction.iter_mut().zip(y).for_each(|(q, yi)| *q -= a * yi);
        }
        if let Some((s, y, _)) = memory.back() {
            let gamma = dot(s, y) / dot(y, y);
            direction.iter_mut().for_each(|q| *q *= gamma);
        }
        for (k, (s, y, rho)) in memory.iter().enumerate() {
            let b = rho * dot(y, &direction);
            let a = alphas[k];
            direction
                .iter_mut()
                .zip(s)
                .for_each(|(r, si)| *r += (a - b) * si);
        }
        direction.iter_mut().for_each(|r| *r = -*r);
        let mut slope = dot(&gradient, &direction);
        // Also catches NaN: a NaN slope is not a descent direction either.
        if slope.is_nan() || slope >= 0.0 || !slope.is_finite() {
            // Lost descent (rounding): restart from steepest descent.
            memory.clear();
            direction
                .iter_mut()
                .zip(&gradient)
                .for_each(|(d, g)| *d = -g);
            slope = -dot(&gradient, &gradient);
        }
        let initial_step = if memory.is_empty() {
            // Unit-length first step: the gradient's scale says nothing about curvature.
            1.0 / dot(&gradient, &gradient).sqrt()
        } else {
            1.0
        };

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

        // s = x_new - x, y = g_new - g.
        let (mut s, mut y) = match memory.len() == options.history.max(1) {
            true => {
                let (s, y, _) = memory.pop_front().unwrap_or_default();
                (s, y)
            }
            false => (vec![0.0; n], vec![0.0; n]),
        };
        for i in 0..n {
            s[i] = x_trial[i] - x[i];
            y[i] = g_trial[i] - gradient[i];
        }
        let sy = dot(&s, &y);
        if sy > f64::EPSILON * dot(&y, &y) {
            memory.push_back((s, y, 1.0 / sy));
        }
        x.copy_from_slice(&x_trial);
        gradient.copy_from_slice(&g_trial);
        let previous = value;
        value = new_value;
        callback(
            &IterationInfo {
                iteration: iterations,
                value,
                gradient_norm: max_abs(&gradient),
                evaluations,
                step,
            },
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
    let c1 = options.sufficient_decrease;
    let c2 = options.curvature;
    let mut evaluations = 0;
    let mut evaluate = |alpha: f64, x_trial: &mut [f64], g_trial: &mut [f64]| {
        for ((xt, xi), di) in x_trial.iter_mut().zip(x).zip(direction) {
            *xt = xi + alpha * di;
        }
        let value = objective(x_trial, g_trial);
        Point {
            alpha,
            value,
            slope: dot(g_trial, direction),
        }
    };
    let armijo_fails = |p: Point| !p.value.is_finite() || p.value > value0 + c1 * p.alpha * slope0;
    let curvature_holds = |p: Point| p.slope.abs() <= -c2 * slope0;

    let start = Point {
        alpha: 0.0,
        value: value0,
        slope: slope0,
    };
    let mut previous = start;
    let mut alpha = initial_step;
    // Bracketing phase (Alg. 3.5): find an interval that contains a Wolfe point.
    let (mut lo, mut hi) = loop {
        let p = evaluate(alpha, x_trial, g_trial);
        evaluations += 1;
        if armijo_fails(p) || (evaluations > 1 && p.value >= previous.value) {
            break (previous, p);
        }
        if curvature_holds(p) {
            return LineSearch {
                accepted: Some((p.alpha, p.value)),
                evaluations,
            };
        }
        if p.slope >= 0.0 {
            break (p, previous);
        }
        if evaluations >= budget {
            // Still descending after the budget: take the last (Armijo) point.
            return LineSearch {
                accepted: Some((p.alpha, p.value)),
                evaluations,
            };
        }
        previous = p;
        alpha *= 2.0;
    };
    // Zoom phase (Alg. 3.6): lo satisfies sufficient decrease and has the lowest value.
    while evaluations < budget && (hi.alpha - lo.alpha).abs() > 1e-14 * lo.alpha.abs().max(1e-300) {
        let p = evaluate(cubic_step(lo, hi), x_trial, g_trial);
        evaluations += 1;
        if armijo_fails(p) || p.value >= lo.value {
            hi = p;
        } else {
            if curvature_holds(p) {
                return LineSearch {
                    accepted: Some((p.alpha, p.value)),
                    evaluations,
                };
            }
            if p.slope * (hi.alpha - lo.alpha) >= 0.0 {
                hi = lo;
            }
            lo = p;
        }
    }
    // Out of budget: fall back to the best point with sufficient decrease, if any.
    if lo.alpha > 0.0 {
        let p = evaluate(lo.alpha, x_trial, g_trial);
        evaluations += 1;
        if p.value.is_finite() && p.value < value0 {
            return LineSearch {
                accepted: Some((p.alpha, p.value)),
                evaluations,
            };
        }
    }
    LineSearch {
        accepted: None,
        evaluations,
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
