//! A general plane mesh of eight-node quadrilaterals (a Gmsh `.msh`, issue 35) assembled
//! in plane stress with the built-in model's own element, `element::q8_plane_stress`:
//! K = int B^T D B t dA and M = int rho t N^T N dA, 3 x 3 Gauss points, per element, summed
//! into M and K over the nodes the elements share. The result is the
//! [`StructureMatrices`] the file readers give (the upper triangle, each entry once), so
//! that `linear_structure::LinearStructure` checks, clamps and orders it as any other.
//!
//! - Rows: the nodes of the 2D elements in increasing Gmsh tag, each with directions 1
//!   (u_x) and 2 (u_y), labelled (tag, direction). Lines and points in the file name
//!   physical groups; they carry no stiffness or mass.
//! - Units are the file's coordinates (m) and the material's (Pa, kg/m3, m).
//! - The elements must be 8-node quadrangles (Gmsh type 16) in the plane z = 0, each with
//!   a Jacobian determinant of one sign at its nine Gauss points: positive when its
//!   corners run counter-clockwise, as Gmsh writes a surface whose normal is +z; an
//!   element whose corners run clockwise (a surface with normal -z) is renumbered
//!   counter-clockwise, which is the same element. A determinant that changes sign or
//!   vanishes is a degenerate or folded element and is refused.
//! - The summation follows the element order and, within an element, the built-in's
//!   (a, then b <= a), so that a mesh with the built-in's nodes and element order
//!   gives the built-in's matrices to the rounding of its coordinates.

use crate::element::{q8_plane_stress, q8_shape, GAUSS3};
use crate::files::{InputFileError, STRUCTURE_FILE};
use crate::short::Short;
use crate::user_structure::{GroupClamp, PlaneStressMaterial, PointLabels, StructureSection};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;
use stickslip_formats::gmsh::{self, GroupError, Mesh};
use stickslip_formats::structure_file::{
    DofLabel, FileText, ReadError, Stored, StructureMatrices, Triplet, Triplets,
};

/// Gmsh's number of the 8-node quadrangle.
const QUAD8: u32 = 16;

/// Why a Gmsh mesh gave no structure: the file, its contents, or what the physics needs
/// of it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlaneMeshError {
    #[error("{0}")]
    File(#[from] InputFileError),
    #[error("{0}")]
    Contents(#[from] ReadError),
    #[error("{file}: no 2D elements: the mesh has nothing to assemble (is the surface in a physical group? Gmsh saves only the elements of physical groups once any is defined)")]
    NoSurface { file: String },
    #[error("{file}, line {line}: element {tag} is a {name} (Gmsh type {number}): only 8-node quadrangles (type 16, the built-in plane stress's Q8) are assembled; mesh with Recombine, Mesh.ElementOrder = 2 and Mesh.SecondOrderIncomplete = 1")]
    UnsupportedElement {
        file: String,
        line: usize,
        tag: u64,
        name: &'static str,
        number: u32,
    },
    #[error(
        "{file}, line {line}: node {tag} has z = {z}: a plane-stress mesh lies in the plane z = 0"
    )]
    NotPlanar {
        file: String,
        line: usize,
        tag: u64,
        z: f64,
    },
    #[error("{file}, line {line}: element {tag} is degenerate or folded: its Jacobian determinant at the Gauss points runs from {} to {} m2, where one sign throughout is needed (are its nodes in Gmsh's order, corners then mid-sides?)", Short(*min), Short(*max))]
    Distorted {
        file: String,
        line: usize,
        tag: u64,
        min: f64,
        max: f64,
    },
    #[error("structure.material is needed with structure.format = gmsh: a mesh file carries no material")]
    NoMaterial,
    #[error("{file}: structure.clamped_groups: {source}")]
    Group { file: String, source: GroupError },
    #[error("{file}: {field}: {source}")]
    PointGroup {
        file: String,
        field: &'static str,
        source: GroupError,
    },
    #[error("{file}: {field}: the physical group '{group}' holds {count} nodes ({nodes}), where a contact or a sensor by group needs exactly one (a physical point, e.g. Physical Point(\"{group}\") = {{3}}; in the .geo), or name the node: {{ node = TAG, direction = D }}")]
    PointGroupSize {
        file: String,
        field: &'static str,
        group: String,
        count: usize,
        nodes: String,
    },
}

