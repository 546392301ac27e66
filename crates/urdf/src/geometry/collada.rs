//! A COLLADA (`.dae`) file checked before `mesh-loader` reads it.
//!
//! `mesh-loader` 0.1.13 trusts its input: on a hostile file it panics, allocates what a count
//! declares, loops forever or, through its recursive `<node>` reader, overflows the stack. A
//! library must return an error on any input instead, and catching the panic is not an option, so
//! [`validate`] parses the file first with the XML parser `mesh-loader` uses (`roxmltree`
//! 0.20, same version) and models exactly what `mesh-loader` will do with it. Only a file
//! that passes reaches `mesh-loader`. The checks, and the `mesh-loader` code each one covers:
//!
//! * **Size of the XML tree** (this module): at most [`MAX_NODES`] `<` and `=` characters
//!   (`roxmltree` reserves a node per `<` and an attribute per `=` before parsing, and parses
//!   with no node limit when `mesh-loader` calls it); at most [`MAX_NAMESPACE_DECLARATIONS`]
//!   `xmlns` in the text (`roxmltree` copies the namespaces in scope to every element that
//!   declares one: many declarations on many elements grow memory as their product); elements
//!   at most [`MAX_DEPTH`] deep, found by a scan of the text before parsing (`roxmltree`'s
//!   tokenizer recurses once per level, and `mesh-loader` reads `<node>` recursively; both
//!   overflow the stack on 100 000 levels). DTDs stay refused (`roxmltree`'s default).
//! * **Data arrays** (`model.rs`): a non-empty `<float_array>` holds exactly the `count`
//!   numbers it declares (`mesh-loader` reserves `count` before reading, 16 GB for
//!   `count="4000000000"`); a non-empty `<Name_array>`/`<IDREF_array>` in a `<source>` is
//!   refused (`mesh-loader`'s reader of them never advances: an endless loop).
//! * **Accessors** (`model.rs`, `build.rs`): `stride >= 1`; one read by a primitive names an
//!   existing `<float_array>` (else `mesh-loader` panics on the missing key or on `unwrap` of
//!   a name array) with `count * stride + offset` within it (its `assert!`, and its iterator's
//!   `unwrap`), and `count >= 1` (a count of 0 underflows its counter); the positions accessor
//!   has three float `<param>`s and `stride >= 3` (else it reads no positions and then indexes
//!   the empty list); texture coordinates leave no 1-value tail (read as a pair).
//! * **Primitives** (`model.rs`, `build.rs`): `<input>` offsets at most [`MAX_INPUT_OFFSET`]
//!   (its `offset + 1` overflows at `u32::MAX`) and every `<input>` before the `<vcount>` and
//!   `<p>` (the index stride must be the one the indices were read with); `<vcount>` holds at
//!   least `count` values, each at least 3; `<p>` holds exactly `faces x vertices x stride`
//!   indices (reserved before reading, then walked without bounds checks); `<polygons>`,
//!   `<trifans>`, `<tristrips>`, `<linestrips>` have an `<input>` before each `<p>` (a
//!   division by their stride), at least 3 vertices per `<p>` (2 for line strips) and `count`
//!   at most their number of children (reserved); the `VERTEX` input names its own mesh's
//!   `<vertices>` (else `todo!()`); every index a face reads is below the element count of
//!   the source it indexes, with the input offsets as `mesh-loader` applies them.
//! * **Work** (`build.rs`): `mesh-loader` copies every source a primitive reads once per
//!   primitive, and multiplies one matrix per enclosing `<node>` for every
//!   `<instance_geometry>`: at most [`MAX_READ_VALUES`] and [`MAX_INSTANCE_WORK`]; at most
//!   [`MAX_FACES`] triangles (its vertex indices are `u32`).
//!
//! A rule is sometimes stricter than `mesh-loader` (a polygon of 1 or 2 vertices, an `<input>`
//! after `<p>`, a count written with no space between numbers): such files are malformed, and
//! the robot descriptions in use (UR, Franka, xArm: `<triangles>`, `<polylist>`, node
//! transforms, `<unit>`, `<up_axis>`) load as before.

mod build;
mod model;

use std::borrow::Cow;
use std::io;
use std::path::Path;

use roxmltree::{Document, Node, ParsingOptions};

/// Deepest element nesting accepted (the root element is at depth 1).
pub const MAX_DEPTH: u32 = 256;
/// Most XML nodes (and `<`, `=` characters) accepted.
pub const MAX_NODES: u32 = 4_000_000;
/// Most `xmlns` occurrences accepted (COLLADA files declare one or two).
pub const MAX_NAMESPACE_DECLARATIONS: usize = 64;
/// Largest `<input offset>` accepted.
pub const MAX_INPUT_OFFSET: u32 = 1024;
/// Most source values `mesh-loader` may copy, summed over primitives.
pub const MAX_READ_VALUES: u64 = 1 << 26;
/// Most `<node>` levels walked, summed over `<instance_geometry>` elements.
pub const MAX_INSTANCE_WORK: u64 = 1 << 24;
/// Most triangles in one file.
pub const MAX_FACES: u64 = (u32::MAX / 4) as u64;

