//! The part as a solid: its closed mesh oriented outward, with the pseudo-normals that tell
//! inside from outside ([`PartSolid`]), for [`crate::inside`]'s signed distance.

use std::collections::HashMap;
use std::sync::OnceLock;

use nalgebra::Point3;
use parry3d_f64::query::{PointQuery, PointQueryWithLocation, Ray};
use parry3d_f64::shape::{CompositeShapeRef, TriMesh, TriMeshFlags};

type P = Point3<f64>;

/// The part as a solid: its mesh oriented outward with pseudo-normals (the inside test), or
/// `None` when it bounds no solid (not closed, no volume, or parry refuses the orientation).
#[derive(Clone, Debug, Default)]
pub(crate) struct PartSolid {
    mesh: Option<TriMesh>,
}

impl PartSolid {
    /// From the part's mesh (object frame).
    ///
    /// Vertices within [`WELD`] of each other are one (a mesh built face by face, or read from
    /// STL without welding, is closed when its faces meet corner to corner); the surface is
    /// closed when every edge then joins exactly two triangles.
    pub(crate) fn of(mesh: &TriMesh) -> PartSolid {
        let (vertices, mut indices) = welded(mesh.vertices(), mesh.indices());
        if pregrasp_geometry::mesh::open_edges(&indices) > 0 {
            return PartSolid { mesh: None };
        }
        let o = vertices.first().copied().unwrap_or_else(P::origin);
        let six_volume: f64 = indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| vertices[k as usize] - o);
                a.dot(&b.cross(&c))
            })
            .sum();
        if six_volume.is_nan() || six_volume.abs() <= 1e-12 {
            return PartSolid { mesh: None };
        }
        if six_volume < 0.0 {
            indices.iter_mut().for_each(|t| t.swap(1, 2));
        } else if vertices.len() == mesh.vertices().len() {
            // Nothing welded, nothing turned: the part's own mesh with the inside test added is
            // the mesh built here (same vertices, triangles and BVH), without building its BVH
            // again (half of what this costs on a 230 k-triangle part).
            let mut same = mesh.clone();
            return PartSolid {
                mesh: same.set_flags(TriMeshFlags::ORIENTED).ok().map(|()| same),
            };
        }
        PartSolid {
            mesh: TriMesh::with_flags(vertices, indices, TriMeshFlags::ORIENTED).ok(),
        }
    }

    /// `f(x)` of the module documentation (object frame): signed distance to the surface,
    /// positive inside. `None` without an inside test.
    pub(crate) fn signed_distance(&self, x: &P) -> Option<f64> {
        self.signed_distance_near(x).map(|(f, _)| f)
    }

    /// [`signed_distance`](Self::signed_distance) and the triangle nearest `x` (an index for
    /// [`triangle_distance`](Self::triangle_distance)).
    pub(crate) fn signed_distance_near(&self, x: &P) -> Option<(f64, u32)> {
        let mesh = self.mesh.as_ref()?;
        let (proj, (triangle, _)) = mesh.project_local_point_and_get_location(x, false);
        let d = (x - proj.point).norm();
        Some((if proj.is_inside { d } else { -d }, triangle))
    }

    /// Distance (m) from `x` to triangle `triangle` of the solid's mesh (0 without a mesh).
    pub(crate) fn triangle_distance(&self, x: &P, triangle: u32) -> f64 {
        self.mesh.as_ref().map_or(0.0, |mesh| {
            mesh.triangle(triangle).distance_to_local_point(x, true)
        })
    }
}

/// Distance (m) within which two vertices are one.
const WELD: f64 = 1e-9;

/// Side (m) of the coarse cells [`welded`] files kept vertices under: a vertex's neighbours
/// within [`WELD`] nearly always share its coarse cell, so one look-up finds them.
const COARSE: f64 = 1024.0 * WELD;

