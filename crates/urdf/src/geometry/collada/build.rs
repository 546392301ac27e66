//! The checks on what `mesh-loader` 0.1.13 does when it builds each geometry's mesh
//! (`collada/instance.rs`, `collada/iter.rs` in its source): every reference it follows
//! resolves, every accessor it reads fits its array, every index a face reads is in range.

use std::io;

use super::model::{Accessor, Kind, Mesh, Model, Primitive};
use super::{bad, MAX_FACES, MAX_READ_VALUES};

/// A source a primitive reads: the accessor's id, the input offset in `<p>`, and the number
/// of elements `mesh-loader` collects from it (0: it collects none and reads no index).
struct Read<'m> {
    what: &'static str,
    id: &'m str,
    offset: u32,
    len: u64,
}

/// Checks every primitive of every geometry `mesh-loader` will build (all of them: it builds
/// instanced and uninstanced geometries alike).
pub(super) fn check(model: &Model) -> io::Result<()> {
    let mut values = 0u64;
    let mut faces = 0u64;
    for (gid, mesh) in &model.geometries {
        for prim in &mesh.primitives {
            let Some(vertex) = &prim.vertex else {
                continue; // mesh-loader reads nothing of a primitive without VERTEX input
            };
            if vertex.source != mesh.vertices_id {
                return Err(bad(format!(
                    "{} of geometry \"{gid}\": its VERTEX input names \"#{}\", not its mesh's \
                     <vertices id=\"{}\"> (mesh-loader 0.1.13 stops at a `todo!()` there)",
                    prim.at, vertex.source, mesh.vertices_id
                )));
            }
            let reads = reads(model, mesh, prim)?;
            values += reads.iter().map(|r| r.len).sum::<u64>();
            if values > MAX_READ_VALUES {
                return Err(bad(format!(
                    "{} of geometry \"{gid}\": the primitives read more than {MAX_READ_VALUES} \
                     source elements in all",
                    prim.at
                )));
            }
            faces += face_count(prim)?;
            if faces > MAX_FACES {
                return Err(bad(format!("more than {MAX_FACES} triangles")));
            }
            if matches!(prim.kind, Kind::Lines | Kind::LineStrips) {
                continue; // no faces, no index read
            }
            for r in reads.iter().filter(|r| r.len > 0) {
                indices_in_range(prim, r)?;
            }
        }
    }
    Ok(())
}

/// The sources of a primitive, resolved as `mesh-loader` resolves them: positions from the
/// mesh's `<vertices>`; normals, the first texture coordinates and colours from the
/// primitive's own input, else from `<vertices>` at the VERTEX offset.
fn reads<'m>(model: &'m Model, mesh: &'m Mesh, prim: &'m Primitive) -> io::Result<Vec<Read<'m>>> {
    let vertex_offset = prim.vertex.as_ref().map_or(0, |v| v.offset);
    let own_or_vertices = |own: Option<&'m super::model::Input<'m>>, shared: Option<&'m str>| {
        own.map(|i| (i.source, i.offset))
            .or(shared.map(|s| (s, vertex_offset)))
    };
    let position = (mesh.position, vertex_offset);
    let normal = own_or_vertices(prim.normal.as_ref(), mesh.normal);
    let texcoord = own_or_vertices(prim.texcoord.first(), mesh.texcoord);
    let color = own_or_vertices(prim.color.as_ref(), mesh.color);
    let mut out = Vec::new();
    for (what, src, need) in [
        ("POSITION", Some(position), 3),
        ("NORMAL", normal, 3),
        ("TEXCOORD", texcoord, 2),
        ("COLOR", color, 3),
    ] {
        let Some((id, offset)) = src else { continue };
        let acc = model.accessors.get(id).ok_or_else(|| {
            bad(format!(
                "{}: its {what} input names \"#{id}\", which is no <source> with an <accessor>",
                prim.at
            ))
        })?;
        let array = array_len(model, acc)?;
        let usable = acc.stride >= need && acc.params >= need as usize && acc.all_float;
        let len = if !usable {
            if what == "POSITION" {
                return Err(bad(format!(
                    "{}: positions need stride >= 3 and three float <param>s (stride {}, {} \
                     params)",
                    acc.at, acc.stride, acc.params
                )));
            }
            0
        } else {
            fits(acc, array)?;
            if what == "TEXCOORD" {
                // mesh-loader collects every `stride` chunk of the whole array as a pair.
                let stride = u64::from(acc.stride);
                if array % stride == 1 {
                    return Err(bad(format!(
                        "{}: the array's last texture coordinate has 1 value (array of {array}, \
                         stride {stride})",
                        acc.at
                    )));
                }
                array.div_ceil(stride)
            } else {
                if acc.count == 0 {
                    return Err(bad(format!("{} declares count 0", acc.at)));
                }
                u64::from(acc.count)
            }
        };
        out.push(Read {
            what,
            id,
            offset,
            len,
        });
    }
    Ok(out)
}

/// The length of the `<float_array>` an accessor reads.
fn array_len(model: &Model, acc: &Accessor) -> io::Result<u64> {
    match model.arrays.get(acc.source) {
        Some(a) if a.float => Ok(a.len),
        Some(_) => Err(bad(format!(
            "{} reads \"#{}\", a name array, not numbers",
            acc.at, acc.source
        ))),
        None => Err(bad(format!(
            "{} reads \"#{}\", which is no data array",
            acc.at, acc.source
        ))),
    }
}

/// `count * stride + offset <= len`.
fn fits(acc: &Accessor, len: u64) -> io::Result<()> {
    let need = u64::from(acc.count) * u64::from(acc.stride) + u64::from(acc.offset);
    if need > len {
        return Err(bad(format!(
            "{} reads {} x {} values from offset {} ({need}) but its array \"#{}\" holds {len}",
            acc.at, acc.count, acc.stride, acc.offset, acc.source
        )));
    }
    Ok(())
}

/// The triangles `mesh-loader` emits for a primitive, once its `<p>` has been checked to hold
/// the indices they read.
fn face_count(prim: &Primitive) -> io::Result<u64> {
    let stride = u64::from(prim.stride);
    let held = prim.p.len() as u64;
    let vertices: u64 = prim.vcount.iter().map(|&v| u64::from(v)).sum();
    let expected = match prim.kind {
        Kind::Lines | Kind::LineStrips => return Ok(0),
        Kind::Triangles => u64::from(prim.count) * 3 * stride,
        _ => vertices * stride,
    };
    if held != expected {
        return Err(bad(format!(
            "{}: <p> holds {held} indices where its count and <vcount> need {expected}",
            prim.at
        )));
    }
    Ok(match prim.kind {
        Kind::Triangles => u64::from(prim.count),
        _ => prim.vcount.iter().map(|&v| u64::from(v) - 2).sum(),
    })
}

/// Every index at `offset` in each vertex's group of `stride` indices (all of which a face
/// reads) is below the element count of the source.
fn indices_in_range(prim: &Primitive, r: &Read) -> io::Result<()> {
    let stride = prim.stride as usize;
    let start = r.offset as usize;
    for (k, &v) in prim.p.iter().enumerate().skip(start).step_by(stride) {
        if u64::from(v) >= r.len {
            return Err(bad(format!(
                "<p> of {} holds index {v} (value {k}) for its {} input at offset {}, but \
                 \"#{}\" has {} elements",
                prim.at, r.what, r.offset, r.id, r.len
            )));
        }
    }
    Ok(())
}