/// A `format = "gmsh"` section's mesh assembled with its material, the DOFs its
/// `clamped_groups` fix, and its contact's and sensors' labels, a group's node found in
/// the mesh ([`point_node`]) (the section's fields checked by
/// `StructureSection::check_fields`: the mesh and the material are given).
pub fn read_section(
    section: &StructureSection,
) -> Result<(StructureMatrices, Vec<DofLabel>, PointLabels), PlaneMeshError> {
    let path = section.mesh.clone().unwrap_or_default();
    let material = section.material.ok_or(PlaneMeshError::NoMaterial)?;
    let mesh = read_gmsh(&path)?;
    let file = path.display().to_string();
    let points = section.point_labels(|field, group| point_node(&mesh, &file, field, group))?;
    Ok((
        assemble(&mesh, &file, &material)?,
        group_dofs(&mesh, &file, &section.clamped_groups)?,
        points,
    ))
}

/// The one node of physical group `group`, which the scene's `field` names: a group of
/// no node (no elements in the file) or of several is refused with its count and
/// nodes, an unknown one with the mesh's group names.
pub fn point_node(
    mesh: &Mesh,
    file: &str,
    field: &'static str,
    group: &str,
) -> Result<u64, PlaneMeshError> {
    let nodes = match mesh.group_nodes(group) {
        Ok(nodes) => nodes,
        Err(GroupError::Empty { .. }) => Vec::new(),
        Err(source) => {
            return Err(PlaneMeshError::PointGroup {
                file: file.to_string(),
                field,
                source,
            })
        }
    };
    match nodes[..] {
        [node] => Ok(node),
        _ => {
            const SHOWN: usize = 6;
            let mut list: Vec<String> = nodes.iter().take(SHOWN).map(u64::to_string).collect();
            if nodes.is_empty() {
                list.push("no elements in the file".to_string());
            } else if nodes.len() > SHOWN {
                list.push("...".to_string());
            }
            Err(PlaneMeshError::PointGroupSize {
                file: file.to_string(),
                field,
                group: group.to_string(),
                count: nodes.len(),
                nodes: list.join(", "),
            })
        }
    }
}

/// The mesh in the file at `path`: opened by `files` (missing, special, oversized files
/// refused there), a binary file refused with the option that writes ASCII, then parsed.
pub fn read_gmsh(path: &Path) -> Result<Mesh, PlaneMeshError> {
    let name = path.display().to_string();
    let bytes = STRUCTURE_FILE.read(path)?;
    // Before the UTF-8 check: a binary mesh is not text, and the hint is the format's.
    gmsh::refuse_binary(&name, &bytes)?;
    let text = STRUCTURE_FILE.text(path, bytes)?;
    Ok(gmsh::read_mesh(FileText {
        name: &name,
        text: &text,
    })?)
}

/// The DOF labels the groups fix: each node of each group in each of its directions,
/// once, in increasing order.
pub fn group_dofs(
    mesh: &Mesh,
    file: &str,
    clamps: &[GroupClamp],
) -> Result<Vec<DofLabel>, PlaneMeshError> {
    let mut dofs = BTreeSet::new();
    for clamp in clamps {
        let nodes = mesh
            .group_nodes(&clamp.group)
            .map_err(|source| PlaneMeshError::Group {
                file: file.to_string(),
                source,
            })?;
        for node in nodes {
            for &direction in &clamp.directions {
                dofs.insert(DofLabel { node, direction });
            }
        }
    }
    Ok(dofs.into_iter().collect())
}

