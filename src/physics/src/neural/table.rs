//! The neural law tabulated at initialisation (`friction.inference = table`): a lookup
//! and a cubic instead of a network evaluation in the time loop.
//!
//! # The tables
//! Over the network's training range of the sliding velocity (the range its input is
//! clamped to): v in [v_min, v_max], for the signed variant the magnitude |v| in
//! [0, max |v|], and F = sign(v) T(|v|), so that the jump at v = 0 stays exact.
//! - In the time loop the normal force is fixed (the scene's, the FMU's input), so the
//!   law is tabulated in v alone at that force (clamped to the training range, as the
//!   network clamps it): one row.
//! - The first call at another normal force builds the table over velocity x normal
//!   force, F_n in [F_min, F_max] of the training range, once, and the law uses it from
//!   then on. Its rows are at normal forces spaced evenly; nodes along v are shared by
//!   every row.
//!
//! Between two nodes each row is the cubic Hermite interpolant of the network's values
//! and exact slopes (forward mode) at the nodes; across F_n, cubic Lagrange
//! interpolation through the four nearest rows. The interpolant is C1 in v, and its
//! slope, which the slip solve's Newton iteration uses, is its exact derivative. Outside
//! the range the table is constant, as the network is. The interval of v is found
//! through a uniform index of buckets, each listing the intervals it overlaps.
//!
//! # Refinement and the verified error
//! - Along v: from 32 equal intervals, an interval is halved while the interpolant
//!   misses the network by more than half of [`TABLE_TOLERANCE`] at a quarter, the
//!   middle or three quarters of it, on the lowest, middle or highest row (the plain
//!   network's smoothed jump at v = 0 takes intervals of ~1e-5 m/s, the rest ~1e-2).
//! - Across F_n (the two-dimensional table): from 5 rows, the rows are doubled (to 65 at
//!   most) while the table misses the network by more than half the tolerance halfway
//!   between two rows. The plain network's zero crossing moves with F_n, which rows
//!   resolve poorly: its two-dimensional table stops at 65 rows with an error of a few
//!   1e-3 N there.
//! - The largest error is then measured on points the refinement did not look at: at
//!   1/8, 3/8, 5/8 and 7/8 of every interval, on every row and halfway between rows.
//!   That is [`Table::largest_error`], reported, and checked in the tests against dense
//!   sampling.
//!
//! A network with inputs besides the sliding velocity and the normal force is refused:
//! the table has two dimensions ([`TableLaw::refusal`]).

use super::law::NeuralLaw;
use super::weights::{network_input_range, FeatureRole, Variant};
use crate::elementary::signum_or_zero;

/// The error (N, target units) the table is refined to: far below the networks' own
/// error against their data (RMS 0.06 N for the signed network, 2 N for the plain one).
pub const TABLE_TOLERANCE: f64 = 1e-5;

/// Intervals along v before refinement.
const START_INTERVALS: usize = 32;
/// Most halvings of an interval: 32 x 2^24 intervals would resolve 5e-8 of the range.
const MAX_DEPTH: u32 = 24;
/// Rows across F_n to start from, and the most.
const START_ROWS: usize = 5;
const MAX_ROWS: usize = 65;
/// Buckets of the index along v per interval of the table.
const BUCKETS_PER_INTERVAL: usize = 4;

/// A network's force and slope tabulated over its training range of the sliding
/// velocity, at one normal force or over a range of them (see the module notes).
#[derive(Clone, Debug)]
pub struct Table {
    /// Velocity nodes (m/s; |v| for the signed variant), increasing.
    nodes: Vec<f64>,
    /// Bucket b covers [nodes[0] + b w, nodes[0] + (b + 1) w) with w = 1 / `per_bucket`
    /// (per m/s); `buckets[b]` is the interval holding its start, and the intervals up to
    /// `buckets[b + 1]` are the ones it overlaps.
    buckets: Vec<usize>,
    per_bucket: f64,
    /// Normal force of the first row (N) and between rows (N; 0 with one row).
    force_first: f64,
    force_step: f64,
    rows: usize,
    /// Row r, interval k at r * intervals + k: the Hermite cubic of the interval in
    /// powers of d = v - nodes[k], c0 + c1 d + c2 d^2 + c3 d^3 (N, N s/m, ...).
    cubics: Vec<[f64; 4]>,
    /// F = sign(v) T(|v|).
    signed: bool,
    /// The largest error against the network found at build (N).
    largest_error: f64,
}

/// The exact network as a function of (velocity, normal force): force and slope.
struct Exact<'a> {
    law: &'a mut NeuralLaw,
    /// The table's velocity is |v| (signed variant): evaluate at the magnitude's side,
    /// v > 0, also at v = 0, where the law itself gives 0.
    signed: bool,
}

