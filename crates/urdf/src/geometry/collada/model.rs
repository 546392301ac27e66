//! What `mesh-loader` 0.1.13 reads of `<library_geometries>`, read the way it reads it: in
//! document order, later ids replacing earlier ones, the checks that must hold before each of
//! its allocations made as the element is read. `build.rs` checks the rest.

use std::collections::{BTreeMap, HashMap};
use std::io;

use roxmltree::{Document, Node};

use super::{bad, describe, MAX_INPUT_OFFSET};

/// A `<float_array>` (or a name array, which `mesh-loader` cannot read as numbers).
pub(super) struct Array {
    /// `<float_array>` rather than `<Name_array>`/`<IDREF_array>`.
    pub float: bool,
    /// Values `mesh-loader` will hold: `count`, or 0 for an empty element.
    pub len: u64,
}

/// An `<accessor>` (the `<source>` id is its key).
pub(super) struct Accessor<'a> {
    pub count: u32,
    pub stride: u32,
    pub offset: u32,
    /// The array id (the `source` attribute without its `#`).
    pub source: &'a str,
    /// Number of `<param>` children, and whether all have `type="float"`.
    pub params: usize,
    pub all_float: bool,
    /// For messages.
    pub at: String,
}

/// An `<input>` of a primitive.
pub(super) struct Input<'a> {
    pub source: &'a str,
    pub offset: u32,
    pub set: u32,
}

/// The primitive elements.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Kind {
    Lines,
    LineStrips,
    Polygons,
    Polylist,
    Triangles,
    TriFans,
    TriStrips,
}

/// A primitive (`<triangles>`, `<polylist>`, ...) as `mesh-loader` holds it.
pub(super) struct Primitive<'a> {
    pub kind: Kind,
    pub count: u32,
    /// One more than the largest input offset: indices per vertex in `<p>`.
    pub stride: u32,
    pub vertex: Option<Input<'a>>,
    pub normal: Option<Input<'a>>,
    pub color: Option<Input<'a>>,
    /// Sorted by `set`, as `mesh-loader` sorts them.
    pub texcoord: Vec<Input<'a>>,
    /// Vertices per polygon (`<vcount>`, or one per `<p>` of the multi-`<p>` kinds).
    pub vcount: Vec<u32>,
    pub p: Vec<u32>,
    pub at: String,
}

/// A `<mesh>`: its `<vertices>` and primitives.
pub(super) struct Mesh<'a> {
    pub vertices_id: &'a str,
    pub position: &'a str,
    pub normal: Option<&'a str>,
    pub texcoord: Option<&'a str>,
    pub color: Option<&'a str>,
    pub primitives: Vec<Primitive<'a>>,
}

/// Everything of `<library_geometries>` `mesh-loader` builds meshes from.
#[derive(Default)]
pub(super) struct Model<'a> {
    /// Array id → array (document-wide, last wins, as in `mesh-loader`).
    pub arrays: HashMap<&'a str, Array>,
    /// `<source>` id → its accessor (document-wide, last wins).
    pub accessors: HashMap<&'a str, Accessor<'a>>,
    /// Geometry id → mesh (last wins; a geometry holding `<convex_mesh>`, `<spline>` or
    /// `<brep>` is dropped, as `mesh-loader` drops it).
    pub geometries: BTreeMap<&'a str, Mesh<'a>>,
}

impl<'a> Model<'a> {
    /// Reads every `<library_geometries>` child of the root element.
    pub fn read(doc: &'a Document<'a>) -> io::Result<Self> {
        let mut m = Model::default();
        let root = doc.root_element();
        for lib in elements(root).filter(|n| n.has_tag_name("library_geometries")) {
            for g in elements(lib).filter(|n| n.has_tag_name("geometry")) {
                let id = required(g, "id")?;
                let mut mesh = None;
                let mut dropped = false;
                for c in elements(g) {
                    match c.tag_name().name() {
                        "mesh" => mesh = Some(m.mesh(c)?),
                        "convex_mesh" | "spline" | "brep" => {
                            dropped = true;
                            break;
                        }
                        _ => {}
                    }
                }
                if let (Some(mesh), false) = (mesh, dropped) {
                    m.geometries.insert(id, mesh);
                }
            }
        }
        Ok(m)
    }

