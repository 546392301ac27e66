//! The pairs a query checks (the module documentation of [`super`] lists them): posing both
//! arms once per state (a per-thread cache keeps the arm that stands still), culling whole
//! shape groups by their spheres, and feeding every remaining pair to a [`Sink`].

use std::ops::ControlFlow;

use nalgebra::{Isometry3, Vector3};
use pregrasp_motion::Doubts;

use crate::arm::PosedArm;
use crate::distance::aabb_aabb_sq;
use crate::object::ObjectGeometry;
use crate::shape::{Bounded, Placed};
use crate::tight::Part;

use super::sink::pair_ids;
use super::{CollisionWorld, Id, ObjectPlacement, Sink, WorldState};

/// Key of a posed arm in the cache: world id, arm, joint bits, gripper gap bits (open: `u64::MAX`).
type PoseKey = (u64, usize, [u64; 6], [u64; 3]);

/// Both arms as last posed on this thread, with the keys they were posed for.
type PosedPair = ([Option<PoseKey>; 2], [PosedArm; 2]);

thread_local! {
    /// Both arms as last posed on this thread: queries pose into it without copying, and an arm
    /// whose key has not changed (the arm that stands still while the other moves, in every
    /// query of a motion) is not posed again.
    static POSED: std::cell::RefCell<PosedPair> =
        const { std::cell::RefCell::new(([None, None], [PosedArm::EMPTY, PosedArm::EMPTY])) };
}

impl CollisionWorld {
    /// Enumerates every pair to check (restricted to arm `only` if given), feeding `sink`.
    pub(crate) fn visit(
        &self,
        only: Option<usize>,
        state: &WorldState,
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        self.with_posed(state, |posed| self.visit_posed(only, state, posed, sink))
    }

    /// The pairs `among` (as [`pair_code`] names them, each found by an earlier visit of a
    /// state that differs from `state` in one arm's joints at most), fed to `sink` directly:
    /// each with the test and clearance [`visit_posed`](Self::visit_posed) gives it, none of
    /// the culls that lead there.
    pub(crate) fn visit_among(
        &self,
        state: &WorldState,
        posed: [Option<&PosedArm>; 2],
        among: &Doubts,
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        let object = self
            .object
            .as_deref()
            .zip(self.object_pose_posed(state, &posed));
        for &code in among.as_slice() {
            let ids = pair_ids(code);
            let part = |id: Id| match id {
                Id::Arm(i, k) => posed[i].map(|p| p.part(self.arms[i].set(), k)),
                Id::Obstacle(o) => Some(Part::plain(&self.obstacles[o].shape)),
                _ => None,
            };
            match ids {
                (Id::Arm(i, k), Id::Support) => {
                    let (Some(h), Some(p)) = (self.support, part(ids.0)) else {
                        continue;
                    };
                    let margin = if state.grasping[i] && self.arms[i].set().is_gripper[k] {
                        if !sink.grasp_support() {
                            continue;
                        }
                        self.grasp_support_margin
                    } else {
                        self.margin
                    };
                    sink.plane(p, h, margin, ids)?;
                }
                (_, Id::Object) | (Id::Object, _) => {
                    let (Some((obj, pose)), Some(p)) = (object, part(ids.0).or(part(ids.1))) else {
                        continue;
                    };
                    sink.object(obj, &pose, p, ids)?;
                }
                (Id::Arm(..), Id::Arm(..) | Id::Obstacle(_)) => {
                    if let (Some(a), Some(b)) = (part(ids.0), part(ids.1)) {
                        sink.pair(a, b, ids)?;
                    }
                }
                _ => unreachable!("not a pair a visit reports: {ids:?}"),
            }
        }
        ControlFlow::Continue(())
    }

    /// Calls `f` with both active arms posed at `state` (from the per-thread buffers).
    pub(crate) fn with_posed<R>(
        &self,
        state: &WorldState,
        f: impl FnOnce([Option<&PosedArm>; 2]) -> R,
    ) -> R {
        self.with_posed_shapes(state, [u64::MAX; 2], f)
    }

