//! Triangulation of a planar polygon with holes: hole bridging, then ear clipping.
//!
//! Input: an outer ring and hole rings of 2-D points (metres, any orientation, no repeated
//! closing point). The rings must be simple, the holes strictly inside the outer ring and
//! disjoint from each other. Output: triangles as index triples into the concatenation
//! `outer ++ holes[0] ++ holes[1] ++ …`, counter-clockwise (positive signed area), covering
//! exactly the region inside the outer ring and outside every hole; every ring edge is an
//! edge of exactly one triangle, and no new vertex is introduced.
//!
//! Method: each hole is joined to the outer ring by a *bridge* — a segment from a hole
//! vertex to a ring vertex that crosses no ring edge and leaves both ends into the region —
//! which turns the region into one weakly simple polygon (the bridge is walked both ways).
//! That polygon is cut by ear clipping: repeatedly remove a convex vertex whose triangle
//! contains no other vertex. `O(n²)` per hole and `O(n³)` worst case for the clipping, which
//! is immaterial for part outlines of a few hundred vertices.

use nalgebra::Point2;
use thiserror::Error;

/// Why a polygon could not be triangulated (the input was not a valid polygon with holes).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum TriangulationError {
    #[error("ring {ring} has {len} vertices; a polygon ring needs at least 3")]
    TooFewVertices { ring: usize, len: usize },
    #[error("ring {ring} has zero area")]
    ZeroArea { ring: usize },
    #[error("hole {hole} cannot be connected to the outer ring (does it lie outside it, or overlap another ring?)")]
    NoBridge { hole: usize },
    #[error("ear clipping found no ear with {remaining} vertices left (self-intersecting rings?)")]
    NoEar { remaining: usize },
}

/// Twice the signed area of triangle `a b c` (positive when counter-clockwise).
pub(crate) fn cross(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>) -> f64 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// Signed area of a ring (positive when counter-clockwise), by the shoelace formula.
pub fn signed_area(ring: &[Point2<f64>]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let (p, q) = (ring[i], ring[(i + 1) % n]);
            p.x * q.y - q.x * p.y
        })
        .sum::<f64>()
        / 2.0
}

/// Triangulates the region inside `outer` and outside every ring of `holes`.
/// See the module documentation for the contract.
pub fn triangulate(
    outer: &[Point2<f64>],
    holes: &[Vec<Point2<f64>>],
) -> Result<Vec<[u32; 3]>, TriangulationError> {
    let rings: Vec<&[Point2<f64>]> = std::iter::once(outer)
        .chain(holes.iter().map(Vec::as_slice))
        .collect();
    let mut points = Vec::new();
    let mut ring_indices: Vec<Vec<usize>> = Vec::new();
    for (r, ring) in rings.iter().enumerate() {
        if ring.len() < 3 {
            return Err(TriangulationError::TooFewVertices {
                ring: r,
                len: ring.len(),
            });
        }
        let area = signed_area(ring);
        if area == 0.0 || !area.is_finite() {
            return Err(TriangulationError::ZeroArea { ring: r });
        }
        let start = points.len();
        points.extend_from_slice(ring);
        let mut idx: Vec<usize> = (start..start + ring.len()).collect();
        // Outer counter-clockwise, holes clockwise: the region is always on the left.
        if (r == 0) != (area > 0.0) {
            idx.reverse();
        }
        ring_indices.push(idx);
    }
    let mut polygon = ring_indices[0].clone();
    let mut pending: Vec<usize> = (1..ring_indices.len()).collect();
    // Rightmost holes first keeps bridges short and rarely blocked.
    pending.sort_by(|&a, &b| {
        let max_x = |r: usize| {
            ring_indices[r]
                .iter()
                .map(|&i| points[i].x)
                .fold(f64::MIN, f64::max)
        };
        max_x(b).total_cmp(&max_x(a)).then(a.cmp(&b))
    });
    for (k, &h) in pending.iter().enumerate() {
        let others: Vec<&Vec<usize>> = pending[k + 1..].iter().map(|&r| &ring_indices[r]).collect();
        polygon = bridge_hole(&points, &polygon, &ring_indices[h], &others)
            .ok_or(TriangulationError::NoBridge { hole: h - 1 })?;
    }
    ear_clip(&points, polygon)
}

/// Whether direction `d` from the apex of the corner `prev → apex → next` points into the
/// region on the left of the boundary (strictly inside the interior angle).
fn direction_inside(
    prev: &Point2<f64>,
    apex: &Point2<f64>,
    next: &Point2<f64>,
    d: &Point2<f64>,
) -> bool {
    let convex = cross(prev, apex, next) > 0.0;
    let left_of_in = cross(prev, apex, d) > 0.0; // left of the incoming edge's line
    let left_of_out = cross(apex, next, d) > 0.0; // left of the outgoing edge's line
    if convex {
        left_of_in && left_of_out
    } else {
        left_of_in || left_of_out
    }
}