impl Exact<'_> {
    fn at(&mut self, v: f64, f_n: f64) -> (f64, f64) {
        let v = if self.signed {
            v.max(f64::MIN_POSITIVE)
        } else {
            v
        };
        self.law.force_and_slope(v, f_n)
    }
}

/// The cubic Hermite interpolant on [a, b] of values (y0, y1) and slopes (m0, m1), in
/// powers of d = v - a: [c0, c1, c2, c3].
fn cubic(a: f64, b: f64, (y0, m0): (f64, f64), (y1, m1): (f64, f64)) -> [f64; 4] {
    let h = b - a;
    let secant = (y1 - y0) / h;
    [
        y0,
        m0,
        (3.0 * secant - 2.0 * m0 - m1) / h,
        (m0 + m1 - 2.0 * secant) / (h * h),
    ]
}

/// Cubic Hermite interpolation on [a, b] of values (y0, y1) and slopes (m0, m1) at
/// `v`: the value and its derivative.
#[inline(always)]
fn hermite(a: f64, b: f64, (y0, m0): (f64, f64), (y1, m1): (f64, f64), v: f64) -> (f64, f64) {
    let h = b - a;
    let t = (v - a) / h;
    let (t2, s) = (t * t, 1.0 - t);
    let value = (1.0 + 2.0 * t) * s * s * y0 + t * s * s * h * m0 + t2 * (3.0 - 2.0 * t) * y1
        - t2 * s * h * m1;
    let slope = 6.0 * t * (t - 1.0) * (y0 - y1) / h
        + (1.0 - 4.0 * t + 3.0 * t2) * m0
        + (3.0 * t2 - 2.0 * t) * m1;
    (value, slope)
}

impl Table {
    /// Tabulates `law` (exact inference, a friction law of the beam: see
    /// [`TableLaw::refusal`] and `NeuralLaw::beam_problem`) at the normal forces from
    /// `force_lo` to `force_hi` (N; one row if equal) and verifies the table.
    fn build(law: &mut NeuralLaw, force_lo: f64, force_hi: f64) -> Table {
        let model = law.model().clone();
        let signed = model.variant == Variant::Signed;
        let velocity = law.velocity().expect("checked by TableLaw::refusal");
        let (v_lo, v_hi) = network_input_range(&model.features[velocity], model.variant);
        let mut exact = Exact { law, signed };
        let check_rows: Vec<f64> = if force_hi > force_lo {
            vec![force_lo, 0.5 * (force_lo + force_hi), force_hi]
        } else {
            vec![force_lo]
        };
        let nodes = refine_nodes(&mut exact, v_lo, v_hi, &check_rows);
        let intervals = nodes.len() - 1;
        let mut table = Table {
            buckets: Vec::new(),
            per_bucket: 0.0,
            nodes,
            force_first: force_lo,
            force_step: 0.0,
            rows: 1,
            cubics: Vec::new(),
            signed,
            largest_error: 0.0,
        };
        table.index(intervals * BUCKETS_PER_INTERVAL);
        if force_hi > force_lo {
            let mut rows = START_ROWS;
            loop {
                table.fill_rows(&mut exact, rows, force_lo, force_hi);
                let between = table.largest_error_at(&mut exact, &[0.5], true);
                if between <= 0.5 * TABLE_TOLERANCE || rows >= MAX_ROWS {
                    break;
                }
                rows = 2 * (rows - 1) + 1;
            }
        } else {
            table.fill_rows(&mut exact, 1, force_lo, force_hi);
        }
        table.largest_error =
            table.largest_error_at(&mut exact, &[0.125, 0.375, 0.625, 0.875], false);
        table
    }

    /// The bucket index of the intervals along v, `count` buckets.
    fn index(&mut self, count: usize) {
        let (first, last) = (self.nodes[0], self.nodes[self.nodes.len() - 1]);
        self.per_bucket = count as f64 / (last - first);
        let intervals = self.nodes.len() - 1;
        self.buckets = (0..=count)
            .map(|b| {
                let start = first + b as f64 / self.per_bucket;
                self.nodes
                    .partition_point(|&node| node <= start)
                    .clamp(1, intervals)
                    - 1
            })
            .collect();
    }

    /// The interval k, nodes[k] <= v <= nodes[k + 1], of `v` inside the node range.
    #[inline]
    fn interval(&self, v: f64) -> usize {
        let last = self.buckets.len() - 2;
        let b = (((v - self.nodes[0]) * self.per_bucket) as usize).min(last);
        let (lo, hi) = (self.buckets[b], self.buckets[b + 1]);
        // Dense regions put several intervals in a bucket: search among them.
        lo + self.nodes[lo + 1..=hi + 1].partition_point(|&node| node < v)
    }