/// Whether `mesh-loader` reads `bytes` named `path` as COLLADA: extension `dae` (any case
/// here, so a `.Dae` file is checked too), or no STL/OBJ extension and `<COLLADA` in the first
/// 1024 bytes before any `solid` (`mesh-loader`'s own sniffing).
pub fn is_collada(path: &Path, bytes: &[u8]) -> bool {
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("dae") => true,
        Some("stl" | "STL" | "obj" | "OBJ") => false,
        _ => {
            let head = &bytes[..bytes.len().min(1024)];
            for i in 0..head.len() {
                if head[i] == b's' && head[i + 1..].starts_with(b"olid") {
                    return false;
                }
                if head[i..].starts_with(b"<COLLADA") {
                    return true;
                }
            }
            false
        }
    }
}

/// Checks COLLADA `bytes` (see the module documentation); the error is
/// [`io::ErrorKind::InvalidData`] naming the element and the value at fault.
pub fn validate(bytes: &[u8]) -> io::Result<()> {
    let text = decode(bytes)?;
    prescan(&text)?;
    nesting(&text)?;
    let options = ParsingOptions {
        allow_dtd: false,
        nodes_limit: MAX_NODES,
    };
    let doc = Document::parse_with_options(&text, options)
        .map_err(|e| bad(format!("not well-formed XML: {e}")))?;
    instance_work(&doc)?;
    let model = model::Model::read(&doc)?;
    build::check(&model)
}

/// The text as `mesh-loader` decodes it: UTF-8 (a BOM skipped), or UTF-16 after its BOM.
fn decode(bytes: &[u8]) -> io::Result<Cow<'_, str>> {
    let utf8 = |b| std::str::from_utf8(b).map(Cow::Borrowed).map_err(bad);
    let utf16 = |b: &[u8], f: fn([u8; 2]) -> u16| {
        if b.len() % 2 != 0 {
            return Err(bad("UTF-16 text of an odd number of bytes"));
        }
        let units = b.chunks_exact(2).map(|c| f([c[0], c[1]]));
        char::decode_utf16(units)
            .collect::<Result<String, _>>()
            .map(Cow::Owned)
            .map_err(bad)
    };
    if let Some(rest) = bytes.strip_prefix(&[0xEF, 0xBB, 0xBF]) {
        utf8(rest)
    } else if bytes.starts_with(&[0xFF, 0xFE, 0, 0]) || bytes.starts_with(&[0, 0, 0xFE, 0xFF]) {
        Err(bad("UTF-32 text is not supported"))
    } else if let Some(rest) = bytes.strip_prefix(&[0xFE, 0xFF]) {
        utf16(rest, u16::from_be_bytes)
    } else if let Some(rest) = bytes.strip_prefix(&[0xFF, 0xFE]) {
        utf16(rest, u16::from_le_bytes)
    } else {
        utf8(bytes)
    }
}

/// Bounds what `roxmltree` allocates before any node limit applies.
fn prescan(text: &str) -> io::Result<()> {
    for (c, what) in [(b'<', "`<` (XML nodes)"), (b'=', "`=` (attributes)")] {
        let n = text.bytes().filter(|&b| b == c).count();
        if n > MAX_NODES as usize {
            return Err(bad(format!(
                "{n} {what}: more than the {MAX_NODES} accepted"
            )));
        }
    }
    let ns = text.matches("xmlns").count();
    if ns > MAX_NAMESPACE_DECLARATIONS {
        return Err(bad(format!(
            "{ns} `xmlns` namespace declarations: more than the {MAX_NAMESPACE_DECLARATIONS} \
             accepted"
        )));
    }
    Ok(())
}

/// The element nesting, found by a scan of the text before any parser sees it
/// ([`pregrasp_limits::xml::check`], a loop): `roxmltree` 0.20's tokenizer recurses once per
/// level (`parse_element` → `parse_content`), as `mesh-loader`'s `<node>` reader does.
fn nesting(text: &str) -> io::Result<()> {
    let shape = pregrasp_limits::xml::Shape {
        max_depth: MAX_DEPTH as usize,
        ..pregrasp_limits::xml::Shape::COLLADA
    };
    pregrasp_limits::xml::check(text, shape).map_err(bad)
}

/// `mesh-loader` walks up the `<node>` ancestors of each `<instance_geometry>` of a
/// `<node>`, one matrix product per level: their sum (bounded by the depth) is bounded.
fn instance_work(doc: &Document) -> io::Result<()> {
    let mut work = 0u64;
    for n in doc
        .descendants()
        .filter(|n| n.has_tag_name("instance_geometry"))
    {
        if n.parent().is_some_and(|p| p.has_tag_name("node")) {
            work += n.ancestors().count() as u64;
            if work > MAX_INSTANCE_WORK {
                return Err(bad(format!(
                    "too many nested <instance_geometry> elements: more than \
                     {MAX_INSTANCE_WORK} node levels to walk (at {})",
                    describe(n)
                )));
            }
        }
    }
    Ok(())
}

/// An [`io::ErrorKind::InvalidData`] error.
fn bad(message: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, message)
}

/// An element for a message: `` `<name id="...">` (line N)`` (its `id`, else its `source`).
fn describe(node: Node) -> String {
    let name = node.tag_name().name();
    let line = node.document().text_pos_at(node.range().start).row;
    match (node.attribute("id"), node.attribute("source")) {
        (Some(id), _) => format!("`<{name} id=\"{id}\">` (line {line})"),
        (None, Some(s)) => format!("`<{name} source=\"{s}\">` (line {line})"),
        (None, None) => format!("`<{name}>` (line {line})"),
    }
}
