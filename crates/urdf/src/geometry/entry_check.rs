//! A cache entry checked against the description it claims to be of.
//!
//! The key names the inputs, but an entry is a file anyone can edit, truncate or replace with
//! another well-formed one: pieces cut to a point would make the arm pass through the part,
//! emptied pieces would leave it without collision geometry. Before an entry is used,
//! [`check_entry`] compares it with what the description gives cheaply, without the
//! expensive parts of a derivation (reading the meshes into hulls, sampling self-collision):
//!
//! * the robot name, and per link with `<collision>` elements its name and element indices,
//!   in file order: the same links and counts the derivation would make;
//! * every piece is finite and within [`MAX_LINK_EXTENT`](super::MAX_LINK_EXTENT) of its
//!   link frame;
//! * a primitive's piece is its polytope: its bounding box is the element's (the polytope is
//!   recomputed, a few points);
//! * a mesh's piece is a solid: four of its points span a tetrahedron whose edges, face
//!   height and apex height are all at least half of [`FLAT_PAD`] (a hull is made solid by
//!   that padding when its mesh is flat, so every derived mesh piece passes);
//! * the pairs index existing links (checked when the entry is read, `cache.rs`).
//!
//! An entry that fails is reported with the reason and derived again
//! ([`super::CacheOutcome::Replaced`]).

use nalgebra::Point3;

use super::element::{element_points, Element};
use super::pieces::{FLAT_PAD, FLAT_PAD_RELATIVE};
use super::types::UrdfGeometry;
use super::values::check_extent;
use crate::model::UrdfModel;

/// Why `g` is not the geometry of `model`'s `elements`, if it is not (see the module
/// documentation).
pub(crate) fn check_entry(
    model: &UrdfModel,
    elements: &[Element],
    g: &UrdfGeometry,
) -> Result<(), String> {
    if g.robot != model.name() {
        return Err(format!("entry of robot `{}`", g.robot));
    }
    let mut expected: Vec<(&str, Vec<usize>)> = Vec::new();
    for e in elements {
        match expected.last_mut() {
            Some((link, idx)) if *link == e.link => idx.push(e.index),
            _ => expected.push((&e.link, vec![e.index])),
        }
    }
    let found: Vec<(&str, Vec<usize>)> = g
        .links
        .iter()
        .map(|l| (l.link.as_str(), l.elements.clone()))
        .collect();
    if found != expected {
        return Err("its links or element counts differ from the description's".to_string());
    }
    let pieces = g.links.iter().flat_map(|l| l.pieces.iter());
    for (e, piece) in elements.iter().zip(pieces) {
        let wrong = || {
            format!(
                "link `{}`: piece of <collision> {} does not match its geometry",
                e.link, e.index
            )
        };
        check_extent(model.source(), &e.link, "a cached piece", piece)
            .map_err(|err| err.to_string())?;
        if e.mesh.is_some() {
            if !solid(piece) {
                return Err(wrong());
            }
            continue;
        }
        let (source, _) = element_points(model, e).map_err(|err| err.to_string())?;
        let (Some(want), Some(have)) = (bounds(&source), bounds(piece)) else {
            return Err(wrong());
        };
        let slack = FLAT_PAD + FLAT_PAD_RELATIVE * (want.1 - want.0).norm() + 1e-9;
        let holds = (0..3).all(|i| {
            have.0[i] <= want.0[i] + 1e-9
                && have.1[i] >= want.1[i] - 1e-9
                && have.0[i] >= want.0[i] - slack
                && have.1[i] <= want.1[i] + slack
        });
        if !holds {
            return Err(wrong());
        }
    }
    Ok(())
}

/// Whether `points` span a solid (see the module documentation): from the first point, the
/// farthest point, the farthest from their line and the farthest from their plane.
fn solid(points: &[Point3<f64>]) -> bool {
    let min = 0.5 * FLAT_PAD;
    let Some(&a) = points.first() else {
        return false;
    };
    let farthest = |d: &dyn Fn(&Point3<f64>) -> f64| {
        points
            .iter()
            .map(|p| (d(p), *p))
            .fold((0.0, a), |best, x| if x.0 > best.0 { x } else { best })
    };
    let (ab, b) = farthest(&|p| (p - a).norm());
    if ab < min {
        return false;
    }
    let u = (b - a) / ab;
    let (h, c) = farthest(&|p| (p - a).cross(&u).norm());
    if h < min {
        return false;
    }
    let n = (c - a).cross(&u).normalize();
    let (apex, _) = farthest(&|p| (p - a).dot(&n).abs());
    apex >= min
}

/// The bounding box of `points`; `None` when empty or a coordinate is not finite.
fn bounds(points: &[Point3<f64>]) -> Option<(Point3<f64>, Point3<f64>)> {
    let first = *points.first()?;
    let mut b = (first, first);
    for p in points {
        if !p.coords.iter().all(|c| c.is_finite()) {
            return None;
        }
        b = (b.0.inf(p), b.1.sup(p));
    }
    Some(b)
}
