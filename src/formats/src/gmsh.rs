//! Gmsh's mesh format, MSH 4.1 ASCII (what `gmsh -2 x.geo -format msh41` and gmsh 4.x
//! write by default), and the older MSH 2.2 ASCII (`-format msh22`, which many tools
//! still write): nodes, elements and physical groups, read into a [`Mesh`].
//!
//! The sections read (Gmsh reference manual, "MSH file format", version 4.1):
//! - `$MeshFormat`: `4.1 0 8` (version, file type 0 = ASCII, size of a double);
//! - `$PhysicalNames`: a count, then `dim tag "name"` per group;
//! - `$Entities`: the counts of points, curves, surfaces, volumes, then one line per
//!   entity with its physical tags (a point `tag x y z nPhys phys...`; a curve, surface
//!   or volume `tag minX minY minZ maxX maxY maxZ nPhys phys... nBound bound...`);
//! - `$Nodes`: `numBlocks numNodes minTag maxTag`, then per block `entityDim entityTag
//!   parametric numNodesInBlock`, that many node tags (one a line), then as many
//!   coordinate lines `x y z` (followed by the parametric coordinates when
//!   `parametric` = 1);
//! - `$Elements`: `numBlocks numElements minTag maxTag`, then per block `entityDim
//!   entityTag elementType numElementsInBlock` and one line `tag node...` per element.
//!
//! MSH 2.2 has no `$Entities`: `$Nodes` is a count and `tag x y z` lines, `$Elements` a
//! count and `tag type ntags tag... node...` lines whose first two tags are the physical
//! group and the elementary entity; the groups are built from those.
//!
//! Other sections (`$NodeData`, `$Periodic`, ...) are skipped to their `$End` line.
//! A physical group's nodes are those of its elements (a curve's line elements hold its
//! end points, which the `$Nodes` block of the curve does not), as Gmsh itself takes
//! them: [`Mesh::group_nodes`].
//!
//! Plain data: which element types a model can assemble, whether the mesh is planar or
//! its elements well shaped is the physics' to decide (`stickslip::plane_mesh`). What
//! the reader refuses makes the file unreadable: a binary file (with the option that
//! writes ASCII), another version, a bad number, a count that does not match, an element
//! type it does not know, an element naming a node the file does not define, a tag twice,
//! a section that does not end. Allocation is proportional to the input.

use crate::structure_file::{value, FileText, Problem, ReadError};
use std::collections::{BTreeSet, HashMap};

/// What to do with a binary or other-version file.
const WRITE_ASCII_41: &str =
    "write it as ASCII MSH 4.1: gmsh -2 x.geo -format msh41 (and Mesh.Binary = 0, the default)";

/// An element type this reader knows: Gmsh's number, its dimension and node count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ElementType {
    /// Gmsh's element type number (15 point, 1 line, 8 line3, 2 triangle, 9 triangle6,
    /// 3 quadrangle, 16 quadrangle8, 10 quadrangle9).
    pub number: u32,
    /// 0 point, 1 line, 2 surface element.
    pub dim: u8,
    pub nodes: usize,
    pub name: &'static str,
}

/// The types read: points, lines and the 2D types of a plane mesh, first and second
/// order (Gmsh's numbering).
pub const ELEMENT_TYPES: [ElementType; 8] = [
    ElementType {
        number: 15,
        dim: 0,
        nodes: 1,
        name: "point",
    },
    ElementType {
        number: 1,
        dim: 1,
        nodes: 2,
        name: "2-node line",
    },
    ElementType {
        number: 8,
        dim: 1,
        nodes: 3,
        name: "3-node line",
    },
    ElementType {
        number: 2,
        dim: 2,
        nodes: 3,
        name: "3-node triangle",
    },
    ElementType {
        number: 9,
        dim: 2,
        nodes: 6,
        name: "6-node triangle",
    },
    ElementType {
        number: 3,
        dim: 2,
        nodes: 4,
        name: "4-node quadrangle",
    },
    ElementType {
        number: 16,
        dim: 2,
        nodes: 8,
        name: "8-node quadrangle",
    },
    ElementType {
        number: 10,
        dim: 2,
        nodes: 9,
        name: "9-node quadrangle",
    },
];

/// Names of types the reader refuses, for the message.
fn unsupported_name(number: u32) -> &'static str {
    match number {
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        11 => "10-node tetrahedron",
        12 => "27-node hexahedron",
        17 => "20-node hexahedron",
        _ => "a type not read here",
    }
}

/// A node: Gmsh's tag and coordinates (m, as the file gives them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    pub tag: u64,
    pub xyz: [f64; 3],
    /// The line of its coordinates.
    pub line: usize,
}

/// An element: Gmsh's tag, type, node tags in Gmsh's order (corners counter-clockwise
/// about the entity's normal, then mid-sides, then the centre) and the entity it lies on.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    pub tag: u64,
    pub kind: ElementType,
    pub nodes: Vec<u64>,
    /// The geometric entity (dimension, tag) of its block.
    pub entity: (u8, i32),
    pub line: usize,
}

