//! A law with state handed over a communication step as two tabulated force curves
//! (issue 36, the `table` coupling; docs/cosimulation.md).
//!
//! A coupled friction model with state (NeuralFriction) knows, from its state s_k
//! committed at the start of a communication step, two force curves in the sliding
//! velocity v: the instantaneous one F(s_k, v) and the one-step one F_h(s_k, v), the
//! force after the whole step at v held with the state advanced. The beam blends them
//! over the step, (1 - theta) F + theta F_h at the fraction theta of the step where an
//! internal step ends. Handing each curve over as a tangent at one velocity linearises
//! it in v, and that linearisation was the aging and the learned laws' coupling error;
//! handed over as values at fixed velocities ([`TABLE_VELOCITIES`]) plus the velocity
//! the model was evaluated at, and interpolated piecewise linearly, the curves the beam
//! solves are the law's to within the table's resolution ([`StepCurves`],
//! [`BlendedCurve`]).

use super::law::FrictionLaw;
use serde::{Deserialize, Serialize};

/// The fixed sliding velocities (m/s) at which both curves are tabulated, ascending: 0
/// and +-1e-6 to +-1e-2 m/s a decade apart. Why these: a law with state changes its
/// force over decades of v near 0 (rate-and-state's ln v, LuGre's bristles in
/// presliding), where stick, breakaway and re-stick happen, so the nodes are spaced
/// logarithmically about 0, both signs (a reversal); 0 itself holds the force the beam
/// solves at rest. Above 1e-2 m/s the curves vary slowly, and the velocity the model was
/// evaluated at (v_rel in slip) is a node of its own. Measured through the coupling lab
/// (tests/fmu/coupling_lab.rs): with these nodes all four laws with state meet issue
/// 36's bounds from h = 2e-3 to 1e-4 s; with nodes only around the evaluated velocity
/// the loading phase crept at 1e-4 s.
pub const TABLE_VELOCITIES: [f64; 11] = [
    -1e-2, -1e-3, -1e-4, -1e-5, -1e-6, 0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2,
];

/// Both curves of a communication step: their values at [`TABLE_VELOCITIES`] and at
/// the velocity `velocity` the model was evaluated at. For a memoryless law both are
/// the law's F(v).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepCurves {
    /// F(s_k, v_i) (N) at each of [`TABLE_VELOCITIES`].
    pub force: [f64; TABLE_VELOCITIES.len()],
    /// F_h(s_k, v_i) (N) at each of [`TABLE_VELOCITIES`].
    pub step_force: [f64; TABLE_VELOCITIES.len()],
    /// The velocity (m/s) the model was evaluated at, a further node.
    pub velocity: f64,
    /// F(s_k, velocity) (N).
    pub force_at_velocity: f64,
    /// F_h(s_k, velocity) (N).
    pub step_force_at_velocity: f64,
}

/// Nodes of [`BlendedCurve`]: the table's and the evaluated velocity.
const NODES: usize = TABLE_VELOCITIES.len() + 1;

/// The blend (1 - theta) F + theta F_h of [`StepCurves`], piecewise linear between the
/// nodes and continued beyond the end nodes along the end segments, as a memoryless
/// law that the contact's slip solve takes like any other (`contact::newton`).
#[derive(Clone, Copy, Debug)]
pub struct BlendedCurve {
    velocities: [f64; NODES],
    forces: [f64; NODES],
    /// How many of the nodes are distinct (the evaluated velocity may be a table node).
    len: usize,
}