    /// [`with_posed`](Self::with_posed) with, of each arm `i`, only the shapes in `shapes[i]`
    /// (bit `k`: shape `k`) sure to be placed: for a query about a few pairs. The frames and
    /// bounding spheres are always posed.
    pub(crate) fn with_posed_shapes<R>(
        &self,
        state: &WorldState,
        shapes: [u64; 2],
        f: impl FnOnce([Option<&PosedArm>; 2]) -> R,
    ) -> R {
        // Both active arms are posed: in a single-arm query the other one is an obstacle.
        POSED.with_borrow_mut(|(keys, buffers)| {
            for i in 0..2 {
                if !self.active[i] {
                    continue;
                }
                let key = self.pose_key(i, state);
                let arm = &self.arms[i];
                if keys[i] != Some(key) {
                    arm.pose_frames_into(&state.q[i], state.gripper[i], &mut buffers[i]);
                    keys[i] = Some(key);
                }
                arm.place_into(&mut buffers[i], shapes[i]);
            }
            let [b0, b1] = &*buffers;
            f([self.active[0].then_some(b0), self.active[1].then_some(b1)])
        })
    }

    /// [`visit`](Self::visit) with both arms posed.
    pub(crate) fn visit_posed(
        &self,
        only: Option<usize>,
        state: &WorldState,
        posed: [Option<&PosedArm>; 2],
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        let object = self
            .object
            .as_deref()
            .zip(self.object_pose_posed(state, &posed));
        let attached_to = match state.object {
            ObjectPlacement::Attached { arm, .. } if object.is_some() => Some(arm),
            _ => None,
        };
        if sink.part_first() {
            for (i, pi) in posed.iter().enumerate() {
                if let Some(pi) = pi.filter(|_| self.active[i] && only.is_none_or(|o| o == i)) {
                    self.visit_part(i, pi, state, object, sink)?;
                }
            }
        }
        for i in 0..2 {
            if !self.active[i] || only.is_some_and(|o| o != i) {
                continue;
            }
            let Some(pi) = posed[i] else { continue };
            let arm = &self.arms[i];
            let shapes = pi.shapes();
            let set = arm.set();
            // 1. Support. A gripper that grasps (holds, closes on or releases the part) keeps
            //    its own clearance from the support.
            //    A group whose sphere keeps its clearance is passed whole (the visit order stays
            //    the shapes').
            if let Some(h) = self.support {
                let grasping = |g: usize| state.grasping[i] && g == 7;
                let plane_margin = |g: usize| {
                    if grasping(g) {
                        self.grasp_support_margin
                    } else {
                        self.margin
                    }
                };
                // A grasping gripper the sink leaves out is passed like a clear group.
                let clear: [bool; pregrasp_robot::SHAPE_GROUPS] = std::array::from_fn(|g| {
                    let ids = (Id::Group(i, g), Id::Support);
                    grasping(g) && !sink.grasp_support()
                        || sink.skip_plane(pi.group_sphere(g), h, plane_margin(g), ids)
                });
                for k in 0..shapes.len() {
                    let g = set.group_of[k] as usize;
                    if arm.is_base_part(k) || clear[g] {
                        continue;
                    }
                    let ids = (Id::Arm(i, k), Id::Support);
                    sink.plane(pi.part(set, k), h, plane_margin(g), ids)?;
                }
            }
            // 2. Self-collision pairs. The culls' margin is one per pair of groups.
            for ((fa, fb), pairs) in &set.link_pair_groups {
                let (ga, gb) = (Id::Group(i, *fa as usize), Id::Group(i, *fb as usize));
                let (sa, sb) = (pi.frame_sphere(*fa as usize), pi.frame_sphere(*fb as usize));
                let m = sink.cull_margin((ga, gb));
                if sink.skip_spheres_at(sa, sb, m) {
                    continue;
                }
                for &(a, b) in pairs {
                    let (a, b) = (a as usize, b as usize);
                    if !sink.skip_spheres_at(&shapes[a], &shapes[b], m) {
                        let (sa, sb) = (pi.part(set, a), pi.part(set, b));
                        sink.pair(sa, sb, (Id::Arm(i, a), Id::Arm(i, b)))?;
                    }
                }
            }
            //    The gripper vs the links it must not touch, culled by its enclosing sphere.
            let grip_m: [f64; 7] =
                std::array::from_fn(|f| sink.cull_margin((Id::Group(i, f), Id::Group(i, 7))));
            for &l in &set.gripper_forbidden {
                let l = l as usize;
                let sl = &shapes[l];
                let m = grip_m[set.group_of[l] as usize];
                if sink.skip_spheres_at(sl, pi.gripper_sphere(), m) {
                    continue;
                }
                for g in pi.gripper_range() {
                    if !sink.skip_spheres_at(sl, &shapes[g], m) {
                        let (pl, pg) = (pi.part(set, l), pi.part(set, g));
                        sink.pair(pl, pg, (Id::Arm(i, l), Id::Arm(i, g)))?;
                    }
                }
            }
            // 3. Static cuboids, culled by the spheres' distances from the boxes themselves (a
            //    group's margin is one against every static body).
            let obstacle_m: [f64; 8] = if self.obstacles.is_empty() {
                [0.0; 8]
            } else {
                std::array::from_fn(|g| sink.cull_margin((Id::Group(i, g), Id::Obstacle(0))))
            };
            for (o, obs) in self.obstacles.iter().enumerate() {
                let (pose, half) = obs.cuboid();
                for (g, members) in set.group_members.iter().enumerate() {
                    if members.is_empty() {
                        continue;
                    }
                    let sg = pi.group_sphere(g);
                    let m = obstacle_m[g];
                    if sink.skip_spheres_at(sg, &obs.shape, m)
                        || sink.skip_cuboid_at(&pose, &half, sg, m)
                    {
                        continue;
                    }
                    for &k in members {
                        let (k, s) = (k as usize, &shapes[k as usize]);
                        if !arm.is_base_part(k)
                            && !sink.skip_spheres_at(s, &obs.shape, m)
                            && !sink.skip_cuboid_at(&pose, &half, s, m)
                        {
                            let ids = (Id::Arm(i, k), Id::Obstacle(o));
                            sink.pair(pi.part(set, k), Part::plain(&obs.shape), ids)?;
                        }
                    }
                }
            }
            // 4. The other arm (each unordered pair of arms once).
            let j = 1 - i;
            if let Some(pj) = posed[j] {
                if self.active[j] && (only.is_some() || i < j) {
                    self.arm_vs_arm(i, pi, j, pj, sink)?;
                }
            }
            // 5. The part (visited first instead when the sink asks).
            if !sink.part_first() {
                self.visit_part(i, pi, state, object, sink)?;
            }
        }
        // 6. The attached part vs static cuboids, and (single-arm queries) vs the other arm.
        if let (Some(a), Some((obj, pose))) = (attached_to, &object) {
            if only.is_none_or(|o| o == a) {
                for (o, obs) in self.obstacles.iter().enumerate() {
                    let part = Part::plain(&obs.shape);
                    sink.object(obj, pose, part, (Id::Object, Id::Obstacle(o)))?;
                }
                let j = 1 - a;
                if only.is_some() && self.active[j] {
                    if let Some(pj) = posed[j] {
                        let set = self.arms[j].set();
                        for k in 0..pj.shapes().len() {
                            if state.grasping[j] && set.is_gripper[k] {
                                continue;
                            }
                            sink.object(obj, pose, pj.part(set, k), (Id::Arm(j, k), Id::Object))?;
                        }
                    }
                }
            }
        }
        ControlFlow::Continue(())
    }

