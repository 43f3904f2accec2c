//! The scene's `[structure]` section: a user's structure from files, in place of the
//! built-in beam (issue 35 item 2, the full model).
//!
//! ```toml
//! [structure]
//! format = "calculix"          # or "matrix-market"
//! job = "beam"                 # calculix: dir/JOB for JOB.sti, JOB.mas, JOB.dof
//! # stiffness = "k.mtx"        # matrix-market: K, M and the DOF map file
//! # mass = "m.mtx"
//! # dofs = "k.dofs"
//! contact = { node = 202, direction = 2 }      # where friction acts and the belt moves
//! clamped = [{ node = 7, direction = 3 }]      # DOFs the files did not remove (optional)
//! sensors = [{ name = "mid_y", node = 252, direction = 2 }]   # named outputs (optional)
//! ```
//!
//! or a 2D Gmsh mesh assembled in plane stress by our own Q8 element (`crate::plane_mesh`):
//!
//! ```toml
//! [structure]
//! format = "gmsh"
//! mesh = "beam.msh"            # MSH 4.1 ASCII, 8-node quadrangles in the plane z = 0
//! material = { thickness = 1.0, youngs_modulus = 200e9, poisson_ratio = 0.3, density = 1000.0 }
//! clamped_groups = [{ group = "clamp", directions = [1, 2] }]   # physical groups fixed
//! contact = { group = "tip", direction = 2 }   # a physical point; direction 1 = x, 2 = y
//! sensors = [{ name = "corner_x", group = "tip", direction = 1 }]   # by group or node
//! ```
//!
//! The contact and the sensors name their node by number (`node`, any format) or, in a
//! Gmsh mesh, by a physical group holding exactly that node (`group`: a physical point,
//! whose name survives a mesh written again with other numbers), [`PointDof`].
//!
//! Paths are relative to the scene file ([`crate::scene::Scene::load`] makes them
//! absolute) or absolute; a scene given as text takes them relative to the working
//! directory. The section is checked twice: its fields by [`StructureSection::check_fields`]
//! inside `Scene::check` (no file is opened there; the rules it sets for the rest of the
//! scene are the scene's), the files and the DOFs by `StructuralModel::from_section`
//! (`crate::linear_structure`) when the model is built. This module is plain data: it
//! imports neither the scene nor the solvers, so that both may import it.
//!
//! The structure is the full model: M and K as given, clamped DOFs removed, the scene's
//! Rayleigh damping C = a M + b K on them as on the beam (the integrator forms it from
//! the model's M and K), plus a damping matrix C0 where a Matrix Market structure gives
//! one (`damping = "c.mtx"`: C = C0 + a M + b K). The tip is the contact DOF: u_tip = u_contact, and the friction
//! force enters as a force on that DOF (N, or N m on a rotation).
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use stickslip_formats::structure_file::{DofLabel, MAX_DIRECTION};

/// How the structure's files are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StructureFormat {
    /// CalculiX's `*MATRIX STORAGE` output: `job`.sti, .mas, .dof.
    Calculix,
    /// Matrix Market `.mtx` files for K and M with a DOF map file.
    MatrixMarket,
    /// A Gmsh `.msh` mesh of 8-node quadrangles, assembled in plane stress.
    Gmsh,
}

impl StructureFormat {
    pub fn word(self) -> &'static str {
        match self {
            StructureFormat::Calculix => "calculix",
            StructureFormat::MatrixMarket => "matrix-market",
            StructureFormat::Gmsh => "gmsh",
        }
    }
}

/// A DOF named in the scene: node number (the file's) and direction (1 to 6: x, y, z,
/// then rotations about them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDof {
    pub node: u64,
    pub direction: u8,
}

impl SceneDof {
    pub fn label(self) -> DofLabel {
        DofLabel {
            node: self.node,
            direction: self.direction,
        }
    }
}