impl StepCurves {
    /// The blend at `theta` in [0, 1] (0 the instantaneous curve, 1 the one-step one).
    pub fn blended(&self, theta: f64) -> BlendedCurve {
        let mix = |f: f64, fh: f64| (1.0 - theta) * f + theta * fh;
        let mut velocities = [0.0; NODES];
        let mut forces = [0.0; NODES];
        let mut len = 0;
        let mut inserted = !self.velocity.is_finite();
        for (i, &v) in TABLE_VELOCITIES.iter().enumerate() {
            if !inserted && self.velocity <= v {
                inserted = true;
                if self.velocity < v {
                    velocities[len] = self.velocity;
                    forces[len] = mix(self.force_at_velocity, self.step_force_at_velocity);
                    len += 1;
                }
            }
            velocities[len] = v;
            forces[len] = mix(self.force[i], self.step_force[i]);
            len += 1;
        }
        if !inserted {
            velocities[len] = self.velocity;
            forces[len] = mix(self.force_at_velocity, self.step_force_at_velocity);
            len += 1;
        }
        BlendedCurve {
            velocities,
            forces,
            len,
        }
    }
}

impl BlendedCurve {
    /// The force (N) and slope (N s/m) at `v` (m/s).
    pub fn at(&self, v: f64) -> (f64, f64) {
        let xs = &self.velocities[..self.len];
        let ys = &self.forces[..self.len];
        // The segment: the first whose right end lies above v, the end ones beyond.
        let i = xs[1..self.len - 1]
            .iter()
            .position(|&x| v < x)
            .unwrap_or(self.len - 2);
        let slope = (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]);
        (ys[i] + slope * (v - xs[i]), slope)
    }
}

impl FrictionLaw for BlendedCurve {
    fn name(&self) -> &str {
        "tabulated step curves"
    }

    fn sliding_force(&mut self, sliding_velocity: f64, _normal_force: f64) -> f64 {
        self.at(sliding_velocity).0
    }

    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, _normal_force: f64) -> (f64, f64) {
        self.at(sliding_velocity)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curves(velocity: f64) -> StepCurves {
        // F = 10 + v, F_h = 20 - 2 v: linear, so the interpolant is exact everywhere.
        StepCurves {
            force: TABLE_VELOCITIES.map(|v| 10.0 + v),
            step_force: TABLE_VELOCITIES.map(|v| 20.0 - 2.0 * v),
            velocity,
            force_at_velocity: 10.0 + velocity,
            step_force_at_velocity: 20.0 - 2.0 * velocity,
        }
    }

    #[test]
    fn a_linear_curve_is_interpolated_and_extended_exactly() {
        for velocity in [-0.3, -1e-2, -5e-4, 0.0, 2e-6, 0.05] {
            let c = curves(velocity);
            for theta in [0.0, 0.25, 1.0] {
                let b = c.blended(theta);
                for v in [-1.0, -2e-2, -7e-3, -3e-6, 0.0, 4e-5, 1e-2, 0.2] {
                    let (f, s) = b.at(v);
                    let want = (1.0 - theta) * (10.0 + v) + theta * (20.0 - 2.0 * v);
                    let want_slope = (1.0 - theta) - 2.0 * theta;
                    assert!(
                        (f - want).abs() < 1e-12,
                        "{velocity} {theta} {v}: {f} {want}"
                    );
                    assert!((s - want_slope).abs() < 1e-6, "{velocity} {theta} {v}: {s}");
                }
            }
        }
    }

    #[test]
    fn the_nodes_are_met_and_the_evaluated_velocity_is_one() {
        // A curve that is not linear: the nodes' values are met, between them the chord.
        let mut c = curves(0.05);
        c.force = TABLE_VELOCITIES.map(|v| v.abs().sqrt());
        c.force_at_velocity = 7.0;
        let b = c.blended(0.0);
        assert_eq!(b.len, NODES);
        for (v, f) in TABLE_VELOCITIES.iter().zip(&c.force) {
            assert_eq!(b.at(*v).0, *f);
        }
        assert_eq!(b.at(0.05).0, 7.0);
        let mid = b.at(0.03).0;
        let at_node = 1e-2_f64.sqrt();
        let chord = at_node + (7.0 - at_node) * (0.03 - 1e-2) / (0.05 - 1e-2);
        assert!((mid - chord).abs() < 1e-12);
        // On a table node, the evaluated velocity is not doubled.
        assert_eq!(curves(1e-3).blended(0.5).len, NODES - 1);
    }
}
