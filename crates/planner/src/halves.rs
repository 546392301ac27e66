//! Collision answers over long runs of states that are exact per state — the first state in
//! contact, each arm's least grasping height — computed in halves side by side where the runs
//! are long and the pool has a second thread: exact answers of the halves combine into the
//! whole run's, bit for bit, whatever the threads. μ_rot's states (checked once its branch is
//! tracked) and the re-check's (thousands a plan) are such runs; the candidate that runs last
//! in its wave gets the idle thread.

use pregrasp_collision::{CollisionWorld, StatesCheck, WorldState};

/// Runs of more states than this are checked in halves.
const SPLIT_STATES: usize = 1024;

/// [`CollisionWorld::check_states`] (no arm singled out) over `states`, in halves.
pub(crate) fn check_states(world: &CollisionWorld, states: &[WorldState]) -> StatesCheck {
    if states.len() <= SPLIT_STATES || rayon::current_num_threads() < 2 {
        return world.check_states(None, states);
    }
    let mid = states.len() / 2;
    let (a, b) = rayon::join(
        || check_states(world, &states[..mid]),
        || check_states(world, &states[mid..]),
    );
    let least = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    };
    StatesCheck {
        first_contact: a.first_contact.or(b.first_contact.map(|k| k + mid)),
        closest_grasp: [0, 1].map(|arm| least(a.closest_grasp[arm], b.closest_grasp[arm])),
    }
}

/// [`CollisionWorld::first_contact_in`] (no arm singled out) over `states`, in halves.
pub(crate) fn first_contact(world: &CollisionWorld, states: &[WorldState]) -> Option<usize> {
    if states.len() <= SPLIT_STATES || rayon::current_num_threads() < 2 {
        return world.first_contact_in(None, states);
    }
    let mid = states.len() / 2;
    let (a, b) = rayon::join(
        || first_contact(world, &states[..mid]),
        || first_contact(world, &states[mid..]),
    );
    a.or(b.map(|k| k + mid))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use nalgebra::{Isometry3, Vector3};
    use pregrasp_collision::fixtures::frame_mesh;
    use pregrasp_collision::{ArmModel, CollisionWorld, ObjectPlacement, WorldState};
    use pregrasp_robot::{Gripper2F85, GripperState, Joints, UrModel};

    use super::{check_states, first_contact, SPLIT_STATES};

    /// Uniform numbers in `[lo, hi)`, the same for the same seed (SplitMix64).
    struct Numbers(u64);

    impl Numbers {
        fn next(&mut self, lo: f64, hi: f64) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            lo + (hi - lo) * (z >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Two UR5e 0.9 m apart, a frame lying between them, the planner's margins.
    fn cell() -> CollisionWorld {
        let arm = |name: &str, y: f64| {
            let base = Isometry3::translation(0.0, y, 0.0);
            ArmModel::new(name, UrModel::Ur5e, base, Gripper2F85::default())
        };
        let mesh = frame_mesh(0.5, 0.3, 0.05, 0.02);
        CollisionWorld::try_new(
            Some(0.0),
            Some(&mesh),
            [arm("left", 0.45), arm("right", -0.45)],
        )
        .expect("a valid mesh")
        .with_margin(0.008)
        .with_grasp_support_margin(0.0026)
        .with_held_fingers([&[GripperState::at_gap(0.02)], &[GripperState::at_gap(0.02)]])
    }

    /// Arm 0 moving along a few straight joint-space legs in steps of at most 0.5 mrad, its
    /// gripper grasping on some legs, arm 1 still, the part turning slowly.
    fn motion(n: &mut Numbers) -> Vec<WorldState> {
        let random_q = |n: &mut Numbers| -> Joints {
            [
                n.next(-PI, PI),
                n.next(-2.8, -0.3),
                n.next(-2.5, 2.5),
                n.next(-PI, PI),
                n.next(-PI, PI),
                n.next(-PI, PI),
            ]
        };
        let other = random_q(n);
        let mut q = random_q(n);
        let mut states = Vec::new();
        for leg in 0..3 {
            let to: Joints = std::array::from_fn(|j| q[j] + n.next(-0.6, 0.6));
            let longest = (0..6).map(|j| (to[j] - q[j]).abs()).fold(0.0, f64::max);
            let steps = ((longest / 0.0005).ceil() as usize).max(1);
            let grasping = leg == 1 || n.next(0.0, 1.0) < 0.3;
            for k in 0..steps {
                let f = k as f64 / steps as f64;
                let theta = 0.3 * states.len() as f64 / 4000.0;
                states.push(WorldState {
                    q: [std::array::from_fn(|j| q[j] + f * (to[j] - q[j])), other],
                    gripper: [GripperState::at_gap(0.02), GripperState::Open],
                    object: ObjectPlacement::Fixed(
                        Isometry3::translation(0.55, -0.25, 0.001)
                            * Isometry3::rotation(Vector3::new(0.0, -theta, 0.0)),
                    ),
                    grasping: [grasping, false],
                });
            }
            q = to;
        }
        states
    }

    /// Checked in halves on two threads, a run gives what it gives checked whole: the same
    /// first state in contact, the same least grasping heights.
    #[test]
    fn states_checked_in_halves_are_the_whole_runs_answer() {
        let world = cell();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("a pool");
        let mut n = Numbers(48);
        let (mut split, mut late_contact, mut clear) = (0, 0, 0);
        for _ in 0..40 {
            let states = motion(&mut n);
            let whole = world.check_states(None, &states);
            let halves = pool.install(|| check_states(&world, &states));
            assert_eq!(halves, whole, "{} states", states.len());
            let first = pool.install(|| first_contact(&world, &states));
            assert_eq!(first, world.first_contact_in(None, &states));
            assert_eq!(first, whole.first_contact);
            split += usize::from(states.len() > SPLIT_STATES);
            match whole.first_contact {
                Some(k) if k > states.len() / 2 => late_contact += 1,
                Some(_) => {}
                None => clear += 1,
            }
        }
        assert!(
            split > 30 && late_contact > 3 && clear > 3,
            "{split} split, {late_contact} in contact past the middle, {clear} clear"
        );
    }
}
