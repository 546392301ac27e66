//! GJK as a yes/no question: do two convex shapes come within a distance of each other?
//!
//! parry's `closest_points_support_map_support_map` with a prediction distance `d` runs GJK
//! (Gilbert–Johnson–Keerthi) on the Minkowski difference `A − B`: each step it keeps the
//! simplex of support points nearest the origin, whose distance `|v|` from the origin is an
//! upper bound of the shapes' distance, and asks for the support point `w` along `−v`, whose
//! plane gives the lower bound `−v̂·w`. It reports the shapes apart as soon as that lower
//! bound exceeds `d`; otherwise it goes on until the bounds meet (the closest points) or the
//! simplex holds the origin (a tetrahedron around it: intersecting).
//!
//! Asked only whether the distance is at most `d`, the run may stop as soon as the upper bound
//! is: `|v| ≤ d`. Every other step is parry's, in parry's order, so where parry reports the
//! shapes apart this does too, with the same axis, and where it reports closest points or an
//! intersection this says *within* — only sooner. Touching and penetrating pairs are where that
//! counts: GJK then needs its last steps (and the tetrahedron) to find out what the first
//! simplex inside the margin already showed.

use nalgebra::{Isometry3, Unit, Vector3};
use parry3d_f64::query::gjk::{self, CSOPoint, VoronoiSimplex};
use parry3d_f64::shape::SupportMap;

/// GJK's answer to "within `dist`?": `Ok(())` within (touching and overlapping included),
/// `Err(axis)` apart, `axis` (in the first shape's frame) the direction of `B − A` along which
/// the gap exceeds `dist`.
pub type Within = Result<(), Unit<Vector3<f64>>>;

/// Whether `g1` and `g2` (the second at `pos12` in the first's frame) come within `dist` of
/// each other: parry's GJK with a prediction distance (`closest_points` with exact distances,
/// started from `start` or else from `−pos12`'s translation), stopping as soon as its upper
/// bound is within `dist`. See the module doc for why the answers are parry's.
pub fn within(
    pos12: &Isometry3<f64>,
    g1: &(impl SupportMap + ?Sized),
    g2: &(impl SupportMap + ?Sized),
    dist: f64,
    start: Option<Vector3<f64>>,
) -> Within {
    let dir = start.unwrap_or(-pos12.translation.vector);
    let dir = Unit::try_new(dir, f64::EPSILON).unwrap_or_else(Vector3::x_axis);
    run(
        pos12,
        g1,
        g2,
        dist,
        CSOPoint::from_shapes(pos12, g1, g2, &dir),
    )
    .0
}

/// How far from `dist` a warm-started run's bounds must put the distance for its answer to be
/// taken (m): beyond GJK's own tolerance (`√ε_tol` of the distance, a few 1e-9 m here), so
/// that [`within`] from its usual start could not answer otherwise.
pub const GUARD: f64 = 1e-7;

/// [`within`] started from `first`, a support point of `A − B` (along the axis that last
/// separated the pair, say): `None` unless its bounds put the distance farther than [`GUARD`]
/// from `dist` — then [`within`] from its usual start gives the same answer (its bounds
/// enclose the same distance, and it only answers against them within its tolerance), so where
/// a run starts, which depends on what was asked before, never shows in an answer.
pub fn within_from(
    pos12: &Isometry3<f64>,
    g1: &(impl SupportMap + ?Sized),
    g2: &(impl SupportMap + ?Sized),
    dist: f64,
    first: CSOPoint,
) -> Option<Within> {
    match run(pos12, g1, g2, dist, first) {
        (Ok(()), upper) if upper <= dist - GUARD => Some(Ok(())),
        (Err(axis), lower) if lower > dist + GUARD => Some(Err(axis)),
        _ => None,
    }
}

