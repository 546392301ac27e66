//! What a visit does with each pair: stop at the first contact ([`FirstContact`]) or keep the
//! smallest clearance ([`MinDistance`]); pairs named by a compact code for the doubts a swept
//! check hands down.

use std::ops::ControlFlow;

use nalgebra::{Isometry3, Vector3};
use pregrasp_motion::Doubts;

use super::Grows;
use crate::object::ObjectGeometry;
use crate::shape::{
    pair_distance, pair_intersects, pair_may_intersect, plane_distance, Bounded, Placed,
};
use crate::tight::{self, Part};

use super::Id;

/// What to do with each candidate pair: stop at the first contact, or track the minimum.
pub(crate) trait Sink {
    /// The clearance within which a pair (`ids`) may matter, for the culls by spheres and boxes:
    /// the same for every pair of bodies of the same two shape groups, and for a group against
    /// any static body (they do not move), so a loop over a group's pairs works it out once. A
    /// margin worked out earlier in a visit may be wider than asking again would give (a sink
    /// that narrows it as it goes), never narrower.
    fn cull_margin(&self, ids: (Id, Id)) -> f64;
    /// Whether bodies in the spheres `s1`, `s2` cannot matter at the cull margin `m`.
    #[inline]
    fn skip_spheres_at(&self, s1: &Bounded, s2: &Bounded, m: f64) -> bool {
        !s1.spheres_near(s2, m)
    }
    /// Whether a pair (`ids`) whose bounding spheres are `s1`, `s2` cannot matter.
    #[inline]
    fn skip_spheres(&self, s1: &Bounded, s2: &Bounded, ids: (Id, Id)) -> bool {
        self.skip_spheres_at(s1, s2, self.cull_margin(ids))
    }
    /// Whether a body (`ids.0`) in the sphere `s` cannot matter against the part's box (its
    /// mesh's bounding box in the object frame) at `pose`.
    fn skip_object_box(
        &self,
        _obj: &ObjectGeometry,
        _pose: &Isometry3<f64>,
        _s: &Bounded,
        _ids: (Id, Id),
    ) -> bool {
        false
    }
    /// Whether a group of bodies (`ids.0`) in the sphere `s` cannot matter against the support
    /// plane `z = height` at clearance `margin` (as [`plane`](Self::plane) would find for each).
    fn skip_plane(&self, _s: &Bounded, _height: f64, _margin: f64, _ids: (Id, Id)) -> bool {
        false
    }
    /// Whether a body in the sphere `s` cannot matter against the cuboid `half` at `pose` (a
    /// static obstacle) at the cull margin `m`.
    fn skip_cuboid_at(
        &self,
        _pose: &Isometry3<f64>,
        _half: &Vector3<f64>,
        _s: &Bounded,
        _m: f64,
    ) -> bool {
        false
    }
    /// Whether a group whose boxes are `sqrt(gap_sq)` apart cannot matter.
    fn skip_gap_sq(&self, gap_sq: f64) -> bool;
    /// Whether the arms are tested against the part before anything else (a swept check, whose
    /// answer does not name the pair, stops soonest where the part is the usual obstacle).
    fn part_first(&self) -> bool {
        false
    }
    /// Whether grasping grippers are tested against the support (a swept query leaves them
    /// to a test at every state: they work millimetres above it).
    fn grasp_support(&self) -> bool {
        true
    }
    /// A solid vs the support plane; `margin` is the clearance this pair must keep.
    fn plane(&mut self, s: Part, height: f64, margin: f64, ids: (Id, Id)) -> ControlFlow<()>;
    /// Two solids.
    fn pair(&mut self, s1: Part, s2: Part, ids: (Id, Id)) -> ControlFlow<()>;
    /// A solid vs the part at `pose`.
    fn object(
        &mut self,
        obj: &ObjectGeometry,
        pose: &Isometry3<f64>,
        s: Part,
        ids: (Id, Id),
    ) -> ControlFlow<()>;
}