    /// Fills `rows` rows evenly from `force_lo` to `force_hi` at the nodes.
    fn fill_rows(&mut self, exact: &mut Exact<'_>, rows: usize, force_lo: f64, force_hi: f64) {
        self.rows = rows;
        self.force_step = if rows > 1 {
            (force_hi - force_lo) / (rows - 1) as f64
        } else {
            0.0
        };
        self.cubics.clear();
        for r in 0..rows {
            let f_n = self.row_force(r);
            let points: Vec<(f64, f64)> = self.nodes.iter().map(|&v| exact.at(v, f_n)).collect();
            for (pair, ends) in self.nodes.windows(2).zip(points.windows(2)) {
                self.cubics.push(cubic(pair[0], pair[1], ends[0], ends[1]));
            }
        }
    }

    fn row_force(&self, row: usize) -> f64 {
        self.force_first + self.force_step * row as f64
    }

    /// The largest |table - network| at the fractions `at` of every interval, on every
    /// row and halfway between rows, or only halfway between rows (`between_only`).
    fn largest_error_at(&self, exact: &mut Exact<'_>, at: &[f64], between_only: bool) -> f64 {
        let mut forces = Vec::new();
        for r in 0..self.rows {
            if !between_only {
                forces.push(self.row_force(r));
            }
            if r + 1 < self.rows {
                forces.push(self.row_force(r) + 0.5 * self.force_step);
            }
        }
        let mut largest: f64 = 0.0;
        for pair in self.nodes.windows(2) {
            for &t in at {
                let v = pair[0] + t * (pair[1] - pair[0]);
                for &f_n in &forces {
                    let (table, _) = self.magnitude(v, f_n);
                    let (network, _) = exact.at(v, f_n);
                    largest = largest.max((table - network).abs());
                }
            }
        }
        largest
    }

    /// The table at velocity (or |v|) `v` inside the node range and normal force `f_n`:
    /// the value and dT/dv.
    #[inline]
    fn magnitude(&self, v: f64, f_n: f64) -> (f64, f64) {
        let n = self.nodes.len();
        let (first, last) = (self.nodes[0], self.nodes[n - 1]);
        let (v, inside) = if v < first {
            (first, false)
        } else if v > last {
            (last, false)
        } else {
            (v, true)
        };
        let k = self.interval(v);
        let d = v - self.nodes[k];
        let intervals = n - 1;
        let row = |r: usize| {
            let [c0, c1, c2, c3] = self.cubics[r * intervals + k];
            (
                c0 + d * (c1 + d * (c2 + d * c3)),
                c1 + d * (2.0 * c2 + d * 3.0 * c3),
            )
        };
        let (value, slope) = if self.rows == 1 {
            row(0)
        } else {
            // Cubic Lagrange through rows r0 .. r0 + 3 at s (in rows from the first).
            let last = (self.rows - 1) as f64;
            let s = ((f_n - self.force_first) / self.force_step).clamp(0.0, last);
            let r0 = (s.floor() as usize).saturating_sub(1).min(self.rows - 4);
            let x = s - r0 as f64;
            let weights = [
                -(x - 1.0) * (x - 2.0) * (x - 3.0) / 6.0,
                x * (x - 2.0) * (x - 3.0) / 2.0,
                -x * (x - 1.0) * (x - 3.0) / 2.0,
                x * (x - 1.0) * (x - 2.0) / 6.0,
            ];
            let (mut value, mut slope) = (0.0, 0.0);
            for (j, w) in weights.iter().enumerate() {
                let (v, s) = row(r0 + j);
                value += w * v;
                slope += w * s;
            }
            (value, slope)
        };
        (value, if inside { slope } else { 0.0 })
    }

    /// The force and dF/dv at (v, F_n) (m/s, N).
    #[inline]
    fn at(&self, v: f64, f_n: f64) -> (f64, f64) {
        if self.signed {
            let (value, slope) = self.magnitude(v.abs(), f_n);
            (signum_or_zero(v) * value, slope)
        } else {
            self.magnitude(v, f_n)
        }
    }

    /// The largest error against the network found at build (N): at 1/8, 3/8, 5/8 and
    /// 7/8 of every interval, on every row and halfway between rows.
    pub fn largest_error(&self) -> f64 {
        self.largest_error
    }

    /// Nodes along the sliding velocity.
    pub fn nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Rows across the normal force.
    pub fn rows(&self) -> usize {
        self.rows
    }
}

/// The neural law evaluated from tables (`friction.inference = table`): the table at
/// the normal force it was built for, and the one over velocity x normal force once
/// another force is asked for (see the module notes).
#[derive(Clone, Debug)]
pub struct TableLaw {
    /// The exact network, for the two-dimensional table if it is needed.
    law: NeuralLaw,
    /// The normal force of `fixed` (N), clamped to the training range.
    fixed_force: f64,
    fixed: Table,
    general: Option<Table>,
}