/// Where the contact or a sensor is: one node, named by its number in the files
/// (`node`) or, with `format = "gmsh"`, by a physical group that holds exactly that node
/// (`group`, a Gmsh physical point: its number may change when the mesh is written again,
/// its name does not); exactly one of the two. `direction` as in [`SceneDof`].
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointDof {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
    pub direction: u8,
}

impl PointDof {
    /// The DOF at node `node`.
    pub fn at_node(node: u64, direction: u8) -> Self {
        Self {
            node: Some(node),
            group: None,
            direction,
        }
    }

    /// The DOF at the one node of physical group `group`.
    pub fn in_group(group: &str, direction: u8) -> Self {
        Self {
            node: None,
            group: Some(group.to_string()),
            direction,
        }
    }

    /// Its label, the group's node given by `group_node` (called only for a group: the
    /// mesh resolves it). A DOF with neither node nor group (refused by
    /// [`StructureSection::check_fields`]) reads as node 0, which no file has.
    pub fn label_with<E>(
        &self,
        group_node: impl FnOnce(&str) -> Result<u64, E>,
    ) -> Result<DofLabel, E> {
        let node = match (&self.group, self.node) {
            (Some(group), _) => group_node(group)?,
            (None, node) => node.unwrap_or(0),
        };
        Ok(DofLabel {
            node,
            direction: self.direction,
        })
    }
}

impl std::fmt::Display for PointDof {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (&self.group, self.node) {
            (Some(group), _) => write!(f, "group '{group}' direction {}", self.direction),
            (None, Some(node)) => write!(f, "node {node} direction {}", self.direction),
            (None, None) => write!(f, "(no node or group) direction {}", self.direction),
        }
    }
}

/// A place's DOFs resolved to labels: the contact's and each sensor's, in the section's
/// order (`crate::linear_structure::scene_model::read_section` resolves them, a group
/// by the mesh).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PointLabels {
    pub contact: DofLabel,
    pub sensors: Vec<DofLabel>,
}

/// The `[structure]` section.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructureSection {
    pub format: StructureFormat,
    /// calculix: the job path without extension.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub job: Option<PathBuf>,
    /// matrix-market: K's file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<PathBuf>,
    /// matrix-market: M's file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<PathBuf>,
    /// matrix-market: a damping matrix C0's file (optional), read and checked as K and
    /// M are (same DOF map, symmetric); the integrator's damping is then C0 plus the
    /// scene's Rayleigh damping, C = C0 + a M + b K (`[damping]`; set a = b = 0 for C0
    /// alone), in the phases `contact.damping_phase` says. The full model only: a modal
    /// reduction refuses it (`modal::reduce`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<PathBuf>,
    /// matrix-market: the DOF map file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dofs: Option<PathBuf>,
    /// The DOF where friction acts and the belt moves: a node, or (gmsh) a physical
    /// point group.
    pub contact: PointDof,
    /// DOFs to fix that the files did not remove.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub clamped: Vec<SceneDof>,
    /// gmsh: the mesh file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<PathBuf>,
    /// gmsh: the plane-stress constants of the mesh (a mesh file carries none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<PlaneStressMaterial>,
    /// gmsh: physical groups whose nodes are fixed in the given directions.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub clamped_groups: Vec<GroupClamp>,
    /// Named output DOFs ([`Sensor`]), reported by every fidelity.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<Sensor>,
}

/// A named output DOF: the displacement u (m, or rad on a rotation) and velocity u'
/// (m/s, rad/s) of free DOF (`node`, `direction`), reported as `name` and
/// `name` + [`Sensor::VELOCITY_SUFFIX`] (CSV columns of `stickslip simulate`, outputs of
/// an exported FMU). The full model reads the DOF; a modal model recovers it from its
/// basis, u = sum_j T_j[dof] q_j, as it recovers the contact DOF (the static
/// correction included: under the contact force alone the static shape makes it exact
/// in statics at any DOF).
///
/// The DOF is named as the contact's ([`PointDof`]): `node`, or `group` with
/// `format = "gmsh"`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sensor {
    pub name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
    pub direction: u8,
}

impl Sensor {
    /// What the velocity's name adds to the sensor's name.
    pub const VELOCITY_SUFFIX: &'static str = "_velocity";