/// The plane-stress M and K of the mesh's 2D elements (`file` names the mesh in errors).
pub fn assemble(
    mesh: &Mesh,
    file: &str,
    material: &PlaneStressMaterial,
) -> Result<StructureMatrices, PlaneMeshError> {
    let surface: Vec<&gmsh::Element> = mesh.elements.iter().filter(|e| e.kind.dim == 2).collect();
    if surface.is_empty() {
        return Err(PlaneMeshError::NoSurface {
            file: file.to_string(),
        });
    }
    if let Some(e) = surface.iter().find(|e| e.kind.number != QUAD8) {
        return Err(PlaneMeshError::UnsupportedElement {
            file: file.to_string(),
            line: e.line,
            tag: e.tag,
            name: e.kind.name,
            number: e.kind.number,
        });
    }
    let by_tag: HashMap<u64, &gmsh::Node> = mesh.nodes.iter().map(|n| (n.tag, n)).collect();
    let used: BTreeSet<u64> = surface
        .iter()
        .flat_map(|e| e.nodes.iter().copied())
        .collect();
    let row_of: HashMap<u64, usize> = used.iter().enumerate().map(|(k, &t)| (t, k)).collect();
    for tag in &used {
        let node = by_tag[tag];
        if node.xyz[2] != 0.0 {
            return Err(PlaneMeshError::NotPlanar {
                file: file.to_string(),
                line: node.line,
                tag: *tag,
                z: node.xyz[2],
            });
        }
    }
    let mut k: BTreeMap<(usize, usize), f64> = BTreeMap::new();
    let mut m: BTreeMap<(usize, usize), f64> = BTreeMap::new();
    for e in &surface {
        let mut conn: [u64; 8] = std::array::from_fn(|a| e.nodes[a]);
        let mut xy = conn.map(|t| (by_tag[&t].xyz[0], by_tag[&t].xyz[1]));
        let (min, max) = jacobian_range(&xy);
        if max < 0.0 {
            // Clockwise corners: the same element counter-clockwise (corners 0 3 2 1,
            // mid-sides of 0-3, 3-2, 2-1, 1-0).
            const REVERSED: [usize; 8] = [0, 3, 2, 1, 7, 6, 5, 4];
            conn = REVERSED.map(|a| conn[a]);
            xy = REVERSED.map(|a| xy[a]);
        } else if min.is_nan() || min <= 0.0 {
            return Err(PlaneMeshError::Distorted {
                file: file.to_string(),
                line: e.line,
                tag: e.tag,
                min,
                max,
            });
        }
        let (ke, me) = q8_plane_stress(
            &xy,
            material.thickness,
            material.youngs_modulus,
            material.poisson_ratio,
            material.density,
        );
        let row = |a: usize| 2 * row_of[&conn[a / 2]] + a % 2;
        for a in 0..16 {
            for b in 0..=a {
                let (i, j) = (row(a), row(b));
                let at = (i.min(j), i.max(j));
                *k.entry(at).or_insert(0.0) += ke[a][b];
                *m.entry(at).or_insert(0.0) += me[a][b];
            }
        }
    }
    let size = 2 * used.len();
    let triplets = |map: BTreeMap<(usize, usize), f64>| Triplets {
        size,
        stored: Stored::Upper,
        entries: map
            .into_iter()
            .map(|((row, col), value)| Triplet { row, col, value })
            .collect(),
    };
    Ok(StructureMatrices {
        stiffness: triplets(k),
        mass: triplets(m),
        damping: None,
        dofs: used
            .iter()
            .flat_map(|&node| (1..=2).map(move |direction| DofLabel { node, direction }))
            .collect(),
    })
}