/// GJK from the simplex `{first}`; the answer with the bound that decided it: the upper bound
/// where within (`∞` where the bounds agreed or it made no progress, `0` with the origin in the
/// simplex), the lower bound where apart (`−∞` where it gave up).
fn run(
    pos12: &Isometry3<f64>,
    g1: &(impl SupportMap + ?Sized),
    g2: &(impl SupportMap + ?Sized),
    dist: f64,
    first: CSOPoint,
) -> (Within, f64) {
    let eps_tol = gjk::eps_tol();
    let eps_rel = eps_tol.sqrt();
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(first);
    let mut proj = simplex.project_origin_and_reduce();
    let mut max_bound = f64::MAX;
    for _ in 0..100 {
        let old_max_bound = max_bound;
        let Some((dir, norm)) = Unit::try_new_and_get(-proj.coords, eps_tol) else {
            return (Ok(()), 0.0); // the origin is on the simplex
        };
        max_bound = norm;
        // The one step parry does not take: the simplex lies in `A − B`, so the shapes are
        // no farther apart than its distance from the origin.
        if max_bound <= dist {
            return (Ok(()), max_bound);
        }
        if max_bound >= old_max_bound {
            return (Ok(()), f64::INFINITY); // no progress: parry reports its closest points
        }
        let w = CSOPoint::from_shapes(pos12, g1, g2, &dir);
        let min_bound = -dir.dot(&w.point.coords);
        if min_bound > dist {
            return (Err(dir), min_bound);
        }
        if max_bound - min_bound <= eps_rel * max_bound || !simplex.add_point(w) {
            // The bounds agree: closest points within `dist`.
            return (Ok(()), f64::INFINITY);
        }
        proj = simplex.project_origin_and_reduce();
        if simplex.dimension() == 3 {
            // A tetrahedron: the origin inside (parry: an intersection), or closest points.
            let inside = min_bound < eps_tol;
            return (Ok(()), if inside { 0.0 } else { f64::INFINITY });
        }
    }
    // parry gives up after as many steps and reports the shapes apart along `x`.
    (Err(Vector3::x_axis()), f64::NEG_INFINITY)
}

/// How far GJK's bounds may stay apart when [`clearance`] stops: it ends once its lower bound
/// is within this fraction of its upper one (a clearance of 80 % of the distance serves as well
/// as the distance for skipping tests, and costs fewer steps).
pub const CLEARANCE_SLACK: f64 = 0.2;

/// Most GJK steps [`clearance`] takes.
const CLEARANCE_STEPS: usize = 32;