/// `vertices` with those within [`WELD`] of a kept one merged into it, and `indices`
/// renumbered to them. The kept vertex a vertex merges into is the first within [`WELD`] in
/// the order of the cells [`WELD`] wide about it (offsets `(dx, dy, dz)` in `−1..=1`,
/// lexicographic), then of keeping. Kept vertices are filed by cells [`COARSE`] wide: a
/// vertex looks in its own and, on each axis where it lies within [`WELD`] of a coarse cell's
/// border, the neighbour across it (one to eight cells).
fn welded(vertices: &[P], indices: &[[u32; 3]]) -> (Vec<P>, Vec<[u32; 3]>) {
    let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut kept: Vec<P> = Vec::with_capacity(vertices.len());
    let fine = |v: &P| [v.x, v.y, v.z].map(|c| (c / WELD).floor() as i64);
    let coarse = |c: f64| (c / COARSE).floor() as i64;
    let map: Vec<u32> = vertices
        .iter()
        .map(|v| {
            let c = fine(v);
            let span = [v.x, v.y, v.z].map(|x| coarse(x - WELD)..=coarse(x + WELD));
            let mut near: Option<([i64; 3], u32)> = None;
            for i in span[0].clone() {
                for j in span[1].clone() {
                    for l in span[2].clone() {
                        for &k in cells.get(&[i, j, l]).into_iter().flatten() {
                            let w = &kept[k as usize];
                            if (w - v).norm() > WELD {
                                continue;
                            }
                            let d = fine(w);
                            let order = [d[0] - c[0], d[1] - c[1], d[2] - c[2]];
                            if near.is_none_or(|best| (order, k) < best) {
                                near = Some((order, k));
                            }
                        }
                    }
                }
            }
            near.map(|(_, k)| k).unwrap_or_else(|| {
                kept.push(*v);
                let k = (kept.len() - 1) as u32;
                let x = [v.x, v.y, v.z].map(coarse);
                cells.entry(x).or_default().push(k);
                k
            })
        })
        .collect();
    let indices = indices
        .iter()
        .map(|t| t.map(|k| map.get(k as usize).copied().unwrap_or(0)))
        .collect();
    (kept, indices)
}

/// Directions of the rays that tell inside from outside, away from the axes and each other.
const RAYS: [[f64; 3]; 2] = [[0.5773, 0.5775, 0.5774], [-0.6, 0.48, -0.64]];

impl PartSolid {
    /// Whether `x` (object frame) lies inside the part (`None` without an inside test): by the
    /// first triangle each of two rays from `x` meets (outward normals: the ray leaves the part
    /// there iff `x` is inside), the unbounded signed distance when they disagree or graze.
    pub(crate) fn side(&self, x: &P) -> Option<bool> {
        let mesh = self.mesh.as_ref()?;
        let side = |dir: &[f64; 3]| {
            let dir = nalgebra::Vector3::from(*dir);
            let ray = Ray::new(*x, dir);
            match CompositeShapeRef(mesh).cast_local_ray_and_get_normal(&ray, f64::MAX, false) {
                None => Some(false),
                Some((id, _)) => {
                    let n = mesh.triangle(id).scaled_normal();
                    let along = n.dot(&dir);
                    (along.abs() > 1e-9 * n.norm()).then_some(along > 0.0)
                }
            }
        };
        match (side(&RAYS[0]), side(&RAYS[1])) {
            (Some(a), Some(b)) if a == b => Some(a),
            _ => Some(self.signed_distance(x)? > 0.0),
        }
    }
}

