//! Convex hulls of the built-in models' fixed point sets, computed once by parry and kept in the
//! repository (`data/baked_hulls.bin`).
//!
//! The first plan of a process hulls the same points every time: each 2F-85 finger link (for
//! the closing and the gripper's lowest point), the finger pieces a closing comes near (their
//! bounding planes), the arm links whose lowest point is asked, the open hand's pieces. parry's
//! quickhull takes about 2 M instructions for a finger link's 400–500 points; the chair side's
//! first plan spent about 20 M instructions (15 % of the process) on such hulls, none of which
//! depend on the part.
//!
//! [`convex_hull`] answers exactly what `parry3d_f64::transformation::try_convex_hull` answers
//! (`None` for its errors): from the table where it holds the points, found by a 128-bit digest
//! of their coordinates' bits and their count, else from parry. The table is parry's own
//! answers, recorded while the test `crates/planner/tests/baked_hulls.rs` plans the built-in
//! examples (recording asks parry every time); the test fails when they differ from the file
//! (another parry, other link data) and `PREGRASP_BLESS=1` writes it again. Points the table
//! does not hold (another arm model, a jaw gripper from a URDF) are hulled at run time as
//! before, and so is a piece's vertex graph built because it was scanned often (which pieces
//! get there varies from run to run: `tight::polytope::Hulled`).

use std::collections::{BTreeMap, HashMap};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, OnceLock};

use nalgebra::Point3;

type P = Point3<f64>;

/// A hull as parry gives it: its vertices and its triangles (indices into them).
pub type HullFaces = (Vec<P>, Vec<[u32; 3]>);

/// The digest of a point set: two 64-bit hashes of its coordinates' bits, and its length.
type Key = (u64, u64, u64);

/// The table, little-endian: the magic `MAGIC`, a `u32` entry count, then per entry (in the
/// order of their keys) the key's three `u64`, a `u32` vertex count `v` and a `u32` face count
/// `f`, `3 v` coordinates as `f64` bits and `3 f` vertex indices as `u32`. Reading it costs
/// next to nothing (an entry is decoded only when asked for); decimal numbers in JSON cost
/// about 4 M instructions to parse, a fifth of what the table saves.
const BLOB: &[u8] = include_bytes!("../data/baked_hulls.bin");
const MAGIC: &[u8; 8] = b"PGHULLS1";

static RECORDING: AtomicBool = AtomicBool::new(false);

fn recorded() -> &'static Mutex<BTreeMap<Key, HullFaces>> {
    static RECORDED: OnceLock<Mutex<BTreeMap<Key, HullFaces>>> = OnceLock::new();
    RECORDED.get_or_init(Default::default)
}

/// The digest of `points`: FNV-1a and a multiply–xorshift mix over every coordinate's bits.
fn digest(points: &[P]) -> Key {
    let (mut a, mut b) = (0xcbf2_9ce4_8422_2325u64, 0x9e37_79b9_7f4a_7c15u64);
    for p in points {
        for c in [p.x, p.y, p.z] {
            let bits = c.to_bits();
            a = (a ^ bits).wrapping_mul(0x0000_0100_0000_01b3);
            b = (b ^ bits).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            b ^= b >> 31;
        }
    }
    (a, b, points.len() as u64)
}

/// A cursor over the table's bytes.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Option<[u8; N]> {
        let out = self.bytes.get(self.at..self.at + N)?.try_into().ok()?;
        self.at += N;
        Some(out)
    }
    fn u32(&mut self) -> Option<u32> {
        self.take().map(u32::from_le_bytes)
    }
    fn u64(&mut self) -> Option<u64> {
        self.take().map(u64::from_le_bytes)
    }
}

/// Where each entry's vertices start in the table, with its vertex and face counts.
type Index = HashMap<Key, (usize, usize, usize)>;

/// The table's index; empty if the table is not one (a test says it is).
fn index() -> &'static Index {
    static INDEX: OnceLock<Index> = OnceLock::new();
    INDEX.get_or_init(|| read_index(BLOB).unwrap_or_default())
}

fn read_index(bytes: &[u8]) -> Option<Index> {
    let mut r = Reader { bytes, at: 0 };
    if &r.take::<8>()? != MAGIC {
        return None;
    }
    let n = r.u32()? as usize;
    let mut index = HashMap::with_capacity(n);
    for _ in 0..n {
        let key = (r.u64()?, r.u64()?, r.u64()?);
        let (v, f) = (r.u32()? as usize, r.u32()? as usize);
        index.insert(key, (r.at, v, f));
        r.at = r.at.checked_add(24 * v + 12 * f)?;
    }
    (r.at == bytes.len()).then_some(index)
}

/// The entry whose vertices start at `at`.
fn read_hull(bytes: &[u8], (at, v, f): (usize, usize, usize)) -> Option<HullFaces> {
    let mut r = Reader { bytes, at };
    let mut coord = || r.u64().map(f64::from_bits);
    let vertices = (0..v)
        .map(|_| Some(P::new(coord()?, coord()?, coord()?)))
        .collect::<Option<Vec<P>>>()?;
    let mut r = Reader {
        bytes,
        at: at + 24 * v,
    };
    let faces = (0..f)
        .map(|_| Some([r.u32()?, r.u32()?, r.u32()?]))
        .collect::<Option<Vec<_>>>()?;
    Some((vertices, faces))
}