impl TableLaw {
    /// Why `law` cannot be tabulated, or None: the table spans the sliding velocity and
    /// the normal force, so a network with other inputs (fixed or not) is refused.
    pub fn refusal(law: &NeuralLaw) -> Option<String> {
        let model = law.model();
        let names = model.feature_names().join(", ");
        if law.velocity().is_none() {
            return Some(format!(
                "a table needs a sliding-velocity input, and this network reads {names}; use exact or f32"
            ));
        }
        let others: Vec<&str> = model
            .features
            .iter()
            .filter(|f| {
                !matches!(
                    f.role,
                    FeatureRole::SlidingVelocity | FeatureRole::NormalForce
                )
            })
            .map(|f| f.name.as_str())
            .collect();
        if others.is_empty() {
            None
        } else {
            Some(format!(
                "the table spans two inputs, the sliding velocity and the normal force, and this network reads {} ({names}): {} cannot be tabulated; use exact or f32",
                model.features.len(),
                others.join(", ")
            ))
        }
    }

    /// Tabulates `law` at the normal force `normal_force` (N) and verifies the table.
    /// `law` must pass [`TableLaw::refusal`] and `NeuralLaw::beam_problem`.
    pub fn build(mut law: NeuralLaw, normal_force: f64) -> TableLaw {
        let fixed_force = law.clamped_normal_force(normal_force);
        let fixed = Table::build(&mut law, fixed_force, fixed_force);
        TableLaw {
            law,
            fixed_force,
            fixed,
            general: None,
        }
    }

    /// The table at the normal force the law was built for.
    pub fn fixed(&self) -> &Table {
        &self.fixed
    }

    /// The table over velocity x normal force, built now if it was not yet.
    /// The table's force (N) and its exact derivative in v (N s/m; the slope of the
    /// magnitude for the signed variant, which is even in v) at `sliding_velocity`
    /// (m/s) and `normal_force` (N): the table built at the run's normal force, or the
    /// general one at another.
    pub fn force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        let table = if self.law.clamped_normal_force(normal_force) == self.fixed_force {
            &self.fixed
        } else {
            self.general()
        };
        table.at(sliding_velocity, normal_force)
    }

    pub fn general(&mut self) -> &Table {
        let TableLaw { law, general, .. } = self;
        general.get_or_insert_with(|| {
            let (lo, hi) = law.normal_force_range();
            Table::build(law, lo, hi)
        })
    }

    /// The largest error against the network found at build over the tables built so
    /// far (N).
    pub fn largest_error(&self) -> f64 {
        let general = self.general.as_ref().map_or(0.0, Table::largest_error);
        self.fixed.largest_error().max(general)
    }
}

/// The velocity nodes: START_INTERVALS equal intervals of [lo, hi], halved while the
/// Hermite interpolant misses the network by more than TABLE_TOLERANCE / 2 at 1/4, 1/2
/// or 3/4 of an interval on one of `rows`.
fn refine_nodes(exact: &mut Exact<'_>, lo: f64, hi: f64, rows: &[f64]) -> Vec<f64> {
    let at = |exact: &mut Exact<'_>, v: f64| -> Vec<(f64, f64)> {
        rows.iter().map(|&f_n| exact.at(v, f_n)).collect()
    };
    let mut nodes = vec![lo];
    let mut start = (lo, at(exact, lo));
    for i in 1..=START_INTERVALS {
        let b = lo + (hi - lo) * i as f64 / START_INTERVALS as f64;
        let end = (b, at(exact, b));
        // Depth-first halving: (a, values at a) .. (b, values at b).
        let mut stack = vec![(start.clone(), end.clone(), 0)];
        while let Some(((a, fa), (b, fb), depth)) = stack.pop() {
            let misses = depth < MAX_DEPTH
                && [0.25, 0.5, 0.75].iter().any(|t| {
                    let v = a + t * (b - a);
                    rows.iter()
                        .zip(fa.iter().zip(&fb))
                        .any(|(&f_n, (&ya, &yb))| {
                            let (table, _) = hermite(a, b, ya, yb, v);
                            (table - exact.at(v, f_n).0).abs() > 0.5 * TABLE_TOLERANCE
                        })
                });
            if misses {
                let m = 0.5 * (a + b);
                let fm = at(exact, m);
                // The left half on top: nodes come out in increasing order.
                stack.push(((m, fm.clone()), (b, fb), depth + 1));
                stack.push(((a, fa), (m, fm), depth + 1));
            } else {
                nodes.push(b);
            }
        }
        start = end;
    }
    nodes
}
