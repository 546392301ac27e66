//! Fitting a description's arm into the link shapes the collision model holds
//! ([`pregrasp_robot::MAX_LINK_SHAPES`]).
//!
//! An arm with at most that many link shapes is left as it is. One with more (a description
//! with covers, brackets and cameras fixed to its links, each with a `<collision>`) has shapes
//! that move with the same frame merged, two at a time, until it fits: each time the two
//! whose merged bounding box grows least over their own boxes' volumes (so a small shape
//! inside or beside a big one goes first; ties: the lowest indices). A merged shape keeps the
//! place of the first, takes the union of both pieces (the exact tier is unchanged: the
//! collision check still tests every piece) and their bounding box as its primitive. A pair of
//! merged shapes is checked for self-collision when any pair of their members was (the
//! members of one shape move together, so no pair between them is needed). An arm has 7
//! frames, so it always fits; one that does not is an error naming the link left over.

use nalgebra::{Point3, Vector3};

/// A link shape before it is made `'static`: the links it stands for, its frame, its pieces
/// in that frame and their bounding box.
#[derive(Clone, Debug)]
pub(crate) struct Draft {
    /// The link names, in the order merged.
    pub links: Vec<String>,
    /// The frame (0..=6) it moves with.
    pub frame: usize,
    /// Vertices of each piece in the frame.
    pub pieces: Vec<Vec<Point3<f64>>>,
    lo: Vector3<f64>,
    hi: Vector3<f64>,
}

impl Draft {
    /// The shape of link `name` in `frame`; `None` when its pieces have no (finite) vertex.
    pub fn new(name: &str, frame: usize, pieces: Vec<Vec<Point3<f64>>>) -> Option<Draft> {
        let mut lo = Vector3::repeat(f64::INFINITY);
        let mut hi = Vector3::repeat(f64::NEG_INFINITY);
        for v in pieces.iter().flatten() {
            lo = lo.inf(&v.coords);
            hi = hi.sup(&v.coords);
        }
        lo.iter().all(|c| c.is_finite()).then(|| Draft {
            links: vec![name.to_string()],
            frame,
            pieces,
            lo,
            hi,
        })
    }

    /// The shape's name: its link's, or the first links' joined by `+` with how many more.
    pub fn name(&self) -> String {
        match self.links.as_slice() {
            [a, b, rest @ ..] if rest.len() > 1 => format!("{a}+{b}+{} more", rest.len()),
            few => few.join("+"),
        }
    }
}

/// Shapes and their self-collision pairs (indices into them, ascending).
pub(crate) type Fitted = (Vec<Draft>, Vec<(usize, usize)>);

fn volume(lo: &Vector3<f64>, hi: &Vector3<f64>) -> f64 {
    (hi - lo).product()
}

/// `drafts` and their self-collision `pairs` merged down to at most `max` shapes (see the
/// module documentation): the shapes, and the pairs as indices into them (ascending).
/// `Err(link)`: the shapes do not fit even merged per frame; `link` is the last shape's.
pub(crate) fn fit(
    mut drafts: Vec<Draft>,
    pairs: &[(usize, usize)],
    max: usize,
) -> Result<Fitted, String> {
    // `owner[k]`: the shape original shape `k` is now part of.
    let mut owner: Vec<usize> = (0..drafts.len()).collect();
    let mut alive: Vec<bool> = vec![true; drafts.len()];
    let mut count = drafts.len();
    while count > max {
        let mut best: Option<(f64, usize, usize)> = None;
        for i in (0..drafts.len()).filter(|&i| alive[i]) {
            for j in (i + 1..drafts.len()).filter(|&j| alive[j]) {
                let (a, b) = (&drafts[i], &drafts[j]);
                if a.frame != b.frame {
                    continue;
                }
                let merged = volume(&a.lo.inf(&b.lo), &a.hi.sup(&b.hi));
                let growth = merged - volume(&a.lo, &a.hi) - volume(&b.lo, &b.hi);
                if best.is_none_or(|(g, _, _)| growth < g) {
                    best = Some((growth, i, j));
                }
            }
        }
        let Some((_, i, j)) = best else {
            let last = drafts.iter().zip(&alive).rev().find(|(_, a)| **a);
            return Err(last.map(|(d, _)| d.name()).unwrap_or_default());
        };
        let taken = std::mem::take(&mut drafts[j].pieces);
        let links = std::mem::take(&mut drafts[j].links);
        let (lo, hi) = (drafts[j].lo, drafts[j].hi);
        let into = &mut drafts[i];
        into.pieces.extend(taken);
        into.links.extend(links);
        into.lo = into.lo.inf(&lo);
        into.hi = into.hi.sup(&hi);
        alive[j] = false;
        owner.iter_mut().filter(|o| **o == j).for_each(|o| *o = i);
        count -= 1;
    }
    // Renumber the shapes left, in order.
    let mut index = vec![0; drafts.len()];
    let mut next = 0;
    for (k, a) in alive.iter().enumerate() {
        index[k] = next;
        next += usize::from(*a);
    }
    let mut mapped: Vec<(usize, usize)> = pairs
        .iter()
        .map(|&(a, b)| (index[owner[a]], index[owner[b]]))
        .filter(|(a, b)| a != b)
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    mapped.sort_unstable();
    mapped.dedup();
    let kept = drafts
        .into_iter()
        .zip(alive)
        .filter_map(|(d, a)| a.then_some(d))
        .collect();
    Ok((kept, mapped))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(name: &str, frame: usize, at: [f64; 3], side: f64) -> Draft {
        let h = side / 2.0;
        let corners = (0..8)
            .map(|k| {
                let s = |b: usize| if k & b == 0 { -h } else { h };
                Point3::new(at[0] + s(1), at[1] + s(2), at[2] + s(4))
            })
            .collect();
        Draft::new(name, frame, vec![corners]).unwrap()
    }

    #[test]
    fn an_arm_that_fits_is_left_as_it_is() {
        let drafts = vec![cube("a", 0, [0.0; 3], 1.0), cube("b", 0, [0.0; 3], 0.1)];
        let (kept, pairs) = fit(drafts, &[(0, 1)], 2).unwrap();
        assert_eq!(kept.len(), 2);
        assert_eq!(pairs, [(0, 1)]);
    }

    #[test]
    fn the_small_shape_goes_into_the_big_one_of_its_frame_and_pairs_follow() {
        // a, c: frame 1 (c small, inside a); b: frame 2; d: frame 2, far from b.
        let drafts = vec![
            cube("a", 1, [0.0; 3], 1.0),
            cube("b", 2, [5.0, 0.0, 0.0], 1.0),
            cube("c", 1, [0.2, 0.0, 0.0], 0.1),
            cube("d", 2, [9.0, 0.0, 0.0], 0.1),
        ];
        // c–d and b–c checked; a–d not: merged, a+c – d is checked.
        let (kept, pairs) = fit(drafts, &[(1, 2), (2, 3)], 3).unwrap();
        let names: Vec<String> = kept.iter().map(Draft::name).collect();
        assert_eq!(names, ["a+c", "b", "d"]);
        assert_eq!(pairs, [(0, 1), (0, 2)]);
        assert_eq!(kept[0].pieces.len(), 2);
    }

    #[test]
    fn shapes_of_different_frames_are_never_merged() {
        let drafts = vec![cube("a", 0, [0.0; 3], 1.0), cube("b", 1, [0.0; 3], 1.0)];
        assert_eq!(fit(drafts, &[], 1).unwrap_err(), "b");
    }
}