/// A lower bound of the distance between `g1` and `g2` (the second at `pos12` in the first's
/// frame), the unit axis that gives it (first shape's frame) and an upper bound, by GJK on
/// `A − B` started along `dir`. Every support plane bounds the distance from below: along a
/// unit axis `u`, `A − B` lies in the half-space `u · x ≤ u · w` (`w` its support point along
/// `u`), so no point of it is nearer the origin than `−u · w` — the lower bound returned is the
/// best such plane GJK met, whatever its tolerances. GJK's simplex bounds the distance from
/// above, as does `upper` (a bound the caller knows, `∞` if none); the run stops once the
/// bounds are within [`CLEARANCE_SLACK`] of each other, when the simplex reaches the origin,
/// or when it makes no progress. The lower bound is `≤ 0` where the shapes touch (or no plane
/// separating them was found).
pub fn clearance(
    pos12: &Isometry3<f64>,
    g1: &(impl SupportMap + ?Sized),
    g2: &(impl SupportMap + ?Sized),
    dir: &Unit<Vector3<f64>>,
    mut upper: f64,
) -> (f64, Unit<Vector3<f64>>, f64) {
    let first = CSOPoint::from_shapes(pos12, g1, g2, dir);
    let mut best = (-dir.dot(&first.point.coords), *dir);
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(first);
    for _ in 0..CLEARANCE_STEPS {
        let proj = simplex.project_origin_and_reduce();
        if simplex.dimension() == 3 {
            break; // the origin in a tetrahedron of A − B: the shapes intersect
        }
        let Some((u, norm)) = Unit::try_new_and_get(-proj.coords, gjk::eps_tol()) else {
            break; // the origin on the simplex: touching
        };
        upper = upper.min(norm);
        if best.0 >= (1.0 - CLEARANCE_SLACK) * upper {
            break;
        }
        let w = CSOPoint::from_shapes(pos12, g1, g2, &u);
        let lower = -u.dot(&w.point.coords);
        if lower > best.0 {
            best = (lower, u);
        }
        if !simplex.add_point(w) {
            break;
        }
    }
    (best.0, best.1, upper)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Point3, Translation3, UnitQuaternion};
    use parry3d_f64::query::details::closest_points_support_map_support_map_with_params;
    use parry3d_f64::query::gjk::GJKResult;
    use parry3d_f64::shape::{ConvexPolyhedron, Cuboid, Segment};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// parry's answer to the same question, run to its end.
    fn parry_within(
        pos12: &Isometry3<f64>,
        g1: &dyn SupportMap,
        g2: &dyn SupportMap,
        dist: f64,
    ) -> Within {
        match closest_points_support_map_support_map_with_params(
            pos12,
            g1,
            g2,
            dist,
            &mut VoronoiSimplex::new(),
            None,
        ) {
            GJKResult::NoIntersection(axis) => Err(axis),
            _ => Ok(()),
        }
    }

    fn random_hull(rng: &mut ChaCha8Rng) -> ConvexPolyhedron {
        let scale = rng.random_range(0.02..0.2);
        let pts: Vec<Point3<f64>> = (0..rng.random_range(4..40))
            .map(|_| Point3::from(Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)) * scale))
            .collect();
        ConvexPolyhedron::from_convex_hull(&pts).expect("a hull of random points")
    }

    fn random_pose(rng: &mut ChaCha8Rng, spread: f64) -> Isometry3<f64> {
        let t = Vector3::from_fn(|_, _| rng.random_range(-spread..spread));
        let axis = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        Isometry3::from_parts(
            Translation3::from(t),
            UnitQuaternion::from_scaled_axis(axis * 3.0),
        )
    }

    /// Same answers (and the same separating axes) as parry run to its end, over random hulls,
    /// segments and boxes placed apart, touching and overlapping, at several distances; the
    /// same answers again from a random start where that run answers at all; and the answers
    /// agree with the distance itself away from GJK's tolerance.
    #[test]
    fn answers_as_parry_run_to_its_end_and_as_the_distance() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let (mut within_n, mut apart_n, mut undecided) = (0, 0, 0);
        for _ in 0..4000 {
            let h1 = random_hull(&mut rng);
            let seg = Segment::new(
                Point3::from(Vector3::from_fn(|_, _| rng.random_range(-0.2..0.2))),
                Point3::from(Vector3::from_fn(|_, _| rng.random_range(-0.2..0.2))),
            );
            let cub = Cuboid::new(Vector3::from_fn(|_, _| rng.random_range(0.01..0.2)));
            let h2 = random_hull(&mut rng);
            let pos12 = random_pose(&mut rng, 0.2);
            let dist = [0.0, 0.001, 0.005, 0.03][rng.random_range(0..4)];
            let pairs: [(&dyn SupportMap, &dyn SupportMap); 3] =
                [(&h1, &h2), (&seg, &cub), (&h1, &cub)];
            for (g1, g2) in pairs {
                let ours = within(&pos12, g1, g2, dist, None);
                assert_eq!(ours, parry_within(&pos12, g1, g2, dist));
                // Started anywhere, GJK answers as from its usual start, or not at all.
                let dir = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
                let first = CSOPoint::from_shapes(&pos12, g1, g2, &Unit::new_normalize(dir));
                match within_from(&pos12, g1, g2, dist, first) {
                    Some(Ok(())) => assert!(ours.is_ok()),
                    Some(Err(_)) => assert!(ours.is_err()),
                    None if dist > 0.0 => undecided += 1,
                    None => {}
                }
                let d =
                    parry3d_f64::query::details::distance_support_map_support_map(&pos12, g1, g2);
                if d > dist + 1e-6 {
                    assert!(ours.is_err(), "distance {d} > {dist} but within");
                    apart_n += 1;
                } else if d < dist - 1e-6 {
                    assert!(ours.is_ok(), "distance {d} < {dist} but apart");
                    within_n += 1;
                }
            }
        }
        // Both answers were asked for often; a warm start rarely leaves the answer open.
        assert!(
            within_n > 2000 && apart_n > 2000,
            "{within_n} within, {apart_n} apart"
        );
        // (Touching at `dist = 0` is never sure: the guard asks for a gap below zero.)
        assert!(undecided < 90, "{undecided} of ~9000 warm starts undecided");
    }
}