/// A physical group: dimension, tag, name (if `$PhysicalNames` gives one) and the
/// entities of that dimension `$Entities` assigns to it.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicalGroup {
    pub dim: u8,
    pub tag: i32,
    pub name: Option<String>,
    pub entities: Vec<i32>,
}

/// A mesh as the file gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub nodes: Vec<Node>,
    pub elements: Vec<Element>,
    pub groups: Vec<PhysicalGroup>,
}

/// Why a group name cannot be resolved.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GroupError {
    #[error("no physical group is named '{name}' (the mesh names {known})")]
    Unknown { name: String, known: String },
    #[error("the physical group '{name}' has no elements in the file (Gmsh saves a group's elements; was the mesh saved with it?)")]
    Empty { name: String },
}

impl Mesh {
    /// The group called `name`.
    pub fn group(&self, name: &str) -> Result<&PhysicalGroup, GroupError> {
        self.groups
            .iter()
            .find(|g| g.name.as_deref() == Some(name))
            .ok_or_else(|| {
                let names: Vec<String> = self
                    .groups
                    .iter()
                    .filter_map(|g| g.name.as_ref().map(|n| format!("'{n}'")))
                    .collect();
                GroupError::Unknown {
                    name: name.to_string(),
                    known: if names.is_empty() {
                        "none".to_string()
                    } else {
                        names.join(", ")
                    },
                }
            })
    }

    /// The node tags of the elements on the entities of group `name`, in increasing
    /// order, each once.
    pub fn group_nodes(&self, name: &str) -> Result<Vec<u64>, GroupError> {
        let group = self.group(name)?;
        let nodes: BTreeSet<u64> = self
            .elements
            .iter()
            .filter(|e| e.entity.0 == group.dim && group.entities.contains(&e.entity.1))
            .flat_map(|e| e.nodes.iter().copied())
            .collect();
        if nodes.is_empty() {
            return Err(GroupError::Empty {
                name: name.to_string(),
            });
        }
        Ok(nodes.into_iter().collect())
    }
}

/// Refuses a binary file from its first bytes, before its text is decoded: Gmsh's binary
/// files start with an ASCII `$MeshFormat` whose file type is 1, then bytes that are not
/// text. Text that does not look like a Gmsh header passes, for [`read_mesh`] to name.
pub fn refuse_binary(name: &str, bytes: &[u8]) -> Result<(), ReadError> {
    let head = &bytes[..bytes.len().min(64)];
    let head = String::from_utf8_lossy(head);
    let mut lines = head.lines();
    if lines.next().map(str::trim) == Some("$MeshFormat") {
        if let Some(format) = lines.next() {
            let fields: Vec<&str> = format.split_whitespace().collect();
            if fields.get(1) == Some(&"1") {
                return Err(ReadError {
                    file: name.to_string(),
                    line: Some(2),
                    problem: Problem::Header(format!(
                        "a binary MSH file (file type 1) is not read: {WRITE_ASCII_41}"
                    )),
                });
            }
        }
    }
    Ok(())
}

/// The lines of a file with their 1-based numbers, trimmed; blank lines skipped.
struct Lines<'a> {
    source: FileText<'a>,
    lines: Box<dyn Iterator<Item = (usize, &'a str)> + 'a>,
}

