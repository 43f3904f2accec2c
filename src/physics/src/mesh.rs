//! Structured mesh of eight-node quadrilaterals (Q8) over the beam's rectangle.
//!
//! x runs along the beam (0 at the clamp, L at the tip), y across its height (the tip
//! deflection direction). Nodes sit on a (2 nx + 1) x (2 ny + 1) grid without the element
//! centres, numbered column by column along x, so that the half-bandwidth of the
//! assembled matrices depends on ny only and the cost per step grows linearly with the
//! length resolution.

/// A structured Q8 mesh of the rectangle [0, length] x [0, height].
#[derive(Clone, Debug)]
pub struct StripMesh {
    /// Elements along the length.
    pub along: usize,
    /// Elements through the height.
    pub through: usize,
    /// Node coordinates (m).
    pub nodes: Vec<(f64, f64)>,
    /// Element connectivity in Q8 order (corners counter-clockwise, then mid-sides).
    pub elements: Vec<[usize; 8]>,
    /// Nodes on the clamped face x = 0, in increasing y.
    pub clamped_nodes: Vec<usize>,
    /// Nodes on the tip face x = L with the weights of the face mean:
    /// mean_y u_y = sum_k w_k u_y(node_k), from Simpson's rule on each quadratic edge
    /// (weights 1/6, 4/6, 1/6 per edge, divided by the number of edges).
    pub tip_face: Vec<(usize, f64)>,
}

impl StripMesh {
    /// Mesh of `along` x `through` elements.
    pub fn new(length: f64, height: f64, along: usize, through: usize) -> Self {
        assert!(along >= 1 && through >= 1);
        let (gx, gy) = (2 * along + 1, 2 * through + 1);
        let is_centre = |i: usize, j: usize| i % 2 == 1 && j % 2 == 1;
        let mut id = vec![usize::MAX; gx * gy];
        let mut nodes = Vec::new();
        for i in 0..gx {
            for j in 0..gy {
                if !is_centre(i, j) {
                    id[i * gy + j] = nodes.len();
                    nodes.push((
                        length * i as f64 / (gx - 1) as f64,
                        height * j as f64 / (gy - 1) as f64,
                    ));
                }
            }
        }
        let at = |i: usize, j: usize| id[i * gy + j];
        let mut elements = Vec::with_capacity(along * through);
        for ex in 0..along {
            for ey in 0..through {
                let (i, j) = (2 * ex, 2 * ey);
                elements.push([
                    at(i, j),
                    at(i + 2, j),
                    at(i + 2, j + 2),
                    at(i, j + 2),
                    at(i + 1, j),
                    at(i + 2, j + 1),
                    at(i + 1, j + 2),
                    at(i, j + 1),
                ]);
            }
        }
        let clamped_nodes = (0..gy).map(|j| at(0, j)).collect();
        let edge_weight = 1.0 / through as f64;
        let mut tip_face: Vec<(usize, f64)> = (0..gy).map(|j| (at(gx - 1, j), 0.0)).collect();
        for e in 0..through {
            tip_face[2 * e].1 += edge_weight / 6.0;
            tip_face[2 * e + 1].1 += edge_weight * 4.0 / 6.0;
            tip_face[2 * e + 2].1 += edge_weight / 6.0;
        }
        Self {
            along,
            through,
            nodes,
            elements,
            clamped_nodes,
            tip_face,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_tip_weights() {
        let m = StripMesh::new(2.0, 0.01, 10, 2);
        // (2 nx + 1)(2 ny + 1) grid points minus nx ny centres.
        assert_eq!(m.nodes.len(), 21 * 5 - 20);
        assert_eq!(m.elements.len(), 20);
        assert_eq!(m.clamped_nodes.len(), 5);
        let total: f64 = m.tip_face.iter().map(|&(_, w)| w).sum();
        assert!((total - 1.0).abs() < 1e-15);
        for &(n, _) in &m.tip_face {
            assert!((m.nodes[n].0 - 2.0).abs() < 1e-12);
        }
    }
}
