//! How far each body may move from a checked state, as the pair tests look it up ([`Grows`]):
//! per arm and shape group its levers about the joint axes at the checked configuration, the
//! part's own bound, and the support's vertical-only rule.

use nalgebra::{Point3, Vector3};
use pregrasp_robot::{Joints, SHAPE_GROUPS};

use super::{CollisionWorld, Id, ObjectPlacement, Sweep, WorldState};
use crate::arm::{ArmModel, PosedArm};
use crate::shape::Bounded;

/// A [`Sweep`] as the pair tests look it up: how much each pair's clearance grows.
///
/// Two shape groups of one arm move relative to each other only by the joints between them:
/// for groups in frames `f_a ≤ f_b`, `Σ_{i ≥ f_a} R[i][b]·reach_i` (the joints before `f_a`
/// move both rigidly). The same holds for a part attached to that arm's flange. Against the
/// support only vertical motion counts, and turning the base of an upright arm moves no point
/// up or down.
#[derive(Clone, Debug)]
pub(crate) struct Grows<'w> {
    group_of: [&'w [u8]; 2],
    /// Per arm, frame `f` and group `g`: `Σ_{i ≥ f} R[i][g]·reach_i` (m), how far group g
    /// may move relative to DH frame `f` (f = 0: absolute).
    after: [[[f64; SHAPE_GROUPS]; 7]; 2],
    /// Per arm, the first joint that moves points vertically.
    tilting: [usize; 2],
    /// The part: absolute motion bound, and (attached to `attached`) per frame of that arm
    /// relative to it.
    object: f64,
    attached: Option<usize>,
    object_after: [f64; 7],
    /// Grasping grippers vs the support are left to a test at every state.
    pub grasp_support_apart: bool,
    /// Per arm that moves: its joint axes at the checked state (origin and direction of DH
    /// frame `j`'s `z`), how far each joint may turn, and the configuration-free lever bounds.
    axes: [Option<JointAxes>; 2],
    reach: [Joints; 2],
    radii: [&'w [[f64; SHAPE_GROUPS]; 6]; 2],
}

/// Per joint `j`, a point of its axis and its direction (DH frame `j`'s origin and `z`).
type JointAxes = [(Point3<f64>, Vector3<f64>); 6];

impl<'w> Grows<'w> {
    /// The growths of `sweep` about `state`, the levers worked out at the posed configuration
    /// for the shape groups in `groups[i]` (bit `g`) of each arm `i` — the others keep their
    /// configuration-free bounds (a query about a few pairs needs few groups).
    pub(crate) fn new(
        world: &'w CollisionWorld,
        state: &WorldState,
        sweep: &Sweep,
        grasp_support_apart: bool,
        posed: &[Option<&PosedArm>; 2],
        groups: [u8; 2],
    ) -> Self {
        let mut after = [[[0.0; SHAPE_GROUPS]; 7]; 2];
        let mut tilting = [0; 2];
        let mut axes = [None; 2];
        for i in 0..2 {
            let model = &world.arms()[i];
            let reach = &sweep.reach[i];
            tilting[i] = first_tilting_joint(model);
            if reach.iter().all(|r| *r == 0.0) {
                continue;
            }
            axes[i] = posed[i].map(|p| {
                std::array::from_fn(|j| {
                    let frame = p.frame(j);
                    (
                        Point3::from(frame.translation.vector),
                        frame.rotation * Vector3::z(),
                    )
                })
            });
            let levers = match (posed[i], &axes[i]) {
                (Some(p), Some(axes)) => {
                    levers(&model.set().group_radii, reach, p, axes, groups[i])
                }
                _ => model.set().group_radii,
            };
            // Suffix sums over the joints, from the wrist down.
            for f in (0..6).rev() {
                for g in 0..SHAPE_GROUPS {
                    after[i][f][g] = after[i][f + 1][g] + levers[f][g] * reach[f];
                }
            }
        }
        let (mut object, mut attached, mut object_after) = (sweep.object, None, [0.0; 7]);
        if let ObjectPlacement::Attached { arm: a, .. } = state.object {
            let rho = attached_reach(world, a, state);
            let flange = &world.arms()[a].set().flange_radii;
            let reach = &sweep.reach[a];
            for f in (0..6).rev() {
                object_after[f] = object_after[f + 1] + (flange[f] + rho) * reach[f];
            }
            object = object_after[0];
            attached = Some(a);
        }
        Grows {
            group_of: [
                &world.arms()[0].set().group_of,
                &world.arms()[1].set().group_of,
            ],
            after,
            tilting,
            object,
            attached,
            object_after,
            grasp_support_apart,
            axes,
            reach: sweep.reach,
            radii: [
                &world.arms()[0].set().group_radii,
                &world.arms()[1].set().group_radii,
            ],
        }
    }

    /// How far a point of one shape (in the sphere `s`, of group `g` of arm `i`) may move
    /// relative to DH frame `from`: as the group's bound in [`Grows::new`], with the shape's
    /// own sphere for the group's — `Σ_{j ≥ from} L_j·reach_j`, `L_j` the sphere's distance
    /// from axis `j` plus its radius plus how far the later joints may move it, never more
    /// than `R[j][g]`. A gripper pad lies much nearer the wrist axes than the gripper's far
    /// side. `∞` where the axes are not known (the group bound then stands).
    fn shape_after(&self, i: usize, g: usize, s: &Bounded, from: usize) -> f64 {
        let Some(axes) = &self.axes[i] else {
            return f64::INFINITY;
        };
        let reach = &self.reach[i];
        let levers = sphere_levers(self.radii[i], g, reach, axes, s, from);
        (from..6).rev().map(|j| levers[j] * reach[j]).sum()
    }

    /// [`pair`](Self::pair) for two shapes in the spheres `sa`, `sb`: the shapes' own levers
    /// where they are tighter than their groups' (an arm shape against its own arm, the
    /// support or a static box).
    #[inline]
    pub fn shapes_pair(&self, a: Id, b: Id, sa: &Bounded, sb: &Bounded) -> f64 {
        let group = self.pair(a, b);
        let shape = match (a, b) {
            (Id::Arm(i, _), Id::Arm(j, _)) if i == j => {
                let (ga, gb) = (self.group(i, a), self.group(j, b));
                if ga.min(6) <= gb.min(6) {
                    self.shape_after(i, gb, sb, ga.min(6))
                } else {
                    self.shape_after(i, ga, sa, gb.min(6))
                }
            }
            (Id::Arm(i, _), Id::Support) => {
                self.shape_after(i, self.group(i, a), sa, self.tilting[i])
            }
            (Id::Arm(i, _), Id::Obstacle(_)) => self.shape_after(i, self.group(i, a), sa, 0),
            _ => return group,
        };
        shape.min(group)
    }

    /// The shape group of an arm body.
    #[inline(always)]
    fn group(&self, i: usize, id: Id) -> usize {
        match id {
            Id::Arm(_, k) => self.group_of[i][k] as usize,
            Id::Group(_, g) => g,
            _ => unreachable!("not an arm body"),
        }
    }

    /// How far body `id` may move (against something static).
    #[inline]
    fn of(&self, id: Id) -> f64 {
        match id {
            Id::Arm(i, _) | Id::Group(i, _) => self.after[i][0][self.group(i, id)],
            Id::Object => self.object,
            Id::Support | Id::Obstacle(_) => 0.0,
        }
    }

    /// How much the clearance of the pair `(a, b)` grows (`b` the support: vertical motion).
    #[inline(always)]
    pub fn pair(&self, a: Id, b: Id) -> f64 {
        let arm = |id: Id| match id {
            Id::Arm(i, _) | Id::Group(i, _) => Some(i),
            _ => None,
        };
        match (a, b, arm(a), arm(b)) {
            // Two groups of one arm: by the joints between them.
            (_, _, Some(i), Some(j)) if i == j => {
                let (ga, gb) = (self.group(i, a), self.group(j, b));
                let (fa, fb) = (ga.min(6), gb.min(6));
                let (near, far) = if fa <= fb { (fa, gb) } else { (fb, ga) };
                self.after[i][near][far]
            }
            (_, Id::Support, Some(i), _) | (Id::Support, _, _, Some(i)) => {
                let id = if arm(a).is_some() { a } else { b };
                self.after[i][self.tilting[i]][self.group(i, id)]
            }
            (_, Id::Object, Some(i), _) | (Id::Object, _, _, Some(i))
                if self.attached == Some(i) =>
            {
                let id = if arm(a).is_some() { a } else { b };
                self.object_after[self.group(i, id).min(6)]
            }
            _ => self.of(a) + self.of(b),
        }
    }

    /// The largest growth of any pair's clearance (for the bounding-box culls).
    #[inline]
    pub fn most_pair(&self) -> f64 {
        let most_arm = self.after.iter().flat_map(|a| a[0]).fold(0.0, f64::max);
        most_arm + most_arm.max(self.object)
    }
}

/// Per joint `j` and shape group `g`, how far any point of the group may be from joint axis
/// `j` anywhere in the joint box `reach` about the posed configuration `p` (m): its distance
/// there (the group's sphere from the axis through DH frame `j`'s origin along its `z`) plus
/// how far the joints after `j` may move the group relative to that axis, and never more than
/// the configuration-free bound `radii` ([`pregrasp_robot::group_sweep_radii`]). Joints before
/// `j` move the axis and the group together, and joint `j` turns the group about the axis:
/// neither changes the distance. In a bent arm these levers are much shorter than the
/// stretched arm's.
fn levers(
    radii: &[[f64; SHAPE_GROUPS]; 6],
    reach: &Joints,
    p: &PosedArm,
    axes: &JointAxes,
    groups: u8,
) -> [[f64; SHAPE_GROUPS]; 6] {
    let mut out = *radii;
    for g in (0..SHAPE_GROUPS).filter(|g| groups >> g & 1 == 1) {
        let levers = sphere_levers(radii, g, reach, axes, p.group_sphere(g), 0);
        for (j, lever) in levers.iter().enumerate() {
            out[j][g] = *lever;
        }
    }
    out
}

/// [`levers`] of the points in the sphere `s` (of group `g`), for the joints `from..6` (the
/// others keep `radii`).
#[inline]
fn sphere_levers(
    radii: &[[f64; SHAPE_GROUPS]; 6],
    g: usize,
    reach: &Joints,
    axes: &JointAxes,
    s: &Bounded,
    from: usize,
) -> [f64; 6] {
    let mut out = std::array::from_fn(|j| radii[j][g]);
    // Σ_{k > j} R[k][g]·reach_k, from the wrist down.
    let mut drift = 0.0;
    for j in (from..6).rev() {
        if radii[j][g] > 0.0 {
            let (origin, axis) = &axes[j];
            let v = s.center - origin;
            let off_axis = (v - v.dot(axis) * axis).norm();
            out[j] = radii[j][g].min(off_axis + s.radius + drift);
        }
        drift += radii[j][g] * reach[j];
    }
    out
}

/// The first joint whose motion can move a point of the arm up or down: 1 when the base
/// joint's axis is the world's vertical (turning about it moves every point horizontally),
/// else 0.
pub(crate) fn first_tilting_joint(model: &ArmModel) -> usize {
    let upright = (model.base.rotation * nalgebra::Vector3::z()).z >= 1.0 - 1e-12;
    usize::from(upright)
}

/// Reach of the part attached to `arm` in `state` from its flange origin (m), or 0.
pub fn attached_reach(world: &CollisionWorld, arm: usize, state: &WorldState) -> f64 {
    match (state.object, world.object()) {
        (
            ObjectPlacement::Attached {
                arm: a,
                flange_to_object,
            },
            Some(obj),
        ) if a == arm => {
            let (c, r) = obj.world_sphere(&flange_to_object);
            c.coords.norm() + r
        }
        _ => 0.0,
    }
}