/// Whether segments `p q` and `a b` meet anywhere (touching included).
fn segments_meet(p: &Point2<f64>, q: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> bool {
    let d1 = cross(p, q, a);
    let d2 = cross(p, q, b);
    let d3 = cross(a, b, p);
    let d4 = cross(a, b, q);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |s: &Point2<f64>, e: &Point2<f64>, x: &Point2<f64>, d: f64| {
        d == 0.0
            && x.x >= s.x.min(e.x)
            && x.x <= s.x.max(e.x)
            && x.y >= s.y.min(e.y)
            && x.y <= s.y.max(e.y)
    };
    on(p, q, a, d1) || on(p, q, b, d2) || on(a, b, p, d3) || on(a, b, q, d4)
}

/// Joins `hole` (clockwise) into `polygon` (counter-clockwise, possibly already bridged) by the
/// shortest valid bridge from the hole's rightmost vertex; `None` when no bridge exists.
fn bridge_hole(
    points: &[Point2<f64>],
    polygon: &[usize],
    hole: &[usize],
    others: &[&Vec<usize>],
) -> Option<Vec<usize>> {
    let m_pos = (0..hole.len())
        .max_by(|&a, &b| {
            let (pa, pb) = (points[hole[a]], points[hole[b]]);
            pa.x.total_cmp(&pb.x).then(pa.y.total_cmp(&pb.y))
        })
        .expect("rings have at least 3 vertices");
    let m = points[hole[m_pos]];
    let hole_prev = points[hole[(m_pos + hole.len() - 1) % hole.len()]];
    let hole_next = points[hole[(m_pos + 1) % hole.len()]];
    let n = polygon.len();
    let mut best: Option<(f64, usize)> = None;
    for pos in 0..n {
        let p = points[polygon[pos]];
        if p == m {
            continue;
        }
        let dist = (p - m).norm_squared();
        if best.is_some_and(|(d, _)| d <= dist) {
            continue;
        }
        let prev = points[polygon[(pos + n - 1) % n]];
        let next = points[polygon[(pos + 1) % n]];
        if !direction_inside(&prev, &p, &next, &m)
            || !direction_inside(&hole_prev, &m, &hole_next, &p)
        {
            continue;
        }
        let blocked_by = |ring: &[usize]| {
            (0..ring.len()).any(|i| {
                let (a, b) = (points[ring[i]], points[ring[(i + 1) % ring.len()]]);
                // Edges incident to the bridge's own endpoints only touch it there.
                let incident = a == p || b == p || a == m || b == m;
                !incident && segments_meet(&m, &p, &a, &b)
            })
        };
        if blocked_by(polygon) || blocked_by(hole) || others.iter().any(|r| blocked_by(r)) {
            continue;
        }
        best = Some((dist, pos));
    }
    let (_, pos) = best?;
    let mut out = Vec::with_capacity(n + hole.len() + 2);
    out.extend_from_slice(&polygon[..=pos]);
    out.extend((0..=hole.len()).map(|k| hole[(m_pos + k) % hole.len()]));
    out.extend_from_slice(&polygon[pos..]);
    Some(out)
}

/// Ear clipping of a weakly simple counter-clockwise polygon given as indices into `points`.
fn ear_clip(
    points: &[Point2<f64>],
    mut polygon: Vec<usize>,
) -> Result<Vec<[u32; 3]>, TriangulationError> {
    let mut triangles = Vec::with_capacity(polygon.len().saturating_sub(2));
    let mut start = 0;
    while polygon.len() > 3 {
        let n = polygon.len();
        let ear = (0..n)
            .map(|k| (start + k) % n)
            .find(|&i| is_ear(points, &polygon, i));
        let Some(i) = ear else {
            return Err(TriangulationError::NoEar { remaining: n });
        };
        let (a, b, c) = (polygon[(i + n - 1) % n], polygon[i], polygon[(i + 1) % n]);
        triangles.push([a as u32, b as u32, c as u32]);
        polygon.remove(i);
        // Resume next to the clipped vertex: keeps the fan local and the result stable.
        start = if i == 0 { 0 } else { i - 1 };
    }
    let (a, b, c) = (polygon[0], polygon[1], polygon[2]);
    if cross(&points[a], &points[b], &points[c]) <= 0.0 {
        return Err(TriangulationError::NoEar { remaining: 3 });
    }
    triangles.push([a as u32, b as u32, c as u32]);
    Ok(triangles)
}

/// Vertex `i` is an ear when its corner is strictly convex and no other polygon vertex (other
/// than copies of the corner points, which bridges create) lies in or on its triangle.
fn is_ear(points: &[Point2<f64>], polygon: &[usize], i: usize) -> bool {
    let n = polygon.len();
    let (a, b, c) = (
        points[polygon[(i + n - 1) % n]],
        points[polygon[i]],
        points[polygon[(i + 1) % n]],
    );
    if cross(&a, &b, &c) <= 0.0 {
        return false;
    }
    polygon.iter().all(|&j| {
        let p = points[j];
        if p == a || p == b || p == c {
            return true;
        }
        !(cross(&a, &b, &p) >= 0.0 && cross(&b, &c, &p) >= 0.0 && cross(&c, &a, &p) >= 0.0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: f64, y0: f64, s: f64) -> Vec<Point2<f64>> {
        vec![
            Point2::new(x0, y0),
            Point2::new(x0 + s, y0),
            Point2::new(x0 + s, y0 + s),
            Point2::new(x0, y0 + s),
        ]
    }

    fn total_area(points: &[Point2<f64>], tris: &[[u32; 3]]) -> f64 {
        tris.iter()
            .map(|t| {
                cross(
                    &points[t[0] as usize],
                    &points[t[1] as usize],
                    &points[t[2] as usize],
                ) / 2.0
            })
            .sum()
    }

    #[test]
    fn square_with_two_holes_covers_exact_area_with_positive_triangles() {
        let outer = square(0.0, 0.0, 1.0);
        let holes = vec![square(0.1, 0.1, 0.3), square(0.6, 0.5, 0.2)];
        let tris = triangulate(&outer, &holes).unwrap();
        let all: Vec<_> = outer
            .iter()
            .chain(holes.iter().flatten())
            .copied()
            .collect();
        // n + 2h - 2 triangles for n vertices and h holes.
        assert_eq!(tris.len(), 12 + 2 * 2 - 2);
        assert!((total_area(&all, &tris) - (1.0 - 0.09 - 0.04)).abs() < 1e-12);
        for t in &tris {
            assert!(
                cross(
                    &all[t[0] as usize],
                    &all[t[1] as usize],
                    &all[t[2] as usize]
                ) > 0.0
            );
        }
    }

    /// Seeded pseudo-random star-shaped outlines (radius 0.6–1.0) with up to four rotated
    /// polygonal holes in fixed cells: the triangles are all counter-clockwise, use each ring
    /// edge once, and cover exactly the outline's area minus the holes'.
    #[test]
    fn random_star_polygons_with_holes_are_covered_exactly() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut rnd = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..200 {
            // n ≥ 8 keeps every edge farther than 0.45 from the centre, clear of the holes.
            let n = 8 + (rnd() * 40.0) as usize;
            let outer: Vec<_> = (0..n)
                .map(|k| {
                    let a = 2.0 * std::f64::consts::PI * (k as f64 + 0.8 * rnd()) / n as f64;
                    let r = 0.6 + 0.4 * rnd();
                    Point2::new(r * a.cos(), r * a.sin())
                })
                .collect();
            let mut holes = Vec::new();
            for (cx, cy) in [(0.2, 0.2), (-0.2, 0.2), (-0.2, -0.2), (0.2, -0.2)] {
                if rnd() < 0.3 {
                    continue;
                }
                let m = 3 + (rnd() * 6.0) as usize;
                let (size, phase) = (0.03 + 0.1 * rnd(), rnd());
                holes.push(
                    (0..m)
                        .map(|k| {
                            let a = 2.0 * std::f64::consts::PI * (k as f64 + phase) / m as f64;
                            Point2::new(cx + size * a.cos(), cy + size * a.sin())
                        })
                        .collect::<Vec<_>>(),
                );
            }
            let tris = triangulate(&outer, &holes).unwrap_or_else(|e| panic!("case {case}: {e}"));
            let all: Vec<_> = outer
                .iter()
                .chain(holes.iter().flatten())
                .copied()
                .collect();
            let expected =
                signed_area(&outer).abs() - holes.iter().map(|h| signed_area(h).abs()).sum::<f64>();
            assert!(
                (total_area(&all, &tris) - expected).abs() < 1e-12,
                "case {case}"
            );
            assert_eq!(tris.len(), all.len() + 2 * holes.len() - 2, "case {case}");
            for t in &tris {
                assert!(
                    cross(
                        &all[t[0] as usize],
                        &all[t[1] as usize],
                        &all[t[2] as usize]
                    ) > 0.0,
                    "case {case}"
                );
            }
        }
    }

    #[test]
    fn clockwise_input_is_accepted() {
        let mut outer = square(0.0, 0.0, 2.0);
        outer.reverse();
        let tris = triangulate(&outer, &[]).unwrap();
        assert!((total_area(&outer, &tris) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn hole_outside_the_outline_has_no_bridge() {
        let outer = square(0.0, 0.0, 1.0);
        // A "hole" that surrounds the outline cannot be bridged from inside.
        let holes = vec![square(-1.0, -1.0, 3.0)];
        assert!(triangulate(&outer, &holes).is_err());
    }

    #[test]
    fn degenerate_rings_are_refused() {
        let line = vec![
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(2.0, 0.0),
        ];
        assert_eq!(
            triangulate(&line, &[]),
            Err(TriangulationError::ZeroArea { ring: 0 })
        );
        assert_eq!(
            triangulate(&line[..2], &[]),
            Err(TriangulationError::TooFewVertices { ring: 0, len: 2 })
        );
    }
}