    fn mesh(&mut self, node: Node<'a, 'a>) -> io::Result<Mesh<'a>> {
        let mut vertices = None;
        let mut primitives = Vec::new();
        for c in elements(node) {
            let kind = match c.tag_name().name() {
                "source" => {
                    self.source(c)?;
                    continue;
                }
                "vertices" => {
                    vertices = Some(c);
                    continue;
                }
                "lines" => Kind::Lines,
                "linestrips" => Kind::LineStrips,
                "polygons" => Kind::Polygons,
                "polylist" => Kind::Polylist,
                "triangles" => Kind::Triangles,
                "trifans" => Kind::TriFans,
                "tristrips" => Kind::TriStrips,
                _ => continue,
            };
            primitives.push(primitive(c, kind)?);
        }
        let v = vertices.ok_or_else(|| bad(format!("{} has no <vertices>", describe(node))))?;
        let mut mesh = Mesh {
            vertices_id: required(v, "id")?,
            position: "",
            normal: None,
            texcoord: None,
            color: None,
            primitives,
        };
        let mut position = None;
        for i in elements(v).filter(|n| n.has_tag_name("input")) {
            let source = Some(url(i, "source")?);
            match required(i, "semantic")? {
                "POSITION" => position = source,
                "NORMAL" => mesh.normal = source,
                "TEXCOORD" => mesh.texcoord = source,
                "COLOR" => mesh.color = source,
                _ => {}
            }
        }
        mesh.position =
            position.ok_or_else(|| bad(format!("{} has no POSITION <input>", describe(v))))?;
        Ok(mesh)
    }

    /// A `<source>`: its last data array and its last accessor, each checked.
    fn source(&mut self, node: Node<'a, 'a>) -> io::Result<()> {
        let id = required(node, "id")?;
        let mut array = None;
        let mut accessor = None;
        for c in elements(node) {
            match c.tag_name().name() {
                "float_array" | "IDREF_array" | "Name_array" => array = Some(data_array(c)?),
                "technique_common" => {
                    for a in elements(c).filter(|n| n.has_tag_name("accessor")) {
                        accessor = Some(read_accessor(a)?);
                    }
                }
                _ => {}
            }
        }
        if let Some(a) = accessor {
            self.accessors.insert(id, a);
        }
        if let Some((array_id, a)) = array {
            self.arrays.insert(array_id, a);
        }
        Ok(())
    }
}

/// A data array: a non-empty one holds exactly its `count` numbers; a non-empty name array is
/// refused (`mesh-loader` loops forever on it).
fn data_array<'a>(node: Node<'a, 'a>) -> io::Result<(&'a str, Array)> {
    let id = required(node, "id")?;
    let count: u32 = number(node, "count")?.ok_or_else(|| missing(node, "count"))?;
    let name = node.tag_name().name();
    let text = trimmed_text(node);
    let float = name == "float_array";
    if text.is_empty() {
        return Ok((id, Array { float, len: 0 }));
    }
    if !float {
        return Err(bad(format!(
            "{} holds names: a non-empty <{name}> in a <source> is not supported (mesh-loader \
             0.1.13 never finishes reading one)",
            describe(node)
        )));
    }
    let held = tokens(text).count() as u64;
    if u64::from(count) != held {
        return Err(bad(format!(
            "{} declares count {count} but holds {held} numbers",
            describe(node)
        )));
    }
    Ok((id, Array { float, len: held }))
}

fn read_accessor<'a>(node: Node<'a, 'a>) -> io::Result<Accessor<'a>> {
    let count = number(node, "count")?.ok_or_else(|| missing(node, "count"))?;
    let stride = number(node, "stride")?.unwrap_or(1);
    if stride == 0 {
        return Err(bad(format!("{} declares stride 0", describe(node))));
    }
    let params: Vec<_> = elements(node).filter(|n| n.has_tag_name("param")).collect();
    Ok(Accessor {
        count,
        stride,
        offset: number(node, "offset")?.unwrap_or(0),
        source: url(node, "source")?,
        params: params.len(),
        all_float: params.iter().all(|p| p.attribute("type") == Some("float")),
        at: describe(node),
    })
}

/// A primitive element, its children in order as `mesh-loader` reads them.
fn primitive<'a>(node: Node<'a, 'a>, kind: Kind) -> io::Result<Primitive<'a>> {
    let at = describe(node);
    let count: u32 = number(node, "count")?.ok_or_else(|| missing(node, "count"))?;
    let children = elements(node).count();
    let mut prim = Primitive {
        kind,
        count,
        stride: 0,
        vertex: None,
        normal: None,
        color: None,
        texcoord: Vec::new(),
        vcount: Vec::new(),
        p: Vec::new(),
        at,
    };
    let mut indices_seen = false;
    for c in elements(node) {
        match c.tag_name().name() {
            "input" => {
                if indices_seen {
                    return Err(bad(format!(
                        "{}: an <input> after <p> or <vcount> (inputs come first)",
                        prim.at
                    )));
                }
                prim.input(c)?;
            }
            "vcount" => {
                indices_seen = true;
                if kind == Kind::Polylist && count > 0 && prim.vcount.is_empty() {
                    prim.vcount = vcount(c, count)?;
                }
            }
            "p" => {
                indices_seen = true;
                if count > 0 {
                    prim.indices(c, children)?;
                }
            }
            _ => {}
        }
    }
    prim.texcoord.sort_by_key(|i| i.set);
    Ok(prim)
}

impl<'a> Primitive<'a> {
    fn input(&mut self, node: Node<'a, 'a>) -> io::Result<()> {
        let offset: u32 = number(node, "offset")?.ok_or_else(|| missing(node, "offset"))?;
        if offset > MAX_INPUT_OFFSET {
            return Err(bad(format!(
                "{} declares offset {offset}: more than the {MAX_INPUT_OFFSET} accepted",
                describe(node)
            )));
        }
        self.stride = self.stride.max(offset + 1);
        let set = number(node, "set")?.unwrap_or(0);
        let input = Input {
            source: url(node, "source")?,
            offset,
            set,
        };
        match required(node, "semantic")? {
            "VERTEX" if set == 0 => self.vertex = Some(input),
            "NORMAL" if set == 0 => self.normal = Some(input),
            "COLOR" => self.color = Some(input),
            "TEXCOORD" => self.texcoord.push(input),
            _ => {}
        }
        Ok(())
    }

