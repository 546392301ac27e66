//! A cache entry checked against the description it claims to be of.
//!
//! The key names the inputs, but an entry is a file anyone can edit, truncate or replace with
//! another well-formed one: pieces cut to a point would make the arm pass through the part,
//! emptied pieces would leave it without collision geometry. Before an entry is used,
//! [`check_entry`] compares it with what the description gives cheaply, without the
//! expensive part (the self-collision sampling):
//!
//! * the robot name, and per link with `<collision>` elements its name and element indices,
//!   in file order: the same links and counts the derivation would make;
//! * every piece has at least one point, all finite;
//! * every piece's bounding box holds its element's geometry (the mesh's vertices as read
//!   and placed, or the primitive's polytope) and exceeds it by no more than the padding of
//!   a flat element ([`FLAT_PAD`], [`FLAT_PAD_RELATIVE`]): a piece is the hull of those
//!   points, whose box is theirs;
//! * the pairs index existing links (checked when the entry is read, `cache.rs`).
//!
//! An entry that fails is reported with the reason and derived again
//! ([`super::CacheOutcome::Replaced`]).

use nalgebra::Point3;

use super::element::{element_points, Element};
use super::pieces::{FLAT_PAD, FLAT_PAD_RELATIVE};
use super::types::UrdfGeometry;
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
        let (source, _) = element_points(model, e).map_err(|err| err.to_string())?;
        let (Some(want), Some(have)) = (bounds(&source), bounds(piece)) else {
            return Err(format!("link `{}`: an empty or non-finite piece", e.link));
        };
        let slack = FLAT_PAD + FLAT_PAD_RELATIVE * (want.1 - want.0).norm() + 1e-9;
        let holds = (0..3).all(|i| {
            have.0[i] <= want.0[i] + 1e-9
                && have.1[i] >= want.1[i] - 1e-9
                && have.0[i] >= want.0[i] - slack
                && have.1[i] <= want.1[i] + slack
        });
        if !holds {
            return Err(format!(
                "link `{}`: piece of <collision> {} does not match its geometry",
                e.link, e.index
            ));
        }
    }
    Ok(())
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
