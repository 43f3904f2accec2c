//! Element matrices: the eight-node serendipity quadrilateral (Q8) in plane stress and
//! the two-node Euler-Bernoulli Hermite beam.
//!
//! Q8 is used rather than the bilinear Q4 because Q4 locks in bending with one element
//! through the height (-62 % tip error at 100 x 1 elements, see shared notes); Q8
//! represents the linear bending-stress field and converges (Zienkiewicz and Taylor, The
//! Finite Element Method, Vol. 1, Sec. 6.5).

/// Gauss-Legendre points and weights, 3 x 3 rule (exact for degree 5 per direction).
pub(crate) const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// Natural coordinates (xi, eta) of the Q8 nodes: corners counter-clockwise from
/// (-1, -1), then the mid-sides of edges 0-1, 1-2, 2-3, 3-0.
pub const Q8_NODES: [(f64, f64); 8] = [
    (-1.0, -1.0),
    (1.0, -1.0),
    (1.0, 1.0),
    (-1.0, 1.0),
    (0.0, -1.0),
    (1.0, 0.0),
    (0.0, 1.0),
    (-1.0, 0.0),
];

/// Q8 shape functions N_a and their derivatives dN_a/dxi, dN_a/deta at (xi, eta).
pub(crate) fn q8_shape(xi: f64, eta: f64) -> ([f64; 8], [f64; 8], [f64; 8]) {
    let mut n = [0.0; 8];
    let mut dxi = [0.0; 8];
    let mut deta = [0.0; 8];
    for (a, &(xa, ea)) in Q8_NODES.iter().enumerate() {
        if a < 4 {
            // N = 1/4 (1 + xi xa)(1 + eta ea)(xi xa + eta ea - 1)
            let (p, q) = (1.0 + xi * xa, 1.0 + eta * ea);
            let r = xi * xa + eta * ea - 1.0;
            n[a] = 0.25 * p * q * r;
            dxi[a] = 0.25 * xa * q * (r + p);
            deta[a] = 0.25 * ea * p * (r + q);
        } else if xa == 0.0 {
            // N = 1/2 (1 - xi^2)(1 + eta ea)
            n[a] = 0.5 * (1.0 - xi * xi) * (1.0 + eta * ea);
            dxi[a] = -xi * (1.0 + eta * ea);
            deta[a] = 0.5 * (1.0 - xi * xi) * ea;
        } else {
            // N = 1/2 (1 + xi xa)(1 - eta^2)
            n[a] = 0.5 * (1.0 + xi * xa) * (1.0 - eta * eta);
            dxi[a] = 0.5 * xa * (1.0 - eta * eta);
            deta[a] = -eta * (1.0 + xi * xa);
        }
    }
    (n, dxi, deta)
}

/// Stiffness and consistent mass (16 x 16, dofs ordered ux0, uy0, ux1, uy1, ...) of a
/// plane-stress Q8 element with node coordinates `xy` (m), thickness `thickness` (m),
/// Young's modulus `e` (Pa), Poisson's ratio `nu` and density `rho` (kg/m3):
/// K = int B^T D B t dA, M = int rho t N^T N dA, 3 x 3 Gauss points,
/// D = E / (1 - nu^2) [[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]].
pub fn q8_plane_stress(
    xy: &[(f64, f64); 8],
    thickness: f64,
    e: f64,
    nu: f64,
    rho: f64,
) -> ([[f64; 16]; 16], [[f64; 16]; 16]) {
    let c = e / (1.0 - nu * nu);
    let d = [
        [c, c * nu, 0.0],
        [c * nu, c, 0.0],
        [0.0, 0.0, c * (1.0 - nu) / 2.0],
    ];
    let mut k = [[0.0; 16]; 16];
    let mut m = [[0.0; 16]; 16];
    for &(xi, wx) in &GAUSS3 {
        for &(eta, wy) in &GAUSS3 {
            let (n, dxi, deta) = q8_shape(xi, eta);
            // Jacobian J = [[dx/dxi, dy/dxi], [dx/deta, dy/deta]].
            let (mut j11, mut j12, mut j21, mut j22) = (0.0, 0.0, 0.0, 0.0);
            for a in 0..8 {
                j11 += dxi[a] * xy[a].0;
                j12 += dxi[a] * xy[a].1;
                j21 += deta[a] * xy[a].0;
                j22 += deta[a] * xy[a].1;
            }
            let det = j11 * j22 - j12 * j21;
            let w = wx * wy * det * thickness;
            let mut dx = [0.0; 8];
            let mut dy = [0.0; 8];
            for a in 0..8 {
                dx[a] = (j22 * dxi[a] - j12 * deta[a]) / det;
                dy[a] = (-j21 * dxi[a] + j11 * deta[a]) / det;
            }
            // B columns: strain (exx, eyy, gxy) per dof.
            let mut b = [[0.0; 16]; 3];
            for a in 0..8 {
                b[0][2 * a] = dx[a];
                b[1][2 * a + 1] = dy[a];
                b[2][2 * a] = dy[a];
                b[2][2 * a + 1] = dx[a];
            }
            let mut db = [[0.0; 16]; 3];
            for r in 0..3 {
                for col in 0..16 {
                    db[r][col] = (0..3).map(|s| d[r][s] * b[s][col]).sum();
                }
            }
            for p in 0..16 {
                for q in 0..16 {
                    k[p][q] += w * (0..3).map(|r| b[r][p] * db[r][q]).sum::<f64>();
                }
            }
            for a in 0..8 {
                for bb in 0..8 {
                    let mab = w * rho * n[a] * n[bb];
                    m[2 * a][2 * bb] += mab;
                    m[2 * a + 1][2 * bb + 1] += mab;
                }
            }
        }
    }
    (k, m)
}