    /// A `<p>`: the index count checked against what the primitive declares before
    /// `mesh-loader` reserves it.
    fn indices(&mut self, node: Node<'a, 'a>, children: usize) -> io::Result<()> {
        let values = index_list(node)?;
        let n = values.len() as u64;
        let stride = u64::from(self.stride);
        match self.kind {
            Kind::Lines | Kind::Polylist | Kind::Triangles => {
                if !self.p.is_empty() {
                    return Err(bad(format!("{}: more than one <p>", self.at)));
                }
                let (vertices, what) = match self.kind {
                    Kind::Polylist => (self.vcount.iter().map(|&v| u64::from(v)).sum(), "<vcount>"),
                    Kind::Lines => (u64::from(self.count) * 2, "count x 2"),
                    _ => (u64::from(self.count) * 3, "count x 3"),
                };
                if n != vertices * stride {
                    return Err(bad(format!(
                        "<p> of {} holds {n} indices, not {} ({vertices} vertices from {what}, \
                         {stride} indices each)",
                        self.at,
                        vertices * stride
                    )));
                }
            }
            Kind::Polygons | Kind::LineStrips | Kind::TriFans | Kind::TriStrips => {
                if stride == 0 {
                    return Err(bad(format!("{}: a <p> before any <input>", self.at)));
                }
                if self.count as usize > children {
                    return Err(bad(format!(
                        "{} declares count {} but has {children} child elements",
                        self.at, self.count
                    )));
                }
                let min = if self.kind == Kind::LineStrips { 2 } else { 3 };
                if n % stride != 0 || n / stride < min {
                    return Err(bad(format!(
                        "<p> of {} holds {n} indices: not a multiple of {stride} indices per \
                         vertex, or fewer than {min} vertices",
                        self.at
                    )));
                }
                self.vcount.push((n / stride) as u32);
            }
        }
        self.p.extend(values);
        Ok(())
    }
}

/// The first `count` values of a `<vcount>` (`mesh-loader` reads no more), each at least 3.
fn vcount(node: Node, count: u32) -> io::Result<Vec<u32>> {
    let mut values = tokens(trimmed_text(node));
    let mut out = Vec::new();
    for k in 0..count {
        let t = values.next().ok_or_else(|| {
            bad(format!(
                "{} holds {k} values but its primitive declares count {count}",
                describe(node)
            ))
        })?;
        let v = index(node, t)?;
        if v < 3 {
            return Err(bad(format!(
                "{} declares a polygon of {v} vertices (at least 3 accepted)",
                describe(node)
            )));
        }
        out.push(v);
    }
    Ok(out)
}

fn index_list(node: Node) -> io::Result<Vec<u32>> {
    tokens(trimmed_text(node)).map(|t| index(node, t)).collect()
}

/// A decimal `u32` (an optional `+`, digits), as `mesh-loader` reads indices.
fn index(node: Node, t: &str) -> io::Result<u32> {
    t.parse()
        .map_err(|_| bad(format!("{} holds {t:?}, not an index", describe(node))))
}

/// The numbers of a text: split at XML whitespace.
fn tokens(text: &str) -> impl Iterator<Item = &str> {
    text.split(['\t', '\n', '\r', ' '])
        .filter(|t| !t.is_empty())
}

/// The element's first text child, trimmed of XML whitespace (what `mesh-loader` reads).
fn trimmed_text<'a>(node: Node<'a, 'a>) -> &'a str {
    node.text()
        .unwrap_or_default()
        .trim_matches(['\t', '\n', '\r', ' '])
}

fn elements<'a>(node: Node<'a, 'a>) -> impl Iterator<Item = Node<'a, 'a>> {
    node.children().filter(Node::is_element)
}

fn required<'a>(node: Node<'a, 'a>, name: &str) -> io::Result<&'a str> {
    node.attribute(name).ok_or_else(|| missing(node, name))
}

fn missing(node: Node, name: &str) -> io::Error {
    bad(format!("{} has no `{name}` attribute", describe(node)))
}

/// A reference `#id`: the id.
fn url<'a>(node: Node<'a, 'a>, name: &str) -> io::Result<&'a str> {
    let v = required(node, name)?;
    v.strip_prefix('#').ok_or_else(|| {
        bad(format!(
            "{}: `{name}=\"{v}\"` is not a `#id` reference",
            describe(node)
        ))
    })
}

/// An optional `u32` attribute, parsed as `mesh-loader` parses it (`str::parse`).
fn number(node: Node, name: &str) -> io::Result<Option<u32>> {
    node.attribute(name)
        .map(|v| {
            v.parse().map_err(|_| {
                bad(format!(
                    "{}: `{name}=\"{v}\"` is not a count",
                    describe(node)
                ))
            })
        })
        .transpose()
}
