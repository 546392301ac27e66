use super::*;
use std::sync::Mutex;

fn line() -> JointSpace<1> {
    JointSpace::new([-10.0], [10.0], [1.0]).unwrap()
}

#[test]
fn edge_checks_every_state_once_in_spread_order() {
    let space = line();
    let seen = Mutex::new(Vec::new());
    let v = |q: &State<1>| {
        seen.lock().unwrap().push(q[0]);
        true
    };
    let mv = MotionValidator::new(&space, &v, 0.1);
    let mut count = 0;
    assert!(mv.check_edge_counted(&[0.0], &[1.0], &mut count));
    let seen = seen.into_inner().unwrap();
    assert_eq!(count, 10);
    assert_eq!(seen.len(), 10);
    assert_eq!(seen[0], 1.0, "end state first");
    assert!((seen[1] - 0.5).abs() < 1e-12, "then the midpoint");
    let mut sorted = seen.clone();
    sorted.sort_by(f64::total_cmp);
    for (k, x) in sorted.iter().enumerate() {
        assert!((x - (k + 1) as f64 * 0.1).abs() < 1e-12);
    }
}

#[test]
fn every_sub_state_is_checked_exactly_once_for_any_step_count() {
    let space = line();
    for n in 1..=130usize {
        let seen = Mutex::new(Vec::new());
        let v = |q: &State<1>| {
            seen.lock()
                .unwrap()
                .push((q[0] * n as f64).round() as usize);
            true
        };
        let mv = MotionValidator::new(&space, &v, 1.0 / n as f64 + 1e-12);
        assert_eq!(mv.edge_steps(&[0.0], &[1.0]), n);
        assert!(mv.check_edge(&[0.0], &[1.0]));
        let mut ks = seen.into_inner().unwrap();
        assert_eq!(ks[0], n, "end state first");
        ks.sort_unstable();
        assert_eq!(ks, (1..=n).collect::<Vec<_>>(), "n = {n}");
    }
}

#[test]
fn spread_visits_each_once_coarse_first() {
    for n in 1..=300usize {
        let ks: Vec<usize> = spread(n).collect();
        let mut sorted = ks.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (1..n).collect::<Vec<_>>(), "n = {n}");
        if n >= 4 {
            assert_eq!(ks[0], n / 2, "n = {n}: the midpoint first");
        }
    }
}

#[test]
fn step_bound_respects_resolution() {
    let space = JointSpace::new([-5.0; 3], [5.0; 3], [0.3, 0.2, 0.1]).unwrap();
    let v = |_: &State<3>| true;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let (a, b) = ([0.0, 1.0, -2.0], [1.5, -0.5, 2.0]);
    let n = mv.edge_steps(&a, &b);
    assert!(space.motion_bound(&a, &b) / n as f64 <= 0.01);
    assert!(space.motion_bound(&a, &b) / (n - 1) as f64 > 0.01);
}

#[test]
fn thin_wall_is_found_and_stops_early() {
    let space = line();
    // A wall thinner than the edge but thicker than the resolution.
    let v = |q: &State<1>| !(q[0] > 0.42 && q[0] < 0.47);
    let mv = MotionValidator::new(&space, &v, 0.04);
    let mut count = 0;
    assert!(!mv.check_edge_counted(&[0.0], &[1.0], &mut count));
    assert!(count < mv.edge_steps(&[0.0], &[1.0]) as u64);
    // Coarser than the wall: may be missed — that is the documented contract.
    assert!(mv.with_resolution(0.5).check_edge(&[0.0], &[1.0]));
}

/// A wall on a line, with exact box answers: the interval `q ± r` misses it.
struct Wall {
    from: f64,
    to: f64,
    limit: f64,
}

impl StateValidator<1> for Wall {
    fn is_valid(&self, q: &State<1>) -> bool {
        !(q[0] > self.from && q[0] < self.to)
    }
    fn is_valid_around(&self, q: &State<1>, r: &State<1>) -> bool {
        q[0] + r[0] <= self.from || q[0] - r[0] >= self.to
    }
    fn around_limit(&self) -> f64 {
        self.limit
    }
}

#[test]
fn edges_checked_by_boxes_give_the_answers_of_state_by_state_with_fewer_checks() {
    let space = JointSpace::new([-10.0], [10.0], [1.0]).unwrap();
    let mut fewer = 0;
    for (k, from) in [0.0, 0.123, 0.42, 0.5, 0.97, 2.0].iter().enumerate() {
        let wall = Wall {
            from: *from,
            to: from + 0.013 * (k + 1) as f64,
            limit: [0.05, 0.2, 5.0][k % 3],
        };
        let plain = |q: &State<1>| wall.is_valid(q);
        for (a, b) in [
            (-0.3, 1.4),
            (1.4, -0.3),
            (0.6, 0.9),
            (0.2, 0.45),
            (2.5, 3.0),
        ] {
            for resolution in [0.001, 0.007, 0.04] {
                let boxes = MotionValidator::new(&space, &wall, resolution);
                let states = MotionValidator::new(&space, &plain, resolution);
                let (mut n1, mut n2) = (0, 0);
                let by_boxes = boxes.check_edge_counted(&[a], &[b], &mut n1);
                let one_by_one = states.check_edge_counted(&[a], &[b], &mut n2);
                assert_eq!(
                    by_boxes, one_by_one,
                    "wall {from}, {a} → {b} at {resolution}"
                );
                // With both ends valid, the states between them decide alone.
                if states.check_state(&[a]) && states.check_state(&[b]) {
                    assert_eq!(boxes.check_edge_between_valid(&[a], &[b]), one_by_one);
                    assert_eq!(states.check_edge_between_valid(&[a], &[b]), one_by_one);
                }
                if by_boxes && states.edge_steps(&[a], &[b]) > 20 {
                    assert!(n1 < n2, "{n1} checks with boxes, {n2} without");
                    fewer += 1;
                }
            }
        }
    }
    assert!(fewer > 10);
}