/// The smallest and largest Jacobian determinant det(dx/dxi) of a Q8 at its 3 x 3 Gauss
/// points (m2; the element's area is their weighted sum).
fn jacobian_range(xy: &[(f64, f64); 8]) -> (f64, f64) {
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for &(xi, _) in &GAUSS3 {
        for &(eta, _) in &GAUSS3 {
            let (_, dxi, deta) = q8_shape(xi, eta);
            let (mut j11, mut j12, mut j21, mut j22) = (0.0, 0.0, 0.0, 0.0);
            for a in 0..8 {
                j11 += dxi[a] * xy[a].0;
                j12 += dxi[a] * xy[a].1;
                j21 += deta[a] * xy[a].0;
                j22 += deta[a] * xy[a].1;
            }
            let det = j11 * j22 - j12 * j21;
            range = (range.0.min(det), range.1.max(det));
        }
    }
    range
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One 8-node quadrangle, 2 m x 1 m, its face x = 0 as group "clamp".
    fn one_quad(nodes: &str, element: &str) -> String {
        format!(
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n1 1 \"clamp\"\n$EndPhysicalNames\n\
             $Entities\n0 1 1 0\n4 0 0 0 0 1 0 1 1 0\n1 0 0 0 2 1 0 0 0\n$EndEntities\n\
             $Nodes\n1 8 1 8\n2 1 0 8\n1\n2\n3\n4\n5\n6\n7\n8\n{nodes}$EndNodes\n\
             $Elements\n2 2 1 2\n1 4 8 1\n1 4 1 8\n2 1 {element}\n$EndElements\n"
        )
    }
    const NODES: &str = "0 0 0\n2 0 0\n2 1 0\n0 1 0\n1 0 0\n2 0.5 0\n1 1 0\n0 0.5 0\n";
    const QUAD8: &str = "16 1\n2 1 2 3 4 5 6 7 8\n";
    const STEEL: PlaneStressMaterial = PlaneStressMaterial {
        thickness: 0.1,
        youngs_modulus: 200e9,
        poisson_ratio: 0.3,
        density: 7800.0,
    };

    fn mesh(text: &str) -> Mesh {
        gmsh::read_mesh(FileText {
            name: "q.msh",
            text,
        })
        .unwrap()
    }

    fn assembled(text: &str) -> Result<StructureMatrices, String> {
        assemble(&mesh(text), "q.msh", &STEEL).map_err(|e| e.to_string())
    }

    fn dense(t: &Triplets) -> Vec<Vec<f64>> {
        let mut a = vec![vec![0.0; t.size]; t.size];
        for e in &t.entries {
            a[e.row][e.col] = e.value;
            a[e.col][e.row] = e.value;
        }
        a
    }

    #[test]
    fn one_element_is_the_q8_with_rows_by_tag() {
        let m = assembled(&one_quad(NODES, QUAD8)).unwrap();
        assert_eq!(m.dofs.len(), 16);
        assert_eq!(
            m.dofs[3],
            DofLabel {
                node: 2,
                direction: 2
            }
        );
        let xy = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (0.0, 1.0),
            (1.0, 0.0),
            (2.0, 0.5),
            (1.0, 1.0),
            (0.0, 0.5),
        ];
        let (ke, me) = q8_plane_stress(&xy, 0.1, 200e9, 0.3, 7800.0);
        let (k, mm) = (dense(&m.stiffness), dense(&m.mass));
        for a in 0..16 {
            for b in 0..=a {
                assert_eq!(k[a][b], ke[a][b]);
                assert_eq!(mm[a][b], me[a][b]);
            }
        }
        // Mass in x: rho t A = 7800 x 0.1 x 2 kg.
        let total: f64 = (0..16)
            .step_by(2)
            .flat_map(|a| (0..16).step_by(2).map(move |b| (a, b)))
            .map(|(a, b)| mm[a][b])
            .sum();
        assert!((total - 1560.0).abs() < 1e-9, "{total}");
        assert_eq!(
            group_dofs(
                &mesh(&one_quad(NODES, QUAD8)),
                "q.msh",
                &[GroupClamp {
                    group: "clamp".into(),
                    directions: vec![1]
                }]
            )
            .unwrap(),
            [1, 4, 8]
                .map(|node| DofLabel { node, direction: 1 })
                .to_vec()
        );
    }

    /// Corners listed clockwise (a surface whose normal is -z) are the same element.
    #[test]
    fn a_clockwise_element_is_renumbered() {
        let ccw = assembled(&one_quad(NODES, QUAD8)).unwrap();
        let cw = assembled(&one_quad(NODES, "16 1\n2 1 4 3 2 8 7 6 5\n")).unwrap();
        assert_eq!(cw.dofs, ccw.dofs);
        let (a, b) = (dense(&ccw.stiffness), dense(&cw.stiffness));
        let scale = a.iter().flatten().fold(0.0_f64, |s, v| s.max(v.abs()));
        for (ra, rb) in a.iter().zip(&b) {
            for (x, y) in ra.iter().zip(rb) {
                assert!((x - y).abs() <= 1e-14 * scale, "{x} vs {y}");
            }
        }
    }

    /// What the physics refuses of a readable mesh (docs/structures.md's table).
    #[test]
    fn meshes_the_plane_stress_cannot_assemble_are_refused() {
        let cases = [
            (
                assembled(&one_quad(NODES, "3 1\n2 1 2 3 4\n")).unwrap_err(),
                "q.msh, line 38: element 2 is a 4-node quadrangle (Gmsh type 3): only 8-node quadrangles (type 16, the built-in plane stress's Q8) are assembled; mesh with Recombine, Mesh.ElementOrder = 2 and Mesh.SecondOrderIncomplete = 1",
            ),
            (
                assembled(&one_quad(&NODES.replace("2 1 0\n", "2 1 0.5\n"), QUAD8)).unwrap_err(),
                "q.msh, line 26: node 3 has z = 0.5: a plane-stress mesh lies in the plane z = 0",
            ),
            (
                assembled(&one_quad(NODES, "16 1\n2 1 3 2 4 5 6 7 8\n")).unwrap_err(),
                "q.msh, line 38: element 2 is degenerate or folded: its Jacobian determinant at the Gauss points runs from",
            ),
            (
                assembled(&one_quad(NODES, QUAD8).replace("2 2 1 2", "1 1 1 1").replace("2 1 16 1\n2 1 2 3 4 5 6 7 8\n", "")).unwrap_err(),
                "q.msh: no 2D elements: the mesh has nothing to assemble",
            ),
        ];
        for (got, want) in &cases {
            assert!(got.starts_with(want), "{got}\n{want}");
        }
        let unknown = group_dofs(
            &mesh(&one_quad(NODES, QUAD8)),
            "q.msh",
            &[GroupClamp {
                group: "fixed".into(),
                directions: vec![1],
            }],
        )
        .unwrap_err();
        assert_eq!(
            unknown.to_string(),
            "q.msh: structure.clamped_groups: no physical group is named 'fixed' (the mesh names 'clamp')"
        );
    }

    /// The patch test (Zienkiewicz and Taylor, Vol. 1, Sec. 10.3) on general geometry:
    /// 2 x 2 quad8 over the unit square with the centre corner moved to (0.6, 0.35)
    /// (straight sides, mid-side nodes at the edge midpoints, no element a rectangle).
    /// With the boundary nodes moved as a linear field u = (a x + b y, c x + d y), the
    /// interior nodes, solved for from K, follow the same field: a constant strain is
    /// represented exactly, so the assembly puts every entry where the geometry says.
    #[test]
    fn a_distorted_patch_reproduces_a_constant_strain() {
        use stickslip_formats::gmsh::{Element, Node, ELEMENT_TYPES};
        let corner = |i: usize, j: usize| -> (f64, f64) {
            if (i, j) == (1, 1) {
                (0.6, 0.35)
            } else {
                (i as f64 / 2.0, j as f64 / 2.0)
            }
        };
        // Corners tagged 1..=9 (i + 3 j + 1); mid-sides found or added per edge.
        let mut nodes: Vec<(f64, f64)> = (0..9).map(|k| corner(k % 3, k / 3)).collect();
        let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
        let mut mid = |a: usize, b: usize, nodes: &mut Vec<(f64, f64)>| -> usize {
            *edges.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (nodes[a], nodes[b]);
                nodes.push(((p.0 + q.0) / 2.0, (p.1 + q.1) / 2.0));
                nodes.len() - 1
            })
        };
        let quad8 = *ELEMENT_TYPES.iter().find(|t| t.number == 16).unwrap();
        let mut elements = Vec::new();
        for (ei, ej) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let c = [
                ei + 3 * ej,
                ei + 1 + 3 * ej,
                ei + 1 + 3 * (ej + 1),
                ei + 3 * (ej + 1),
            ];
            let m: Vec<usize> = (0..4)
                .map(|k| mid(c[k], c[(k + 1) % 4], &mut nodes))
                .collect();
            elements.push(Element {
                tag: elements.len() as u64 + 1,
                kind: quad8,
                nodes: c.iter().chain(&m).map(|&n| n as u64 + 1).collect(),
                entity: (2, 1),
                line: 1,
            });
        }
        let mesh = Mesh {
            nodes: nodes
                .iter()
                .enumerate()
                .map(|(k, &(x, y))| Node {
                    tag: k as u64 + 1,
                    xyz: [x, y, 0.0],
                    line: 1,
                })
                .collect(),
            elements,
            groups: vec![],
        };
        let m = assemble(&mesh, "patch", &STEEL).unwrap();
        let k = dense(&m.stiffness);
        let field = |(x, y): (f64, f64)| [1e-3 * x + 2e-4 * y, -3e-4 * x + 5e-4 * y];
        let on_boundary = |(x, y): (f64, f64)| x == 0.0 || y == 0.0 || x == 1.0 || y == 1.0;
        let exact: Vec<f64> = m
            .dofs
            .iter()
            .map(|d| field(nodes[d.node as usize - 1])[d.direction as usize - 1])
            .collect();
        let free: Vec<usize> = (0..m.dofs.len())
            .filter(|&r| !on_boundary(nodes[m.dofs[r].node as usize - 1]))
            .collect();
        assert_eq!(free.len(), 10, "the centre and the four interior mid-sides");
        // K_ff u_f = -K_fb u_b, by Gaussian elimination (10 x 10, K_ff positive definite).
        let n = free.len();
        let mut a: Vec<Vec<f64>> = free
            .iter()
            .map(|&i| {
                let mut row: Vec<f64> = free.iter().map(|&j| k[i][j]).collect();
                let rhs: f64 = (0..m.dofs.len())
                    .filter(|j| !free.contains(j))
                    .map(|j| -k[i][j] * exact[j])
                    .sum();
                row.push(rhs);
                row
            })
            .collect();
        for p in 0..n {
            let pivot = a[p].clone();
            for row in a.iter_mut().skip(p + 1) {
                let f = row[p] / pivot[p];
                for (x, y) in row.iter_mut().zip(&pivot).skip(p) {
                    *x -= f * y;
                }
            }
        }
        let mut u = vec![0.0; n];
        for p in (0..n).rev() {
            u[p] = (a[p][n] - (p + 1..n).map(|c| a[p][c] * u[c]).sum::<f64>()) / a[p][p];
        }
        for (q, &r) in free.iter().enumerate() {
            // Displacements of 1e-3: 1e-15 is a few roundings of the solve.
            assert!(
                (u[q] - exact[r]).abs() < 1e-15,
                "{}: {} vs {}",
                m.dofs[r],
                u[q],
                exact[r]
            );
        }
    }

    #[test]
    fn a_binary_or_missing_mesh_file_is_refused_naming_it() {
        let dir = std::env::temp_dir().join(format!("plane-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("b.msh");
        let mut bytes = b"$MeshFormat\n4.1 1 8\n".to_vec();
        bytes.extend_from_slice(&[1, 0, 0, 0, 0xff, 0xfe, b'\n']);
        std::fs::write(&path, bytes).unwrap();
        let binary = read_gmsh(&path).unwrap_err().to_string();
        let missing = read_gmsh(&dir.join("none.msh")).unwrap_err().to_string();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(
            binary,
            format!("{}, line 2: a binary MSH file (file type 1) is not read: write it as ASCII MSH 4.1: gmsh -2 x.geo -format msh41 (and Mesh.Binary = 0, the default)", path.display())
        );
        assert_eq!(
            missing,
            format!(
                "structure file {}: no such file",
                dir.join("none.msh").display()
            )
        );
    }
}