    /// Arm `i` (posed as `pi`) vs the part at its pose, by groups culled by the part's sphere
    /// and box; the gripper of an arm that grasps is left out.
    fn visit_part(
        &self,
        i: usize,
        pi: &PosedArm,
        state: &WorldState,
        object: Option<(&ObjectGeometry, Isometry3<f64>)>,
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        let Some((obj, pose)) = object else {
            return ControlFlow::Continue(());
        };
        let set = self.arms[i].set();
        let (c, r) = obj.world_sphere(&pose);
        let part = Bounded::new(Placed::Capsule {
            a: c,
            b: c,
            radius: r,
        });
        for (g, members) in set.group_members.iter().enumerate() {
            let sphere = pi.group_sphere(g);
            let gripper = g == 7;
            if members.is_empty()
                || gripper && state.grasping[i]
                || sink.skip_spheres(sphere, &part, (Id::Group(i, g), Id::Object))
                || sink.skip_object_box(obj, &pose, sphere, (Id::Group(i, g), Id::Object))
            {
                continue;
            }
            for &k in members {
                let k = k as usize;
                sink.object(obj, &pose, pi.part(set, k), (Id::Arm(i, k), Id::Object))?;
            }
        }
        ControlFlow::Continue(())
    }

    /// What arm `i`'s pose at `state` depends on.
    fn pose_key(&self, i: usize, state: &WorldState) -> PoseKey {
        (
            self.id,
            i,
            state.q[i].map(f64::to_bits),
            state.gripper[i].key(),
        )
    }