/// parry's convex hull of `points` (`try_convex_hull`; `None` where it gives an error), from
/// the baked table where it holds them.
pub fn convex_hull(points: &[P]) -> Option<HullFaces> {
    let key = digest(points);
    if RECORDING.load(Ordering::Relaxed) {
        let hull = parry3d_f64::transformation::try_convex_hull(points).ok()?;
        if let Ok(mut rec) = recorded().lock() {
            rec.insert(key, hull.clone());
        }
        return Some(hull);
    }
    if let Some(hull) = index().get(&key).and_then(|&e| read_hull(BLOB, e)) {
        return Some(hull);
    }
    parry3d_f64::transformation::try_convex_hull(points).ok()
}

/// parry's `ConvexPolyhedron::from_convex_hull(points)` (its `try_convex_hull`, then
/// `from_convex_mesh`), the hull from the baked table where it holds the points
/// ([`convex_hull`]): the same polyhedron, without the quickhull (the 2F-85's open-hand pieces
/// cost about 38 M instructions to hull).
pub fn convex_polyhedron(points: &[P]) -> Option<parry3d_f64::shape::ConvexPolyhedron> {
    let (vertices, faces) = convex_hull(points)?;
    parry3d_f64::shape::ConvexPolyhedron::from_convex_mesh(vertices, &faces)
}

/// From now on every hull comes from parry and is recorded (the table's test: call it before
/// anything is hulled).
#[doc(hidden)]
pub fn start_recording() {
    RECORDING.store(true, Ordering::Relaxed);
}

/// The hulls recorded since [`start_recording`], as the table's bytes.
#[doc(hidden)]
pub fn recorded_table() -> Vec<u8> {
    let rec = recorded().lock().map(|r| r.clone()).unwrap_or_default();
    write_table(&rec)
}

fn write_table(hulls: &BTreeMap<Key, HullFaces>) -> Vec<u8> {
    let count = |n: usize| u32::try_from(n).expect("a table entry's count fits u32");
    let mut out = MAGIC.to_vec();
    out.extend(count(hulls.len()).to_le_bytes());
    for (&(a, b, n), (vertices, faces)) in hulls {
        for k in [a, b, n] {
            out.extend(k.to_le_bytes());
        }
        out.extend(count(vertices.len()).to_le_bytes());
        out.extend(count(faces.len()).to_le_bytes());
        for c in vertices.iter().flat_map(|p| [p.x, p.y, p.z]) {
            out.extend(c.to_bits().to_le_bytes());
        }
        for k in faces.iter().flatten() {
            out.extend(k.to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_digest_tells_point_sets_apart() {
        let a = vec![P::new(0.0, 0.0, 0.0), P::new(1.0, 0.0, 0.0)];
        let b = vec![P::new(1.0, 0.0, 0.0), P::new(0.0, 0.0, 0.0)];
        let c = vec![P::new(0.0, 0.0, 0.0), P::new(1.0, 0.0, -0.0)];
        assert_ne!(digest(&a), digest(&b));
        assert_ne!(digest(&a), digest(&c));
        assert_eq!(digest(&a), digest(&a.clone()));
    }

    #[test]
    fn points_the_table_lacks_are_hulled_by_parry() {
        let cube: Vec<P> = (0..8)
            .map(|k| {
                P::new(
                    (k & 1) as f64,
                    ((k >> 1) & 1) as f64,
                    ((k >> 2) & 1) as f64 + 0.123,
                )
            })
            .collect();
        assert!(!index().contains_key(&digest(&cube)));
        let want = parry3d_f64::transformation::try_convex_hull(&cube).unwrap();
        assert_eq!(convex_hull(&cube), Some(want));
    }

    #[test]
    fn a_table_reads_back_bit_for_bit() {
        let pts = vec![
            P::new(0.1, -0.0, f64::MIN_POSITIVE),
            P::new(1e300, -2.5, 3.0),
            P::new(0.0, 1.0, 0.0),
            P::new(0.0, 0.0, 1.0),
        ];
        let hull: HullFaces = (
            pts.clone(),
            vec![[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]],
        );
        let table = BTreeMap::from([(digest(&pts), hull.clone())]);
        let bytes = write_table(&table);
        let index = read_index(&bytes).unwrap();
        let back = read_hull(&bytes, index[&digest(&pts)]).unwrap();
        let bits = |v: &[P]| {
            v.iter()
                .flat_map(|p| [p.x, p.y, p.z])
                .map(f64::to_bits)
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&back.0), bits(&hull.0));
        assert_eq!(back.1, hull.1);
        assert!(
            read_index(&bytes[..bytes.len() - 1]).is_none(),
            "a cut table is none"
        );
    }

    #[test]
    fn the_shipped_table_reads_and_its_faces_index_their_vertices() {
        let index = read_index(BLOB).expect("data/baked_hulls.bin is a table");
        assert!(!index.is_empty());
        for &entry in index.values() {
            let (vertices, faces) = read_hull(BLOB, entry).unwrap();
            assert!(faces.len() >= 4);
            assert!(faces
                .iter()
                .flatten()
                .all(|&k| (k as usize) < vertices.len()));
        }
    }
}