/// Stops at the first pair within its clearance: the margin, grown for a swept query by
/// how far each of the pair's bodies may move ([`Grows`]).
pub(crate) struct FirstContact<'g> {
    pub margin: f64,
    /// Margin used to cull by bounding spheres and boxes: `margin` plus the largest growth of
    /// any pair.
    pub cull: f64,
    pub grow: Option<&'g Grows<'g>>,
    /// Collecting: every pair in contact goes here (the query goes on) until it is full.
    pub found: Option<Doubts>,
    /// A pair whose primitive comes within its clearance counts as a contact without its
    /// exact pieces being asked (see [`collecting`](Self::collecting)).
    pub by_primitives: bool,
    /// The primitives of a pair with exact pieces filter it loosely (cylinders as their
    /// enclosing capsules, [`pair_may_intersect`]): for pairs known to be near (a box's
    /// doubts), whose exact cylinder test would cost about what the pieces' does and let them
    /// through anyway.
    pub loose_filter: bool,
    /// The last pair found in contact (with `found`: the one that did not fit, if any).
    pub ids: Option<(Id, Id)>,
}

impl<'g> FirstContact<'g> {
    /// A plain query at `margin`.
    pub fn new(margin: f64) -> Self {
        FirstContact {
            margin,
            cull: margin,
            grow: None,
            found: None,
            by_primitives: false,
            loose_filter: false,
            ids: None,
        }
    }

    /// A swept query: every pair's clearance grows by the motion bounds of its two sides.
    pub fn swept(margin: f64, grow: &'g Grows<'g>) -> Self {
        FirstContact {
            cull: margin + grow.most_pair(),
            grow: Some(grow),
            ..Self::new(margin)
        }
    }

    /// Every pair in contact is collected (up to [`Doubts::CAPACITY`]) instead of stopping at
    /// the first; `by_primitives`: by their primitives alone. So a box asked about every pair
    /// names its doubts: they go to smaller boxes, which ask the pieces, and a box near many
    /// things fails for the price of its primitives.
    pub fn collecting(self, by_primitives: bool) -> Self {
        FirstContact {
            found: Some(Doubts::default()),
            by_primitives,
            ..self
        }
    }

    #[inline]
    fn hit(&mut self, hit: bool, ids: (Id, Id)) -> ControlFlow<()> {
        if !hit {
            return ControlFlow::Continue(());
        }
        if let Some(found) = &mut self.found {
            if pair_code(ids).is_some_and(|c| found.insert(c)) {
                return ControlFlow::Continue(());
            }
        }
        self.ids = Some(ids);
        ControlFlow::Break(())
    }

    /// What a collecting query found: the pairs in contact, or `None` when they did not fit.
    pub fn doubts(&self) -> Option<Doubts> {
        match self.ids {
            Some(_) => None,
            None => self.found,
        }
    }

    /// [`margin_of`](Self::margin_of) for two shapes in the spheres `sa`, `sb`, by their own
    /// levers where those are tighter ([`Grows::shapes_pair`]).
    #[inline]
    fn margin_of_shapes(&self, margin: f64, (a, b): (Id, Id), sa: &Bounded, sb: &Bounded) -> f64 {
        match self.grow {
            None => margin,
            Some(g) => margin + g.shapes_pair(a, b, sa, sb),
        }
    }

    /// The clearance pair `ids` must keep: `margin` plus both sides' growth.
    #[inline]
    fn margin_of(&self, margin: f64, (a, b): (Id, Id)) -> f64 {
        match self.grow {
            None => margin,
            Some(g) => margin + g.pair(a, b),
        }
    }
}

/// Per arm, the shapes the pairs `among` name (bit `k`: shape `k`).
pub(crate) fn shapes_among(among: &Doubts) -> [u64; 2] {
    let mut masks = [0u64; 2];
    for &code in among.as_slice() {
        for side in [code >> 16, code & 0xFFFF] {
            if let Id::Arm(i, k) = side_id(side) {
                masks[i] |= 1 << k;
            }
        }
    }
    masks
}

/// The pair [`pair_code`] gave `code`.
pub(super) fn pair_ids(code: u32) -> (Id, Id) {
    (side_id(code >> 16), side_id(code & 0xFFFF))
}