impl<'a> Lines<'a> {
    fn new(source: FileText<'a>) -> Self {
        let lines = source
            .text
            .lines()
            .enumerate()
            .map(|(k, l)| (k + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty());
        Self {
            source,
            lines: Box::new(lines),
        }
    }

    fn fail(&self, line: Option<usize>, text: String) -> ReadError {
        self.source.error(line, Problem::Header(text))
    }

    /// The next line inside section `section`; the end of the file is an error naming it.
    fn next_in(&mut self, section: &str) -> Result<(usize, &'a str), ReadError> {
        match self.lines.next() {
            Some(line) => Ok(line),
            None => Err(self.fail(
                None,
                format!("the file ends inside ${section} (no $End{section})"),
            )),
        }
    }

    /// The next line inside `section`, split into exactly `count` fields (or at least
    /// `count` when `at_least`).
    fn fields_in(
        &mut self,
        section: &str,
        count: usize,
        at_least: bool,
        form: &'static str,
    ) -> Result<(usize, Vec<&'a str>), ReadError> {
        let (n, l) = self.next_in(section)?;
        let fields: Vec<&str> = l.split_whitespace().collect();
        if fields.len() != count && !(at_least && fields.len() > count) {
            return Err(self.source.error(
                Some(n),
                Problem::FieldCount {
                    found: fields.len(),
                    expected: count,
                    form,
                },
            ));
        }
        Ok((n, fields))
    }

    /// The `$End<section>` line.
    fn end(&mut self, section: &str) -> Result<(), ReadError> {
        let (n, l) = self.next_in(section)?;
        if l != format!("$End{section}") {
            return Err(self.fail(
                Some(n),
                format!("'{l}' where ${section} should end ($End{section}): the section holds more lines than its counts declare"),
            ));
        }
        Ok(())
    }
}

/// An integer field `what` of the form `form`.
fn integer<T: std::str::FromStr>(text: &str, what: &'static str) -> Result<T, Problem> {
    text.parse().map_err(|_| Problem::NotANumber {
        text: text.to_string(),
        what,
    })
}

fn dim(text: &str) -> Result<u8, Problem> {
    match text.parse::<u8>() {
        Ok(d) if d <= 3 => Ok(d),
        _ => Err(Problem::NotANumber {
            text: text.to_string(),
            what: "dimension (0 to 3)",
        }),
    }
}

/// Reads an ASCII MSH 4.1 file's text (`source.name` appears in errors).
pub fn read_mesh(source: FileText) -> Result<Mesh, ReadError> {
    let mut lines = Lines::new(source);
    let at = |n: usize| move |p: Problem| source.error(Some(n), p);
    match lines.lines.next() {
        None => return Err(source.error(None, Problem::Empty("no $MeshFormat"))),
        Some((n, l)) if l != "$MeshFormat" => {
            return Err(lines.fail(
                Some(n),
                format!(
                    "'{}' is not a Gmsh MSH header: a mesh file starts with $MeshFormat",
                    clip(l)
                ),
            ))
        }
        Some(_) => {}
    }
    let (n, format) = lines.fields_in("MeshFormat", 3, false, "version file-type data-size")?;
    if format[1] == "1" {
        return Err(lines.fail(
            Some(n),
            format!("a binary MSH file (file type 1) is not read: {WRITE_ASCII_41}"),
        ));
    }
    let legacy = match format[0] {
        "4.1" => false,
        "2.2" => true,
        other => {
            return Err(lines.fail(
                Some(n),
                format!("MSH version {other} is not read (only 4.1 and 2.2): {WRITE_ASCII_41}"),
            ))
        }
    };
    if format[1] != "0" {
        return Err(lines.fail(
            Some(n),
            format!("file type {} is not 0 (ASCII): {WRITE_ASCII_41}", format[1]),
        ));
    }
    lines.end("MeshFormat")?;

    let mut names: HashMap<(u8, i32), String> = HashMap::new();
    let mut entity_groups: Vec<(u8, i32, Vec<i32>)> = Vec::new();
    let mut nodes: Option<Vec<Node>> = None;
    let mut elements: Option<Vec<Element>> = None;
    while let Some((n, l)) = lines.lines.next() {
        let Some(section) = l.strip_prefix('$') else {
            return Err(lines.fail(
                Some(n),
                format!(
                    "'{}' outside a section: a section starts with $Name",
                    clip(l)
                ),
            ));
        };
        match section {
            "PhysicalNames" => read_physical_names(&mut lines, &mut names)?,
            "Entities" => entity_groups = read_entities(&mut lines)?,
            "Nodes" => {
                if nodes.is_some() {
                    return Err(lines.fail(Some(n), "a second $Nodes section".into()));
                }
                nodes = Some(if legacy {
                    read_nodes_22(&mut lines)?
                } else {
                    read_nodes(&mut lines)?
                });
            }
            "Elements" => {
                if elements.is_some() {
                    return Err(lines.fail(Some(n), "a second $Elements section".into()));
                }
                elements = Some(if legacy {
                    let (read, groups) = read_elements_22(&mut lines)?;
                    entity_groups.extend(groups);
                    read
                } else {
                    read_elements(&mut lines)?
                });
            }
            other => {
                // A section this reader does not need: skipped to its end.
                let end = format!("$End{other}");
                loop {
                    let (_, l) = lines.next_in(other)?;
                    if l == end {
                        break;
                    }
                }
            }
        }
    }
    let nodes = nodes.ok_or_else(|| source.error(None, Problem::Empty("no $Nodes section")))?;
    let elements =
        elements.ok_or_else(|| source.error(None, Problem::Empty("no $Elements section")))?;
    let defined: HashMap<u64, ()> = nodes.iter().map(|nd| (nd.tag, ())).collect();
    for e in &elements {
        if let Some(missing) = e.nodes.iter().find(|t| !defined.contains_key(t)) {
            return Err(at(e.line)(Problem::Header(format!(
                "element {} names node {missing}, which $Nodes does not define",
                e.tag
            ))));
        }
    }
    let mut groups: Vec<PhysicalGroup> = Vec::new();
    for (d, entity, physicals) in entity_groups {
        for tag in physicals {
            match groups.iter_mut().find(|g| g.dim == d && g.tag == tag) {
                Some(g) => {
                    if !g.entities.contains(&entity) {
                        g.entities.push(entity)
                    }
                }
                None => groups.push(PhysicalGroup {
                    dim: d,
                    tag,
                    name: names.get(&(d, tag)).cloned(),
                    entities: vec![entity],
                }),
            }
        }
    }
    Ok(Mesh {
        nodes,
        elements,
        groups,
    })
}

/// A line shortened for a message.
fn clip(l: &str) -> String {
    if l.chars().count() > 40 {
        format!("{}...", l.chars().take(40).collect::<String>())
    } else {
        l.to_string()
    }
}

fn read_physical_names(
    lines: &mut Lines,
    names: &mut HashMap<(u8, i32), String>,
) -> Result<(), ReadError> {
    const SECTION: &str = "PhysicalNames";
    let (n, count) = lines.fields_in(SECTION, 1, false, "number of names")?;
    let count: usize = integer(count[0], "count (a non-negative integer)")
        .map_err(|p| lines.source.error(Some(n), p))?;
    for _ in 0..count {
        let (n, l) = lines.next_in(SECTION)?;
        let parsed = (|| {
            let mut parts = l.splitn(3, char::is_whitespace);
            let (d, tag, rest) = (
                parts.next().unwrap_or(""),
                parts.next().unwrap_or(""),
                parts.next().unwrap_or("").trim(),
            );
            let d = dim(d)?;
            let tag: i32 = integer(tag, "physical tag (an integer)")?;
            let name = rest
                .strip_prefix('"')
                .and_then(|r| r.strip_suffix('"'))
                .ok_or_else(|| Problem::NotANumber {
                    text: rest.to_string(),
                    what: "quoted name (\"name\")",
                })?;
            Ok((d, tag, name.to_string()))
        })();
        let (d, tag, name) = parsed.map_err(|p| lines.source.error(Some(n), p))?;
        names.insert((d, tag), name);
    }
    lines.end(SECTION)
}

/// (dim, entity tag, physical tags) of every entity.
fn read_entities(lines: &mut Lines) -> Result<Vec<(u8, i32, Vec<i32>)>, ReadError> {
    const SECTION: &str = "Entities";
    let (n, counts) = lines.fields_in(
        SECTION,
        4,
        false,
        "numPoints numCurves numSurfaces numVolumes",
    )?;
    let counts: Vec<usize> = counts
        .iter()
        .map(|c| integer(c, "count (a non-negative integer)"))
        .collect::<Result<_, _>>()
        .map_err(|p| lines.source.error(Some(n), p))?;
    let mut entities = Vec::new();
    for (d, &count) in counts.iter().enumerate() {
        for _ in 0..count {
            // A point: tag x y z nPhys phys...; higher: tag box(6) nPhys phys... nBound ...
            let first = if d == 0 { 4 } else { 7 };
            let (n, fields) = lines.fields_in(
                SECTION,
                first + 1,
                true,
                "entity: tag, coordinates or box, physical tags",
            )?;
            let parsed = (|| {
                let tag: i32 = integer(fields[0], "entity tag (an integer)")?;
                for f in &fields[1..first] {
                    value(f)?;
                }
                let n_phys: usize = integer(fields[first], "count (a non-negative integer)")?;
                // Saturating: a count near usize::MAX is refused by the field count.
                let end = (first + 1).saturating_add(n_phys);
                let phys = fields.get(first + 1..end).ok_or(Problem::FieldCount {
                    found: fields.len(),
                    expected: end,
                    form: "entity: its physical tags as many as it declares",
                })?;
                let phys: Vec<i32> = phys
                    .iter()
                    .map(|p| integer(p, "physical tag (an integer)"))
                    .collect::<Result<_, _>>()?;
                Ok((d as u8, tag, phys))
            })();
            entities.push(parsed.map_err(|p| lines.source.error(Some(n), p))?);
        }
    }
    lines.end(SECTION)?;
    Ok(entities)
}

fn read_nodes(lines: &mut Lines) -> Result<Vec<Node>, ReadError> {
    const SECTION: &str = "Nodes";
    let (n, head) = lines.fields_in(
        SECTION,
        4,
        false,
        "numEntityBlocks numNodes minNodeTag maxNodeTag",
    )?;
    let source = lines.source;
    let at = |n: usize| move |p: Problem| source.error(Some(n), p);
    let blocks: usize = integer(head[0], "count (a non-negative integer)").map_err(at(n))?;
    let declared: usize = integer(head[1], "count (a non-negative integer)").map_err(at(n))?;
    let mut nodes: Vec<Node> = Vec::new();
    let mut seen: HashMap<u64, usize> = HashMap::new();
    for _ in 0..blocks {
        let (n, block) = lines.fields_in(
            SECTION,
            4,
            false,
            "entityDim entityTag parametric numNodesInBlock",
        )?;
        let entity_dim = dim(block[0]).map_err(at(n))?;
        integer::<i32>(block[1], "entity tag (an integer)").map_err(at(n))?;
        let parametric = match block[2] {
            "0" => false,
            "1" => true,
            other => {
                return Err(at(n)(Problem::NotANumber {
                    text: other.to_string(),
                    what: "parametric flag (0 or 1)",
                }))
            }
        };
        let count: usize = integer(block[3], "count (a non-negative integer)").map_err(at(n))?;
        let mut tags = Vec::new();
        for _ in 0..count {
            let (n, tag) = lines.fields_in(SECTION, 1, false, "node tag")?;
            let tag: u64 = match tag[0].parse::<u64>() {
                Ok(t) if t >= 1 => t,
                _ => {
                    return Err(at(n)(Problem::NotANumber {
                        text: tag[0].to_string(),
                        what: "node tag (a positive integer)",
                    }))
                }
            };
            if let Some(first) = seen.insert(tag, n) {
                return Err(at(n)(Problem::Header(format!(
                    "node {tag} appears a second time (first on line {first})"
                ))));
            }
            tags.push(tag);
        }
        let width = 3 + if parametric { entity_dim as usize } else { 0 };
        for tag in tags {
            let (n, xyz) = lines.fields_in(
                SECTION,
                width,
                false,
                "node coordinates x y z (then u v if parametric)",
            )?;
            let mut c = [0.0; 3];
            for (k, f) in xyz.iter().take(3).enumerate() {
                c[k] = value(f).map_err(at(n))?;
            }
            nodes.push(Node {
                tag,
                xyz: c,
                line: n,
            });
        }
    }
    if nodes.len() != declared {
        return Err(at(n)(Problem::Header(format!(
            "the header declares {declared} nodes but the blocks hold {}",
            nodes.len()
        ))));
    }
    lines.end(SECTION)?;
    Ok(nodes)
}

fn read_elements(lines: &mut Lines) -> Result<Vec<Element>, ReadError> {
    const SECTION: &str = "Elements";
    let (n, head) = lines.fields_in(
        SECTION,
        4,
        false,
        "numEntityBlocks numElements minElementTag maxElementTag",
    )?;
    let source = lines.source;
    let at = |n: usize| move |p: Problem| source.error(Some(n), p);
    let blocks: usize = integer(head[0], "count (a non-negative integer)").map_err(at(n))?;
    let declared: usize = integer(head[1], "count (a non-negative integer)").map_err(at(n))?;
    let mut elements: Vec<Element> = Vec::new();
    let mut seen: HashMap<u64, usize> = HashMap::new();
    for _ in 0..blocks {
        let (n, block) = lines.fields_in(
            SECTION,
            4,
            false,
            "entityDim entityTag elementType numElementsInBlock",
        )?;
        let entity_dim = dim(block[0]).map_err(at(n))?;
        let entity: i32 = integer(block[1], "entity tag (an integer)").map_err(at(n))?;
        let number: u32 = integer(block[2], "element type (a positive integer)").map_err(at(n))?;
        let kind = element_type(number).map_err(at(n))?;
        if kind.dim != entity_dim {
            return Err(at(n)(Problem::Header(format!(
                "a block of {}s (type {number}, dimension {}) on an entity of dimension {entity_dim}",
                kind.name, kind.dim
            ))));
        }
        let count: usize = integer(block[3], "count (a non-negative integer)").map_err(at(n))?;
        for _ in 0..count {
            let (n, fields) = lines.next_in(SECTION)?;
            let fields: Vec<&str> = fields.split_whitespace().collect();
            if fields.len() != 1 + kind.nodes {
                return Err(at(n)(Problem::FieldCount {
                    found: fields.len(),
                    expected: 1 + kind.nodes,
                    form: "element tag, then its nodes",
                }));
            }
            let tags: Vec<u64> = fields
                .iter()
                .map(|f| match f.parse::<u64>() {
                    Ok(t) if t >= 1 => Ok(t),
                    _ => Err(Problem::NotANumber {
                        text: f.to_string(),
                        what: "tag (a positive integer)",
                    }),
                })
                .collect::<Result<_, _>>()
                .map_err(at(n))?;
            if let Some(first) = seen.insert(tags[0], n) {
                return Err(at(n)(Problem::Header(format!(
                    "element {} appears a second time (first on line {first})",
                    tags[0]
                ))));
            }
            elements.push(Element {
                tag: tags[0],
                kind,
                nodes: tags[1..].to_vec(),
                entity: (entity_dim, entity),
                line: n,
            });
        }
    }
    if elements.len() != declared {
        return Err(at(n)(Problem::Header(format!(
            "the header declares {declared} elements but the blocks hold {}",
            elements.len()
        ))));
    }
    lines.end(SECTION)?;
    Ok(elements)
}

/// The element type numbered `number`, or why it is not read.
fn element_type(number: u32) -> Result<ElementType, Problem> {
    ELEMENT_TYPES.iter().find(|t| t.number == number).copied().ok_or_else(|| {
        Problem::Header(format!(
            "element type {number} ({}) is not read: a plane mesh has points (15), lines (1, 8), triangles (2, 9) and quadrangles (3, 16, 10)",
            unsupported_name(number)
        ))
    })
}

/// MSH 2.2's `$Nodes`: a count, then `tag x y z` per node.
fn read_nodes_22(lines: &mut Lines) -> Result<Vec<Node>, ReadError> {
    const SECTION: &str = "Nodes";
    let source = lines.source;
    let at = |n: usize| move |p: Problem| source.error(Some(n), p);
    let (n, head) = lines.fields_in(SECTION, 1, false, "number of nodes")?;
    let declared: usize = integer(head[0], "count (a non-negative integer)").map_err(at(n))?;
    let mut nodes = Vec::new();
    let mut seen: HashMap<u64, usize> = HashMap::new();
    for _ in 0..declared {
        let (n, f) = lines.fields_in(SECTION, 4, false, "node tag x y z")?;
        let tag = positive_tag(f[0], "node tag (a positive integer)").map_err(at(n))?;
        if let Some(first) = seen.insert(tag, n) {
            return Err(at(n)(Problem::Header(format!(
                "node {tag} appears a second time (first on line {first})"
            ))));
        }
        let mut xyz = [0.0; 3];
        for (k, text) in f[1..].iter().enumerate() {
            xyz[k] = value(text).map_err(at(n))?;
        }
        nodes.push(Node { tag, xyz, line: n });
    }
    lines.end(SECTION)?;
    Ok(nodes)
}

/// MSH 2.2's `$Elements`: a count, then `tag type ntags tag... node...` per element,
/// whose first two tags are the physical group and the elementary entity (Gmsh's
/// convention); the elements, and (dim, entity, [physical]) for the groups.
#[allow(clippy::type_complexity)]
fn read_elements_22(
    lines: &mut Lines,
) -> Result<(Vec<Element>, Vec<(u8, i32, Vec<i32>)>), ReadError> {
    const SECTION: &str = "Elements";
    let source = lines.source;
    let at = |n: usize| move |p: Problem| source.error(Some(n), p);
    let (n, head) = lines.fields_in(SECTION, 1, false, "number of elements")?;
    let declared: usize = integer(head[0], "count (a non-negative integer)").map_err(at(n))?;
    let mut elements = Vec::new();
    let mut groups = Vec::new();
    let mut seen: HashMap<u64, usize> = HashMap::new();
    for _ in 0..declared {
        let (n, f) =
            lines.fields_in(SECTION, 3, true, "element: tag type ntags tags... nodes...")?;
        let parsed = (|| {
            let tag = positive_tag(f[0], "element tag (a positive integer)")?;
            let kind = element_type(integer(f[1], "element type (a positive integer)")?)?;
            let ntags: usize = integer(f[2], "count (a non-negative integer)")?;
            // Saturating: a tag count near usize::MAX is refused by the field count.
            let expected = (3 + kind.nodes).saturating_add(ntags);
            if f.len() != expected {
                return Err(Problem::FieldCount {
                    found: f.len(),
                    expected,
                    form: "element: tag type ntags, its tags, then its nodes",
                });
            }
            let tags: Vec<i32> = f[3..3 + ntags]
                .iter()
                .map(|t| integer(t, "element tag (an integer)"))
                .collect::<Result<_, _>>()?;
            let nodes: Vec<u64> = f[3 + ntags..]
                .iter()
                .map(|t| positive_tag(t, "node tag (a positive integer)"))
                .collect::<Result<_, _>>()?;
            Ok((tag, kind, tags, nodes))
        })();
        let (tag, kind, tags, nodes) = parsed.map_err(at(n))?;
        if let Some(first) = seen.insert(tag, n) {
            return Err(at(n)(Problem::Header(format!(
                "element {tag} appears a second time (first on line {first})"
            ))));
        }
        let physical = tags.first().copied().filter(|&p| p != 0);
        let entity = tags.get(1).copied().unwrap_or(0);
        if let Some(p) = physical {
            groups.push((kind.dim, entity, vec![p]));
        }
        elements.push(Element {
            tag,
            kind,
            nodes,
            entity: (kind.dim, entity),
            line: n,
        });
    }
    lines.end(SECTION)?;
    Ok((elements, groups))
}

fn positive_tag(text: &str, what: &'static str) -> Result<u64, Problem> {
    match text.parse::<u64>() {
        Ok(t) if t >= 1 => Ok(t),
        _ => Err(Problem::NotANumber {
            text: text.to_string(),
            what,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two 8-node quadrangles side by side (2 x 1 m each), the face x = 0 as group
    /// "clamp", the corner (4, 1) as group "tip".
    const GOOD: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
0 2 \"tip\"
1 1 \"clamp\"
$EndPhysicalNames
$Entities
1 1 1 0
3 4 1 0 1 2
4 0 0 0 0 1 0 1 1 0
1 0 0 0 4 1 0 0 0
$EndEntities
$Nodes
1 13 1 13
2 1 0 13
1
2
3
4
5
6
7
8
9
10
11
12
13
0 0 0
2 0 0
4 0 0
4 1 0
2 1 0
0 1 0
1 0 0
3 0 0
4 0.5 0
3 1 0
1 1 0
0 0.5 0
2 0.5 0
$EndNodes
$Elements
3 4 1 4
0 3 15 1
1 4
1 4 8 1
2 6 1 12
2 1 16 2
3 1 2 5 6 7 13 11 12
4 2 3 4 5 8 9 10 13
$EndElements
";

    fn read(text: &str) -> Result<Mesh, ReadError> {
        read_mesh(FileText {
            name: "b.msh",
            text,
        })
    }

    #[test]
    fn reads_nodes_elements_and_groups() {
        let mesh = read(GOOD).unwrap();
        assert_eq!(mesh.nodes.len(), 13);
        assert_eq!(mesh.nodes[8].tag, 9);
        assert_eq!(mesh.nodes[8].xyz, [4.0, 0.5, 0.0]);
        assert_eq!(mesh.elements.len(), 4);
        let quad = &mesh.elements[3];
        assert_eq!((quad.tag, quad.kind.number, quad.entity), (4, 16, (2, 1)));
        assert_eq!(quad.nodes, vec![2, 3, 4, 5, 8, 9, 10, 13]);
        // A curve's group holds its end points, which its $Nodes block does not.
        assert_eq!(mesh.group_nodes("clamp").unwrap(), vec![1, 6, 12]);
        assert_eq!(mesh.group_nodes("tip").unwrap(), vec![4]);
        assert_eq!(
            mesh.group_nodes("beam").unwrap_err().to_string(),
            "no physical group is named 'beam' (the mesh names 'tip', 'clamp')"
        );
        // Unknown sections are skipped, blank lines too.
        let extra = GOOD.replace(
            "$Nodes\n",
            "$Comments\nanything $Nodes\n$EndComments\n\n$Nodes\n",
        );
        let again = read(&extra).unwrap();
        assert_eq!(again.groups, mesh.groups);
        let tags = |m: &Mesh| {
            m.elements
                .iter()
                .map(|e| e.nodes.clone())
                .collect::<Vec<_>>()
        };
        assert_eq!(tags(&again), tags(&mesh));
        assert_eq!(again.nodes[12].xyz, mesh.nodes[12].xyz);
        assert_eq!(again.nodes[12].line, mesh.nodes[12].line + 4);
    }

    /// The same mesh in MSH 2.2.
    const GOOD_22: &str = "$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
0 2 \"tip\"
1 1 \"clamp\"
$EndPhysicalNames
$Nodes
13
1 0 0 0
2 2 0 0
3 4 0 0
4 4 1 0
5 2 1 0
6 0 1 0
7 1 0 0
8 3 0 0
9 4 0.5 0
10 3 1 0
11 1 1 0
12 0 0.5 0
13 2 0.5 0
$EndNodes
$Elements
4
1 15 2 2 3 4
2 8 2 1 4 6 1 12
3 16 2 0 1 1 2 5 6 7 13 11 12
4 16 2 0 1 2 3 4 5 8 9 10 13
$EndElements
";

    #[test]
    fn msh_22_reads_to_the_same_mesh() {
        let (old, new) = (read(GOOD_22).unwrap(), read(GOOD).unwrap());
        let xyz = |m: &Mesh| m.nodes.iter().map(|n| (n.tag, n.xyz)).collect::<Vec<_>>();
        assert_eq!(xyz(&old), xyz(&new));
        let conn = |m: &Mesh| {
            m.elements
                .iter()
                .map(|e| (e.tag, e.kind, e.nodes.clone(), e.entity))
                .collect::<Vec<_>>()
        };
        assert_eq!(conn(&old), conn(&new));
        for group in ["clamp", "tip"] {
            assert_eq!(old.group_nodes(group), new.group_nodes(group));
        }
        let fails = |from: &str, to: &str| {
            read(&GOOD_22.replacen(from, to, 1))
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            fails("2 8 2 1 4 6 1 12", "2 8 2 1 4 6 1"),
            "b.msh, line 28: 7 fields where 8 are expected (element: tag type ntags, its tags, then its nodes)"
        );
        assert_eq!(
            fails("2 8 2 1 4", "2 8 18446744073709551615 1 4"),
            "b.msh, line 28: 8 fields where 18446744073709551615 are expected (element: tag type ntags, its tags, then its nodes)"
        );
        assert_eq!(
            fails("13 2 0.5 0", "13 2 0.5"),
            "b.msh, line 23: 3 fields where 4 are expected (node tag x y z)"
        );
        assert_eq!(
            fails("4 16 2 0 1", "4 5 2 0 1"),
            "b.msh, line 30: element type 5 (8-node hexahedron) is not read: a plane mesh has points (15), lines (1, 8), triangles (2, 9) and quadrangles (3, 16, 10)"
        );
    }

    /// Each malformed file and the message a user sees (docs/structures.md's table).
    #[test]
    fn bad_files_name_the_file_the_line_and_the_fault() {
        let fails = |text: String| read(&text).unwrap_err().to_string();
        let edit = |from: &str, to: &str| {
            assert!(GOOD.contains(from), "{from}");
            fails(GOOD.replacen(from, to, 1))
        };
        let cases: Vec<(String, &str)> = vec![
            (fails(String::new()), "b.msh: is empty: no $MeshFormat"),
            (
                fails("solid beam\n".into()),
                "b.msh, line 1: 'solid beam' is not a Gmsh MSH header: a mesh file starts with $MeshFormat",
            ),
            (
                edit("4.1 0 8", "4.0 0 8"),
                "b.msh, line 2: MSH version 4.0 is not read (only 4.1 and 2.2): write it as ASCII MSH 4.1: gmsh -2 x.geo -format msh41 (and Mesh.Binary = 0, the default)",
            ),
            (
                edit("4.1 0 8", "4.1 1 8"),
                "b.msh, line 2: a binary MSH file (file type 1) is not read: write it as ASCII MSH 4.1: gmsh -2 x.geo -format msh41 (and Mesh.Binary = 0, the default)",
            ),
            (
                edit("1 1 \"clamp\"", "1 1 clamp"),
                "b.msh, line 7: 'clamp' is not a quoted name (\"name\")",
            ),
            (
                edit("3 4 1 0 1 2", "3 4 1 0 18446744073709551615 2"),
                "b.msh, line 11: 6 fields where 18446744073709551615 are expected (entity: its physical tags as many as it declares)",
            ),
            (
                edit("1 13 1 13", "1 14 1 14"),
                "b.msh, line 16: the header declares 14 nodes but the blocks hold 13",
            ),
            (
                edit("2 1 0 13\n1\n2\n", "2 1 0 13\n1\n1\n"),
                "b.msh, line 19: node 1 appears a second time (first on line 18)",
            ),
            (
                edit("4 0.5 0", "4 0,5 0"),
                "b.msh, line 39: '0,5' is not a real number",
            ),
            (edit("4 0.5 0", "4 nan 0"), "b.msh, line 39: the value nan is not finite"),
            (
                edit("4 0.5 0", "4 0.5"),
                "b.msh, line 39: 2 fields where 3 are expected (node coordinates x y z (then u v if parametric))",
            ),
            (
                edit("2 1 16 2", "2 1 5 2"),
                "b.msh, line 51: element type 5 (8-node hexahedron) is not read: a plane mesh has points (15), lines (1, 8), triangles (2, 9) and quadrangles (3, 16, 10)",
            ),
            (
                edit("2 1 16 2", "2 1 99 2"),
                "b.msh, line 51: element type 99 (a type not read here) is not read: a plane mesh has points (15), lines (1, 8), triangles (2, 9) and quadrangles (3, 16, 10)",
            ),
            (
                edit("2 1 16 2", "1 1 16 2"),
                "b.msh, line 51: a block of 8-node quadrangles (type 16, dimension 2) on an entity of dimension 1",
            ),
            (
                edit("3 1 2 5 6 7 13 11 12", "3 1 2 5 6 7 13 11"),
                "b.msh, line 52: 8 fields where 9 are expected (element tag, then its nodes)",
            ),
            (
                edit("3 1 2 5 6 7 13 11 12", "3 1 2 5 6 7 13 11 99"),
                "b.msh, line 52: element 3 names node 99, which $Nodes does not define",
            ),
            (
                edit("4 2 3 4 5", "3 2 3 4 5"),
                "b.msh, line 53: element 3 appears a second time (first on line 52)",
            ),
            (
                edit("3 4 1 4", "3 5 1 5"),
                "b.msh, line 46: the header declares 5 elements but the blocks hold 4",
            ),
            (
                edit("3 4 1 4\n0 3 15 1\n1 4\n", "3 4 1 4\n0 3 15 2\n1 4\n"),
                "b.msh, line 49: 4 fields where 2 are expected (element tag, then its nodes)",
            ),
            (
                fails(GOOD.replace("$EndElements\n", "")),
                "b.msh: the file ends inside $Elements (no $EndElements)",
            ),
            (
                edit("$EndNodes", "1 2 3"),
                "b.msh, line 44: '1 2 3' where $Nodes should end ($EndNodes): the section holds more lines than its counts declare",
            ),
            (
                fails(GOOD[..GOOD.find("$Nodes").unwrap()].to_string()),
                "b.msh: is empty: no $Nodes section",
            ),
            (
                edit("$EndPhysicalNames\n", "$EndPhysicalNames\nstray\n"),
                "b.msh, line 9: 'stray' outside a section: a section starts with $Name",
            ),
        ];
        for (got, want) in &cases {
            assert_eq!(got, want);
        }
    }

    #[test]
    fn a_binary_file_is_refused_before_its_bytes_are_decoded() {
        let mut bytes = b"$MeshFormat\n4.1 1 8\n".to_vec();
        bytes.extend_from_slice(&[1, 0, 0, 0, 0xff, 0xfe]);
        assert_eq!(
            refuse_binary("b.msh", &bytes).unwrap_err().to_string(),
            "b.msh, line 2: a binary MSH file (file type 1) is not read: write it as ASCII MSH 4.1: gmsh -2 x.geo -format msh41 (and Mesh.Binary = 0, the default)"
        );
        assert!(refuse_binary("b.msh", GOOD.as_bytes()).is_ok());
    }

    /// 20,000 corruptions of the good files, 4.1 and 2.2 (bytes replaced, deleted or repeated at
    /// deterministic places): none panics, every error's line is a line of the input.
    #[test]
    fn corrupted_meshes_are_refused_without_panicking() {
        let alphabet = b"0123456789.-+e $\n\"End";
        let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = |bound: usize| {
            // xorshift64 (Marsaglia 2003).
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % bound as u64) as usize
        };
        for round in 0..20_000 {
            let original = if round % 2 == 0 { GOOD } else { GOOD_22 };
            let mut bytes = original.as_bytes().to_vec();
            for _ in 0..1 + next(3) {
                let at = next(bytes.len());
                match next(3) {
                    0 => bytes[at] = alphabet[next(alphabet.len())],
                    1 => {
                        bytes.remove(at);
                    }
                    _ => {
                        let end = (at + next(12)).min(bytes.len());
                        let copy = bytes[at..end].to_vec();
                        bytes.splice(at..at, copy);
                    }
                }
            }
            let text = String::from_utf8(bytes).expect("the alphabet is ASCII");
            let lines = text.lines().count();
            if let Err(e) = read(&text) {
                assert_eq!(e.file, "b.msh");
                assert!(
                    e.line.is_none_or(|l| (1..=lines).contains(&l)),
                    "{e}\n{text}"
                );
            }
        }
    }
}