/// The part's [`PartSolid`], built on first use and kept with its geometry.
pub(crate) fn solid_of<'a>(cell: &'a OnceLock<PartSolid>, mesh: &TriMesh) -> &'a PartSolid {
    cell.get_or_init(|| PartSolid::of(mesh))
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};

    use super::*;

    /// [`welded`] as it searched before the coarse cells: the 27 cells [`WELD`] wide about a
    /// vertex, in order.
    fn welded_by_fine_cells(vertices: &[P]) -> Vec<u32> {
        let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        let mut kept: Vec<P> = Vec::new();
        let cell = |v: &P| [v.x, v.y, v.z].map(|c| (c / WELD).floor() as i64);
        vertices
            .iter()
            .map(|v| {
                let c = cell(v);
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                            let found = cells.get(&key).and_then(|ks| {
                                ks.iter()
                                    .copied()
                                    .find(|&k| (kept[k as usize] - v).norm() <= WELD)
                            });
                            if let Some(k) = found {
                                return k;
                            }
                        }
                    }
                }
                kept.push(*v);
                let k = (kept.len() - 1) as u32;
                cells.entry(c).or_default().push(k);
                k
            })
            .collect()
    }

    /// The coarse cells merge every vertex into the kept one the fine cells' search chose:
    /// clusters of points within a few `WELD` of each other, strewn across coarse cells'
    /// borders (near a multiple of `COARSE`), so that several kept vertices lie within
    /// `WELD` of one point.
    #[test]
    fn welding_by_coarse_cells_merges_as_the_fine_search_did() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(61);
        for _ in 0..50 {
            let mut pts = Vec::new();
            for _ in 0..40 {
                let base = [0; 3].map(|_| {
                    rng.random_range(-3i64..3) as f64 * COARSE + rng.random_range(-3.0..3.0) * WELD
                });
                for _ in 0..rng.random_range(1..6) {
                    let jitter = [0; 3].map(|_| rng.random_range(-1.5..1.5) * WELD);
                    pts.push(P::new(
                        base[0] + jitter[0],
                        base[1] + jitter[1],
                        base[2] + jitter[2],
                    ));
                }
            }
            let tris: Vec<[u32; 3]> = (0..pts.len() as u32 / 3)
                .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
                .collect();
            let want = welded_by_fine_cells(&pts);
            let (kept, got) = welded(&pts, &tris);
            let got: Vec<u32> = got.iter().flatten().copied().collect();
            assert_eq!(got, want[..got.len()].to_vec());
            assert!(kept.len() < pts.len(), "some points merged");
        }
    }

    /// A part whose mesh needs no welding and faces outward takes its own mesh (BVH and all)
    /// with the inside test added: it answers as the mesh built again from its vertices and
    /// triangles does, bit for bit, at points inside, outside and on the surface; a mesh
    /// wound inward is turned and still answers.
    #[test]
    fn the_part_s_own_mesh_answers_as_one_built_again() {
        let mesh =
            pregrasp_geometry::shapes::cuboid(P::new(0.0, 0.0, -0.02), P::new(0.3, 0.2, 0.0));
        let tri = TriMesh::new(mesh.vertices.clone(), mesh.triangles.clone()).unwrap();
        let solid = PartSolid::of(&tri);
        // Nothing to weld or turn: the shortcut is what is tried here.
        assert_eq!(
            welded(tri.vertices(), tri.indices()).0.len(),
            tri.vertices().len()
        );
        assert_eq!(solid.mesh.as_ref().unwrap().indices(), tri.indices());
        let built = PartSolid {
            mesh: TriMesh::with_flags(
                mesh.vertices.clone(),
                mesh.triangles.clone(),
                TriMeshFlags::ORIENTED,
            )
            .ok(),
        };
        let mut inward = mesh.clone();
        inward.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        let turned = PartSolid::of(&TriMesh::new(inward.vertices, inward.triangles).unwrap());
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(29);
        for _ in 0..2000 {
            let x = P::new(
                rng.random_range(-0.05..0.35),
                rng.random_range(-0.05..0.25),
                rng.random_range(-0.04..0.02),
            );
            let (f, t) = solid.signed_distance_near(&x).unwrap();
            let (g, u) = built.signed_distance_near(&x).unwrap();
            assert_eq!((f.to_bits(), t), (g.to_bits(), u), "at {x:?}");
            assert_eq!(solid.side(&x), built.side(&x), "at {x:?}");
            let h = turned.signed_distance(&x).unwrap();
            assert!((h - f).abs() < 1e-12, "turned: {h} against {f} at {x:?}");
        }
    }
}