/// One side of a [`pair_code`] (its 16 bits).
fn side_id(c: u32) -> Id {
    let low = (c & 0x3FFF) as usize;
    match c >> 14 {
        0 | 1 => Id::Arm((c >> 14) as usize, low),
        2 => Id::Obstacle(low),
        _ if c == 0xFFFF => Id::Support,
        _ => Id::Object,
    }
}

/// A pair of bodies as one number (for [`Doubts`]): each side in 16 bits, an arm shape as
/// `arm << 14 | shape`, an obstacle as `2 << 14 | index`, the support and the part as the
/// two largest codes. `None` for whole groups (never reported) and indices too large to
/// code: a collecting query that finds such a pair in contact names none (all stay in doubt).
#[inline(always)]
pub(crate) fn pair_code((a, b): (Id, Id)) -> Option<u32> {
    const LOW: usize = (1 << 14) - 2;
    let side = |id: Id| -> Option<u32> {
        match id {
            Id::Arm(i, k) if i < 2 && k < LOW => Some(((i as u32) << 14) | k as u32),
            Id::Obstacle(o) if o < LOW => Some((2 << 14) | o as u32),
            Id::Support => Some(0xFFFF),
            Id::Object => Some(0xFFFE),
            _ => None,
        }
    };
    Some((side(a)? << 16) | side(b)?)
}

impl Sink for FirstContact<'_> {
    /// The pair's own clearance in a swept query (never more than [`cull`](Self::cull)), the
    /// widest of any pair otherwise.
    #[inline]
    fn cull_margin(&self, ids: (Id, Id)) -> f64 {
        match self.grow {
            None => self.cull,
            Some(_) => self.margin_of(self.margin, ids).min(self.cull),
        }
    }
    #[inline]
    fn skip_object_box(
        &self,
        obj: &ObjectGeometry,
        pose: &Isometry3<f64>,
        s: &Bounded,
        ids: (Id, Id),
    ) -> bool {
        !obj.sphere_near_box(pose, s, self.margin_of(self.margin, ids))
    }
    #[inline]
    fn skip_cuboid_at(
        &self,
        pose: &Isometry3<f64>,
        half: &Vector3<f64>,
        s: &Bounded,
        m: f64,
    ) -> bool {
        let reach = s.radius + m;
        s.centre_box_gap_sq(pose, half) > reach * reach
    }
    #[inline]
    fn skip_gap_sq(&self, gap_sq: f64) -> bool {
        gap_sq > self.cull * self.cull
    }
    /// The sphere holds its shapes grown by their slack, so its lowest point above the plane
    /// by more than the pair's clearance passes each shape's test in [`plane`](Sink::plane).
    #[inline]
    fn skip_plane(&self, s: &Bounded, height: f64, margin: f64, ids: (Id, Id)) -> bool {
        s.center.z - s.radius - height > self.margin_of(margin, ids)
    }
    #[inline]
    fn grasp_support(&self) -> bool {
        self.grow.is_none_or(|g| !g.grasp_support_apart)
    }
    #[inline]
    fn part_first(&self) -> bool {
        self.grow.is_some()
    }
    /// The primitive first, with the margin grown by the pieces' slack; the pieces only
    /// where that finds contact (every `FirstContact` test below has this shape).
    #[inline]
    fn plane(&mut self, s: Part, height: f64, margin: f64, ids: (Id, Id)) -> ControlFlow<()> {
        let bound = plane_distance(s.shape(), height);
        // The group's clearance first (no sphere cull came before); where that comes near, the
        // shape's own.
        if bound > self.margin_of(margin, ids) + s.slack() {
            return ControlFlow::Continue(());
        }
        let margin = self.margin_of_shapes(margin, ids, s.bounded, s.bounded);
        let near = bound <= margin + s.slack();
        let hit =
            near && (self.by_primitives || s.plane_distance(height).is_none_or(|d| d <= margin));
        self.hit(hit, ids)
    }
    #[inline]
    fn pair(&mut self, s1: Part, s2: Part, ids: (Id, Id)) -> ControlFlow<()> {
        let margin = self.margin_of_shapes(self.margin, ids, s1.bounded, s2.bounded);
        let plain = s1.tight().is_none() && s2.tight().is_none();
        let (a, b, grown) = (s1.shape(), s2.shape(), margin + s1.slack() + s2.slack());
        // Where the pieces decide, the primitives only filter them (see `by_primitives`). Two
        // boxes go to GJK, which remembers the axis that last kept them apart.
        let boxes = matches!((a, b), (Placed::Cuboid { .. }, Placed::Cuboid { .. }));
        let near = if boxes && plain {
            tight::within(&s1, &s2, grown)
        } else if plain || !self.loose_filter {
            pair_intersects(a, b, grown)
        } else {
            pair_may_intersect(a, b, grown)
        };
        let hit = near && (plain || self.by_primitives || tight::within(&s1, &s2, margin));
        self.hit(hit, ids)
    }
    #[inline]
    fn object(
        &mut self,
        obj: &ObjectGeometry,
        pose: &Isometry3<f64>,
        s: Part,
        ids: (Id, Id),
    ) -> ControlFlow<()> {
        let margin = self.margin_of(self.margin, ids);
        let near = obj.intersects(pose, s.bounded, margin + s.slack());
        let hit = near
            && (self.by_primitives
                || s.tight()
                    .is_none_or(|t| obj.pieces_intersect(pose, &t, margin)));
        self.hit(hit, ids)
    }
}