/// Several walls on a line, each a constraint of its own, counting how often each is asked.
struct Walls {
    walls: Vec<(f64, f64)>,
    asked: Mutex<usize>,
}

impl Walls {
    fn free(&self, w: usize, q: f64, r: f64) -> bool {
        *self.asked.lock().unwrap() += 1;
        let (from, to) = self.walls[w];
        q + r <= from || q - r >= to
    }
}

impl StateValidator<1> for Walls {
    fn is_valid(&self, q: &State<1>) -> bool {
        (0..self.walls.len()).all(|w| self.free(w, q[0], 0.0))
    }
    fn is_valid_around(&self, q: &State<1>, r: &State<1>) -> bool {
        (0..self.walls.len()).all(|w| self.free(w, q[0], r[0]))
    }
    fn around_limit(&self) -> f64 {
        0.2
    }
    fn doubts_around(&self, q: &State<1>, r: &State<1>, among: Option<&Doubts>) -> Option<Doubts> {
        let mut doubts = Doubts::default();
        for w in 0..self.walls.len() {
            let asked = among.is_none_or(|d| d.contains(w as u32));
            if asked && !self.free(w, q[0], r[0]) && !doubts.insert(w as u32) {
                return None;
            }
        }
        Some(doubts)
    }
    fn is_valid_among(&self, q: &State<1>, among: &Doubts) -> bool {
        among
            .as_slice()
            .iter()
            .all(|&w| self.free(w as usize, q[0], 0.0))
    }
}

/// The same walls, box checks whole (the default `doubts_around`).
struct Whole<'a>(&'a Walls);

impl StateValidator<1> for Whole<'_> {
    fn is_valid(&self, q: &State<1>) -> bool {
        self.0.is_valid(q)
    }
    fn is_valid_around(&self, q: &State<1>, r: &State<1>) -> bool {
        self.0.is_valid_around(q, r)
    }
    fn around_limit(&self) -> f64 {
        self.0.around_limit()
    }
}

#[test]
fn doubts_handed_down_give_the_same_answers_for_fewer_questions() {
    let space = JointSpace::new([-10.0], [10.0], [1.0]).unwrap();
    let mut rng_state = 7u64;
    let mut next = || {
        rng_state = rng_state.wrapping_mul(6364136223846793005).wrapping_add(1);
        (rng_state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut named, mut whole) = (0, 0);
    for case in 0..200 {
        // Up to 20 thin walls, some grazed by the edge, some across it.
        let count = 1 + case % 20;
        let walls = Walls {
            walls: (0..count)
                .map(|_| {
                    let from = next() * 4.0 - 1.0;
                    (from, from + 0.001 + 0.02 * next())
                })
                .collect(),
            asked: Mutex::new(0),
        };
        let (a, b) = (next() * 3.0 - 1.0, next() * 3.0 - 1.0);
        let plain = |q: &State<1>| walls.walls.iter().all(|&(f, t)| q[0] <= f || q[0] >= t);
        for resolution in [0.002, 0.01] {
            let truth = MotionValidator::new(&space, &plain, resolution).check_edge(&[a], &[b]);
            *walls.asked.lock().unwrap() = 0;
            let by_doubts = MotionValidator::new(&space, &walls, resolution).check_edge(&[a], &[b]);
            named += *walls.asked.lock().unwrap();
            *walls.asked.lock().unwrap() = 0;
            let by_boxes =
                MotionValidator::new(&space, &Whole(&walls), resolution).check_edge(&[a], &[b]);
            whole += *walls.asked.lock().unwrap();
            assert_eq!(by_doubts, truth, "case {case}: {a} → {b} at {resolution}");
            assert_eq!(by_boxes, truth, "case {case}: {a} → {b} at {resolution}");
        }
    }
    // Walls asked about: a box near one wall no longer asks the others again.
    assert!(2 * named < whole, "{named} with doubts, {whole} without");
}

#[test]
fn doubts_hold_each_constraint_once_up_to_capacity() {
    let mut d = Doubts::default();
    assert!(d.is_empty());
    for id in 0..Doubts::CAPACITY as u32 {
        assert!(d.insert(id));
        assert!(d.insert(id), "already in");
    }
    assert_eq!(d.as_slice().len(), Doubts::CAPACITY);
    assert!(!d.insert(99), "full");
    assert!(d.contains(3) && !d.contains(99));
}

#[test]
fn end_state_outside_bounds_is_invalid() {
    let space = line();
    let v = |_: &State<1>| true;
    let mv = MotionValidator::new(&space, &v, 0.1);
    assert!(!mv.check_edge(&[0.0], &[11.0]));
    assert!(mv.check_path(&[[0.0], [1.0], [-3.0]]));
    assert!(!mv.check_path(&[]));
}

#[test]
fn zero_resolution_does_not_hang_on_zero_length_edge() {
    let space = line();
    let v = |_: &State<1>| true;
    let mv = MotionValidator::new(&space, &v, 0.0);
    assert!(mv.check_edge(&[1.0], &[1.0]));
}