/// Stiffness and consistent mass of a two-node Euler-Bernoulli beam element of length
/// `l` (m), bending stiffness `ei` (N m2), mass per length `rho_a` (kg/m); dofs
/// (w0, theta0, w1, theta1) (Przemieniecki, Theory of Matrix Structural Analysis, 1968):
/// K = EI / l^3 [[12, 6l, -12, 6l], ...], M = rho A l / 420 [[156, 22l, 54, -13l], ...].
pub fn hermite_beam(l: f64, ei: f64, rho_a: f64) -> ([[f64; 4]; 4], [[f64; 4]; 4]) {
    let kc = ei / l.powi(3);
    let k = [
        [12.0, 6.0 * l, -12.0, 6.0 * l],
        [6.0 * l, 4.0 * l * l, -6.0 * l, 2.0 * l * l],
        [-12.0, -6.0 * l, 12.0, -6.0 * l],
        [6.0 * l, 2.0 * l * l, -6.0 * l, 4.0 * l * l],
    ]
    .map(|row| row.map(|v| v * kc));
    let mc = rho_a * l / 420.0;
    let m = [
        [156.0, 22.0 * l, 54.0, -13.0 * l],
        [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
        [54.0, 13.0 * l, 156.0, -22.0 * l],
        [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
    ]
    .map(|row| row.map(|v| v * mc));
    (k, m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rectangle(a: f64, b: f64) -> [(f64, f64); 8] {
        Q8_NODES.map(|(xi, eta)| ((xi + 1.0) * a / 2.0, (eta + 1.0) * b / 2.0))
    }

    #[test]
    fn q8_shape_functions_are_a_partition_of_unity_and_interpolate() {
        for &(xi, eta) in &[(0.3, -0.7), (0.0, 0.0), (-0.9, 0.2)] {
            let (n, dxi, deta) = q8_shape(xi, eta);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(dxi.iter().sum::<f64>().abs() < 1e-14);
            assert!(deta.iter().sum::<f64>().abs() < 1e-14);
        }
        for (a, &(xa, ea)) in Q8_NODES.iter().enumerate() {
            let (n, _, _) = q8_shape(xa, ea);
            for (b, &nb) in n.iter().enumerate() {
                assert!((nb - if a == b { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn q8_mass_sums_to_element_mass_and_rigid_motion_is_strain_free() {
        let (a, b, t, rho) = (0.02, 0.01, 1.0, 1000.0);
        let (k, m) = q8_plane_stress(&rectangle(a, b), t, 200e9, 0.3, rho);
        // Translation in x: sum over x-dofs of M equals the element mass.
        let total: f64 = (0..8)
            .flat_map(|p| (0..8).map(move |q| (p, q)))
            .map(|(p, q)| m[2 * p][2 * q])
            .sum();
        assert!((total - rho * a * b * t).abs() < 1e-12 * rho * a * b);
        // Rigid translation and rotation give zero force.
        let xy = rectangle(a, b);
        let rigid: [Vec<f64>; 3] = [
            (0..16)
                .map(|i| if i % 2 == 0 { 1.0 } else { 0.0 })
                .collect(),
            (0..16)
                .map(|i| if i % 2 == 1 { 1.0 } else { 0.0 })
                .collect(),
            (0..16)
                .map(|i| {
                    if i % 2 == 0 {
                        -xy[i / 2].1
                    } else {
                        xy[i / 2].0
                    }
                })
                .collect(),
        ];
        for u in &rigid {
            for row in &k {
                let f: f64 = row.iter().zip(u).map(|(a, b)| a * b).sum();
                assert!(f.abs() < 1e-3, "rigid motion force {f}");
            }
        }
    }

    #[test]
    fn beam_element_cantilever_is_exact_for_tip_load() {
        // One clamped element: tip compliance l^3 / (3 EI).
        let (l, ei) = (2.0, 16_666.67);
        let (k, m) = hermite_beam(l, ei, 10.0);
        let (a, b, c) = (k[2][2], k[2][3], k[3][3]);
        let compliance = c / (a * c - b * b);
        assert!((compliance - l.powi(3) / (3.0 * ei)).abs() < 1e-12 * compliance);
        // Translational mass of the element: total rho A l.
        let total = m[0][0] + m[0][2] + m[2][0] + m[2][2];
        assert!((total - 20.0).abs() < 1e-12);
    }
}