pub(super) struct MinDistance {
    pub(super) best: f64,
    pub(super) ids: Option<(Id, Id)>,
}

impl MinDistance {
    fn offer(&mut self, d: f64, ids: (Id, Id)) -> ControlFlow<()> {
        if d < self.best || self.ids.is_none() {
            self.best = d;
            self.ids = Some(ids);
        }
        ControlFlow::Continue(())
    }
}

impl Sink for MinDistance {
    /// The best distance so far (a culled pair cannot beat it).
    fn cull_margin(&self, _ids: (Id, Id)) -> f64 {
        self.best
    }
    fn skip_spheres_at(&self, s1: &Bounded, s2: &Bounded, m: f64) -> bool {
        (s1.center - s2.center).norm() - s1.radius - s2.radius >= m
    }
    fn skip_cuboid_at(
        &self,
        pose: &Isometry3<f64>,
        half: &Vector3<f64>,
        s: &Bounded,
        m: f64,
    ) -> bool {
        s.centre_box_gap_sq(pose, half).sqrt() - s.radius >= m
    }
    fn skip_gap_sq(&self, gap_sq: f64) -> bool {
        gap_sq.sqrt() >= self.best
    }
    /// Distances of the exact solids; the primitive's distance less the slack (a lower bound)
    /// skips the pieces when it cannot beat the best so far.
    fn plane(&mut self, s: Part, height: f64, _margin: f64, ids: (Id, Id)) -> ControlFlow<()> {
        let bound = plane_distance(s.shape(), height);
        if bound - s.slack() >= self.best && self.ids.is_some() {
            return ControlFlow::Continue(());
        }
        self.offer(s.plane_distance(height).unwrap_or(bound), ids)
    }
    fn pair(&mut self, s1: Part, s2: Part, ids: (Id, Id)) -> ControlFlow<()> {
        let bound = pair_distance(s1.shape(), s2.shape());
        if s1.tight().is_none() && s2.tight().is_none() {
            return self.offer(bound, ids);
        }
        if bound - s1.slack() - s2.slack() >= self.best && self.ids.is_some() {
            return ControlFlow::Continue(());
        }
        self.offer(tight::distance(&s1, &s2), ids)
    }
    fn object(
        &mut self,
        obj: &ObjectGeometry,
        pose: &Isometry3<f64>,
        s: Part,
        ids: (Id, Id),
    ) -> ControlFlow<()> {
        let (c, r) = obj.world_sphere(pose);
        let b = s.bounded;
        if (c - b.center).norm() - r - b.radius - s.slack() >= self.best {
            return ControlFlow::Continue(());
        }
        match s.tight() {
            None => self.offer(obj.distance(pose, b), ids),
            Some(t) => {
                let bound = obj.distance(pose, b);
                if bound - s.slack() >= self.best && self.ids.is_some() {
                    return ControlFlow::Continue(());
                }
                self.offer(obj.pieces_distance(pose, &t), ids)
            }
        }
    }
}