    /// The sensor `name` at node `node`.
    pub fn at_node(name: &str, node: u64, direction: u8) -> Self {
        Self {
            name: name.to_string(),
            node: Some(node),
            group: None,
            direction,
        }
    }

    pub fn dof(&self) -> PointDof {
        PointDof {
            node: self.node,
            group: self.group.clone(),
            direction: self.direction,
        }
    }

    /// The name of the sensor's velocity output.
    pub fn velocity_name(&self) -> String {
        format!("{}{}", self.name, Self::VELOCITY_SUFFIX)
    }
}

/// Whether `name` is an identifier: a letter or _, then letters, digits or _ (ASCII).
/// Such a name is a valid FMI variable name under either naming convention (FMI 2.0
/// section 2.2.9 structured: an identifier is a `name` part), a CSV header without
/// quoting, and a C and Python identifier.
pub fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c == '_' || c.is_ascii_alphabetic())
        && chars.all(|c| c == '_' || c.is_ascii_alphanumeric())
}

/// The plane-stress constants of a Gmsh mesh: the out-of-plane thickness t (m), Young's
/// modulus E (Pa), Poisson's ratio nu (1) and the density rho (kg/m3). They belong to the
/// `[structure]` section, not to the scene's `[geometry]`/`[material]` (which describe
/// the built-in beam and are unused with any `[structure]`), so that the section is the
/// whole structure, as a CalculiX deck carries its material.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneStressMaterial {
    pub thickness: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
}

/// A Gmsh physical group (by name) whose nodes are fixed in `directions` (1 = x, 2 = y).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupClamp {
    pub group: String,
    pub directions: Vec<u8>,
}

/// A path field's dotted name and whether the scene gives it.
type GivenField = (&'static str, bool);

/// A field of the section out of its rule: its dotted name, its value as written and
/// what it must be (the scene turns it into its `SceneError::Invalid`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FieldProblem {
    pub field: &'static str,
    pub value: String,
    pub requirement: String,
}

fn refused(field: &'static str, value: impl ToString, requirement: impl ToString) -> FieldProblem {
    FieldProblem {
        field,
        value: value.to_string(),
        requirement: requirement.to_string(),
    }
}

fn check_dof(field: &'static str, dof: SceneDof) -> Result<(), FieldProblem> {
    if dof.node == 0 {
        return Err(refused(
            field,
            dof.label(),
            "a node number >= 1 (the file's numbering)",
        ));
    }
    if !(1..=MAX_DIRECTION).contains(&dof.direction) {
        return Err(refused(
            field,
            dof.label(),
            format!("a direction in 1..={MAX_DIRECTION} (x, y, z, then rotations about them)"),
        ));
    }
    Ok(())
}

/// A contact's or sensor's DOF: exactly one of node and group, a group only in a Gmsh
/// mesh (the other formats have no groups), then the node and direction as [`check_dof`].
fn check_point(
    field: &'static str,
    format: StructureFormat,
    dof: &PointDof,
) -> Result<(), FieldProblem> {
    match (&dof.group, dof.node) {
        (Some(_), Some(_)) | (None, None) => Err(refused(
            field,
            dof,
            "one of node (the file's number) or group (a Gmsh physical point group), not both and not neither",
        )),
        (Some(_), None) if format != StructureFormat::Gmsh => Err(refused(
            field,
            dof,
            format!(
                "a node number with structure.format = {}: only a Gmsh mesh has physical groups",
                format.word()
            ),
        )),
        (Some(group), None) if group.is_empty() => {
            Err(refused(field, dof, "a group name that is not empty"))
        }
        (Some(_), None) => check_dof(
            field,
            SceneDof {
                node: 1,
                direction: dof.direction,
            },
        )
        .map_err(|p| FieldProblem {
            value: dof.to_string(),
            ..p
        }),
        (None, Some(node)) => check_dof(
            field,
            SceneDof {
                node,
                direction: dof.direction,
            },
        ),
    }
}

