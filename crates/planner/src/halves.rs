//! Collision answers over long runs of states that are exact per state — the first state in
//! contact, each arm's least grasping height — computed in halves side by side where the runs
//! are long and the pool has a second thread: exact answers of the halves combine into the
//! whole run's, bit for bit, whatever the threads. μ_rot's states (checked once its branch is
//! tracked) and the re-check's (thousands a plan) are such runs; the candidate that runs last
//! in its wave gets the idle thread.

use pregrasp_collision::{CollisionWorld, StatesCheck, WorldState};

/// Runs of more states than this are checked in halves.
const SPLIT_STATES: usize = 1024;

/// `whole` over `states`, or over its halves side by side (`join` makes one answer of the
/// halves', the second half's indices counted from `mid`).
fn in_halves<T: Send>(
    states: &[WorldState],
    whole: &(impl Fn(&[WorldState]) -> T + Sync),
    join: &(impl Fn(T, T, usize) -> T + Sync),
) -> T {
    if states.len() <= SPLIT_STATES || rayon::current_num_threads() < 2 {
        return whole(states);
    }
    let mid = states.len() / 2;
    let (a, b) = rayon::join(
        || in_halves(&states[..mid], whole, join),
        || in_halves(&states[mid..], whole, join),
    );
    join(a, b, mid)
}

/// [`CollisionWorld::check_states`] (no arm singled out) over `states`, in halves.
pub(crate) fn check_states(world: &CollisionWorld, states: &[WorldState]) -> StatesCheck {
    let least = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    };
    in_halves(
        states,
        &|run| world.check_states(None, run),
        &|a: StatesCheck, b: StatesCheck, mid| StatesCheck {
            first_contact: a.first_contact.or(b.first_contact.map(|k| k + mid)),
            closest_grasp: [0, 1].map(|arm| least(a.closest_grasp[arm], b.closest_grasp[arm])),
        },
    )
}

/// [`CollisionWorld::first_contact_in`] (no arm singled out) over `states`, in halves.
pub(crate) fn first_contact(world: &CollisionWorld, states: &[WorldState]) -> Option<usize> {
    in_halves(
        states,
        &|run| world.first_contact_in(None, run),
        &|a: Option<usize>, b: Option<usize>, mid| a.or(b.map(|k| k + mid)),
    )
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry3, Vector3};
    use pregrasp_collision::fixtures::{two_arm_cell, SAMPLE_RANGES};
    use pregrasp_collision::{CollisionWorld, ObjectPlacement, WorldState};
    use pregrasp_robot::{GripperState, Joints};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::{check_states, first_contact, SPLIT_STATES};

    /// Arm 0 moving along a few straight joint-space legs in steps of at most 0.5 mrad from a
    /// state clear of everything (so that contacts come anywhere along the run), its gripper
    /// grasping on some legs, arm 1 still, the part turning slowly.
    fn motion(world: &CollisionWorld, rng: &mut ChaCha8Rng) -> Vec<WorldState> {
        let random_q = |rng: &mut ChaCha8Rng| -> Joints {
            SAMPLE_RANGES.map(|(lo, hi)| rng.random_range(lo..hi))
        };
        let (other, mut q) = loop {
            let (other, q) = (random_q(rng), random_q(rng));
            if world.check(&WorldState::new([q, other])).is_ok() {
                break (other, q);
            }
        };
        let mut states = Vec::new();
        for leg in 0..3 {
            let to: Joints = std::array::from_fn(|j| q[j] + rng.random_range(-0.6..0.6));
            let longest = (0..6).map(|j| (to[j] - q[j]).abs()).fold(0.0, f64::max);
            let steps = ((longest / 0.0005).ceil() as usize).max(1);
            let grasping = leg == 1 || rng.random_bool(0.3);
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
        let world = two_arm_cell();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("a pool");
        let mut rng = ChaCha8Rng::seed_from_u64(48);
        let (mut split, mut late_contact, mut clear) = (0, 0, 0);
        for _ in 0..40 {
            let states = motion(&world, &mut rng);
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