    /// [`object_pose`](Self::object_pose), reusing the flange of an already posed arm.
    fn object_pose_posed(
        &self,
        state: &WorldState,
        posed: &[Option<&PosedArm>; 2],
    ) -> Option<Isometry3<f64>> {
        match (state.object, self.object.as_deref()) {
            (
                ObjectPlacement::Attached {
                    arm,
                    flange_to_object,
                },
                Some(_),
            ) => match posed[arm] {
                Some(p) => Some(p.flange() * flange_to_object),
                None => self.object_pose(state),
            },
            _ => self.object_pose(state),
        }
    }

    /// Arm `i` vs arm `j`, by groups (the links of one DH frame, or the gripper) culled by
    /// their spheres before their shapes are paired. The two bases are never paired: both are
    /// mounted.
    fn arm_vs_arm(
        &self,
        i: usize,
        pi: &PosedArm,
        j: usize,
        pj: &PosedArm,
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        let (lo_i, hi_i) = pi.bounds();
        let (lo_j, hi_j) = pj.bounds();
        if sink.skip_gap_sq(aabb_aabb_sq(&lo_i, &hi_i, &lo_j, &hi_j)) {
            return ControlFlow::Continue(());
        }
        let (set_i, set_j) = (self.arms[i].set(), self.arms[j].set());
        for (gi, members_i) in set_i.group_members.iter().enumerate() {
            let si = pi.group_sphere(gi);
            if members_i.is_empty() {
                continue;
            }
            let r = Vector3::repeat(si.radius);
            if sink.skip_gap_sq(aabb_aabb_sq(
                &(si.center - r),
                &(si.center + r),
                &lo_j,
                &hi_j,
            )) {
                continue;
            }
            for (gj, members_j) in set_j.group_members.iter().enumerate() {
                if members_j.is_empty() {
                    continue;
                }
                // One cull margin for the two groups' pairs; a shape far from the other
                // group's sphere skips its shapes.
                let sj = pj.group_sphere(gj);
                let m = sink.cull_margin((Id::Group(i, gi), Id::Group(j, gj)));
                if sink.skip_spheres_at(si, sj, m) {
                    continue;
                }
                for &k in members_i {
                    let k = k as usize;
                    let a = &pi.shapes()[k];
                    if sink.skip_spheres_at(a, sj, m) {
                        continue;
                    }
                    let base_k = self.arms[i].is_base_part(k);
                    for &l in members_j {
                        let l = l as usize;
                        if base_k && self.arms[j].is_base_part(l) {
                            continue;
                        }
                        if !sink.skip_spheres_at(a, &pj.shapes()[l], m) {
                            let (pa, pb) = (pi.part(set_i, k), pj.part(set_j, l));
                            sink.pair(pa, pb, (Id::Arm(i, k), Id::Arm(j, l)))?;
                        }
                    }
                }
            }
        }
        ControlFlow::Continue(())
    }
}