impl StructureSection {
    /// The fields (no file opened): the format's paths present and the other format's
    /// absent, no damping file, the DOFs well formed, the contact not clamped. What the
    /// rest of the scene must be with a user's structure is the scene's check.
    pub fn check_fields(&self) -> Result<(), FieldProblem> {
        let format = self.format.word();
        let (needed, foreign): (&[GivenField], &[GivenField]) = match self.format {
            StructureFormat::Calculix => (
                &[("structure.job", self.job.is_some())],
                &[
                    ("structure.stiffness", self.stiffness.is_some()),
                    ("structure.mass", self.mass.is_some()),
                    ("structure.dofs", self.dofs.is_some()),
                    ("structure.mesh", self.mesh.is_some()),
                    ("structure.material", self.material.is_some()),
                    ("structure.clamped_groups", !self.clamped_groups.is_empty()),
                ],
            ),
            StructureFormat::MatrixMarket => (
                &[
                    ("structure.stiffness", self.stiffness.is_some()),
                    ("structure.mass", self.mass.is_some()),
                    ("structure.dofs", self.dofs.is_some()),
                ],
                &[
                    ("structure.job", self.job.is_some()),
                    ("structure.mesh", self.mesh.is_some()),
                    ("structure.material", self.material.is_some()),
                    ("structure.clamped_groups", !self.clamped_groups.is_empty()),
                ],
            ),
            StructureFormat::Gmsh => (
                &[
                    ("structure.mesh", self.mesh.is_some()),
                    ("structure.material", self.material.is_some()),
                ],
                &[
                    ("structure.job", self.job.is_some()),
                    ("structure.stiffness", self.stiffness.is_some()),
                    ("structure.mass", self.mass.is_some()),
                    ("structure.dofs", self.dofs.is_some()),
                ],
            ),
        };
        if let Some((field, _)) = needed.iter().find(|(_, given)| !given) {
            return Err(refused(
                field,
                "(absent)",
                format!("given with structure.format = {format}"),
            ));
        }
        if let Some((field, _)) = foreign.iter().find(|(_, given)| *given) {
            return Err(refused(
                field,
                "(given)",
                format!("absent with structure.format = {format}: it belongs to the other format"),
            ));
        }
        if let (Some(path), false) = (&self.damping, self.format == StructureFormat::MatrixMarket) {
            return Err(refused(
                "structure.damping",
                path.display(),
                format!("absent with structure.format = {format}: a damping matrix is read from a Matrix Market file with the DOF map of K and M (ccx 2.20 writes none; a Gmsh mesh carries none); the scene's Rayleigh damping ([damping]: C = a M + b K) acts on the structure"),
            ));
        }
        check_point("structure.contact", self.format, &self.contact)?;
        for &dof in &self.clamped {
            check_dof("structure.clamped", dof)?;
        }
        if let Some(material) = &self.material {
            material.check()?;
        }
        for clamp in &self.clamped_groups {
            if clamp.directions.is_empty() || clamp.directions.iter().any(|d| !(1..=2).contains(d))
            {
                return Err(refused(
                    "structure.clamped_groups",
                    format!("group '{}' directions {:?}", clamp.group, clamp.directions),
                    "one or both of the plane's directions 1 (x) and 2 (y)",
                ));
            }
        }
        if self.is_clamped(&self.contact) {
            return Err(refused(
                "structure.contact",
                &self.contact,
                "a free DOF: structure.clamped fixes it, so friction could not move it",
            ));
        }
        self.check_sensors()
    }

    /// Each sensor's name an identifier, its two output names (`name`, `name_velocity`)
    /// unique among all sensors', its DOF well formed and not in `structure.clamped`
    /// (whether the DOF is in the files is known when they are read).
    fn check_sensors(&self) -> Result<(), FieldProblem> {
        let mut names: Vec<(String, &str)> = Vec::new();
        for sensor in &self.sensors {
            let value = |what: &str| match what {
                "" => format!("'{}'", sensor.name),
                _ => format!("'{}' {what}", sensor.name),
            };
            if !is_identifier(&sensor.name) {
                return Err(refused(
                    "structure.sensors",
                    value(""),
                    "a name of ASCII letters, digits and _ that starts with a letter or _ (it becomes an FMI variable and a CSV column)",
                ));
            }
            for output in [sensor.name.clone(), sensor.velocity_name()] {
                if let Some((_, other)) = names.iter().find(|(n, _)| *n == output) {
                    return Err(refused(
                        "structure.sensors",
                        value(""),
                        format!("a name whose outputs {} and {} no other sensor has: '{other}' has {output}", sensor.name, sensor.velocity_name()),
                    ));
                }
                names.push((output, &sensor.name));
            }
            check_point("structure.sensors", self.format, &sensor.dof()).map_err(|p| {
                FieldProblem {
                    value: value(&format!("at {}", p.value)),
                    ..p
                }
            })?;
            if self.is_clamped(&sensor.dof()) {
                return Err(refused(
                    "structure.sensors",
                    value(&format!("at {}", sensor.dof())),
                    "a free DOF: structure.clamped fixes it, so it would read 0",
                ));
            }
        }
        Ok(())
    }

    /// Whether `dof`, named by its node, is one of `clamped`'s (a group's node is known
    /// when the mesh is read: the model's free-DOF check refuses it then).
    fn is_clamped(&self, dof: &PointDof) -> bool {
        dof.group.is_none()
            && dof.node.is_some_and(|node| {
                self.clamped.contains(&SceneDof {
                    node,
                    direction: dof.direction,
                })
            })
    }

    /// The contact's and the sensors' labels, a group's node given by `group_node`
    /// (field, group name) (only a Gmsh mesh has groups; the fields are checked).
    pub fn point_labels<E>(
        &self,
        mut group_node: impl FnMut(&'static str, &str) -> Result<u64, E>,
    ) -> Result<PointLabels, E> {
        let contact = self
            .contact
            .label_with(|group| group_node("structure.contact", group))?;
        let sensors = self
            .sensors
            .iter()
            .map(|s| {
                s.dof()
                    .label_with(|group| group_node("structure.sensors", group))
            })
            .collect::<Result<_, E>>()?;
        Ok(PointLabels { contact, sensors })
    }

    /// Makes relative paths relative to `dir` (the scene file's directory).
    pub fn resolve_paths(&mut self, dir: &Path) {
        for path in [
            &mut self.job,
            &mut self.stiffness,
            &mut self.mass,
            &mut self.damping,
            &mut self.dofs,
            &mut self.mesh,
        ]
        .into_iter()
        .flatten()
        {
            if path.is_relative() {
                *path = dir.join(&*path);
            }
        }
    }

    /// The files' name for labels: "calculix beam" for job `dir/beam`.
    pub fn source(&self) -> String {
        let stem = |p: &Option<PathBuf>| {
            p.as_deref()
                .and_then(Path::file_stem)
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        };
        match self.format {
            StructureFormat::Calculix => format!("calculix {}", stem(&self.job)),
            StructureFormat::MatrixMarket => format!("matrix-market {}", stem(&self.stiffness)),
            StructureFormat::Gmsh => format!("gmsh {}", stem(&self.mesh)),
        }
    }
}

impl PlaneStressMaterial {
    /// Finite and positive constants, nu in (-1, 1/2) (where the plane-stress D is
    /// positive definite and a solid is stable).
    fn check(&self) -> Result<(), FieldProblem> {
        for (field, value, unit) in [
            ("structure.material.thickness", self.thickness, "m"),
            (
                "structure.material.youngs_modulus",
                self.youngs_modulus,
                "Pa",
            ),
            ("structure.material.density", self.density, "kg/m3"),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(refused(field, value, format!("finite and > 0 ({unit})")));
            }
        }
        let nu = self.poisson_ratio;
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(refused(
                "structure.material.poisson_ratio",
                nu,
                "in (-1, 0.5), where an isotropic solid is stable",
            ));
        }
        Ok(())
    }
}
