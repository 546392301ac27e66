//! How the 2F-85's fingers close on what lies between them: quasi-static, as the linkage
//! ([`crate::FingerLinkage`]) closes — the real gripper's adaptive grasp, not a parallel slide.
//!
//! Both drivers turn together (one actuator drives both; [`close_fingers`]). At every driver
//! angle each finger settles: its spring pushes the spring link closed as far as it is free,
//! up to the coupler's stop, so in free air the finger closes in the parallel mode. What meets
//! the part first decides the rest:
//! - the follower or the pad: a **pinch**; friction holds the pad where it met the part, and
//!   the drivers stop once a pad cannot move on without entering the part, and the other
//!   finger, if it has touched nothing, meets the part too where [`CONTACT_SLACK`] of driver
//!   travel takes it there (the part and the pads give by more than that);
//! - the spring link (the proximal phalanx): it rests on the part while the driver turns on, so
//!   the follower curls inward about its hinge, and where the curling follower meets the part
//!   the part pushes the spring link open again (the finger wraps the part) — but where the pad
//!   meets it, the pad presses the part and the finger stops: **encompassing** when the drivers
//!   are blocked, **caged** when the tips meet in the middle first;
//! - the driver or the coupler: the finger is **stuck** there.
//!
//! A finger that reaches the middle plane (`x = 0`, where it meets the other finger) without
//! touching the part has **closed** on nothing. Every configuration either finger passes
//! through is tested against the support as well: the first touch is recorded (link, driver
//! angle) and the closing stops there — the real finger would be stopped or dragged by the
//! table, so the grasp is not the one planned.
//!
//! Held to MuJoCo's closing of the Menagerie model on 471 bars (`tests/closing_truth.rs`): the
//! same table verdict in every row that is not a graze, 92 % of the pads and tips within 2 mm;
//! and on 294 bars held as power grasps, their top 0.5–16 mm below the palm: ours squeezes where
//! MuJoCo's pads press the bar from both sides in 212 of 217 rows and is caged in the other 77,
//! as MuJoCo is (the pads' positions there differ by 4.6 mm at the median: the force balance
//! that pushes MuJoCo's spring link open is not in a kinematic model).
//! Where it departs — MuJoCo's spring link, pushed open by force balance, lets the follower wrap
//! tighter under a bar at the power point — ours curls deeper, the cautious side for the table.
//!
//! What touches what is the caller's ([`ClosingWorld`]): this module knows the linkage, not the
//! part. Contacts are found on a driver-angle grid of [`DRIVER_STEP`] and refined by bisection
//! to [`DRIVER_TOLERANCE`].

use std::cell::{Cell, RefCell};

use crate::linkage::{FingerConfig, FingerLinkage, PlanarPose};

/// Driver-angle step of the closing search (rad): about 0.27 mm of pad travel.
pub const DRIVER_STEP: f64 = 0.005;
/// Resolution of a contact's driver angle (rad): about 1 µm of pad travel.
pub const DRIVER_TOLERANCE: f64 = 2e-5;

/// Links of a finger as [`crate::FINGER_LINKS`] numbers them.
pub const DRIVER: usize = 0;
pub const COUPLER: usize = 1;
pub const SPRING_LINK: usize = 2;
pub const FOLLOWER: usize = 3;
pub const PAD: usize = 4;

/// A link ([`crate::FINGER_LINKS`] number) and what it touches, if anything does.
type LinkTouch = Option<(usize, Touch)>;
/// A settled finger and the touch bounding its spring link from above, or what blocks it.
type Settled = Result<(FingerConfig, LinkTouch), LinkTouch>;

/// What a finger link touches in one pose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Touch {
    Nothing,
    Part,
    Support,
}

/// What the fingers close on: asked for one link of one finger in one pose.
pub trait ClosingWorld {
    /// What link `link` ([`crate::FINGER_LINKS`] order) of the finger on side `side` (`+1.0`:
    /// the `+x` finger, `−1.0` its mirror image) touches with its frame at `pose` (in the
    /// finger plane of G; [`PlanarPose::to_isometry`] gives the 3-D frame).
    fn touch(&self, side: f64, link: usize, pose: &PlanarPose) -> Touch;

    /// Whether the world has a support at all (without one, a finger's first touch of the
    /// part decides what it touches and the links after it need not be asked).
    fn has_support(&self) -> bool {
        true
    }
}

/// How a finger's closing ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClosingKind {
    /// The follower or pad touched the part first.
    Pinch,
    /// The spring link touched first; the follower curled until it touched the part.
    Encompassing,
    /// The spring link touched first; the follower curled until its tip met the other finger
    /// (or a joint its limit) without touching the part again: the bar is caged.
    Caged,
    /// The driver or coupler touched the part.
    Stuck,
    /// The finger reached the middle without touching the part.
    Closed,
}

/// One finger's closing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FingerClosing {
    /// The finger where it stopped.
    pub config: FingerConfig,
    pub kind: ClosingKind,
    /// The link that touched the part first, if any.
    pub first_touch: Option<usize>,
    /// The first configuration of the closing in which a link touched the support:
    /// `(link, driver angle)`. The closing stops there.
    pub support: Option<(usize, f64)>,
}

/// The middle plane test: the pad face (or the curled tip) of the `+x` finger has reached
/// `x = 0`.
fn at_middle(linkage: &FingerLinkage, cfg: &FingerConfig) -> bool {
    let (center, tip) = cfg.pad_face(linkage);
    center.x <= 0.0 || tip.x <= 0.0
}

/// What the finger touches in `cfg`: the first link (in [`crate::FINGER_LINKS`] order) that
/// touches the support, else the first that touches the part.
fn touches(
    world: &dyn ClosingWorld,
    linkage: &FingerLinkage,
    side: f64,
    cfg: &FingerConfig,
) -> LinkTouch {
    // The follower's and the pad's frames only when the links before them leave it open.
    let [driver, coupler, spring] = cfg.proximal_frames(linkage);
    let mut distal = None;
    let support = world.has_support();
    let mut part = None;
    for link in 0..crate::FINGER_LINKS.len() {
        let frame = match link {
            0 => driver,
            1 => coupler,
            2 => spring,
            _ => {
                let (follower, pad) = *distal.get_or_insert_with(|| cfg.distal_frames(linkage));
                if link == FOLLOWER {
                    follower
                } else {
                    pad
                }
            }
        };
        match world.touch(side, link, &frame) {
            Touch::Support => return Some((link, Touch::Support)),
            Touch::Part if !support => return Some((link, Touch::Part)),
            Touch::Part if part.is_none() => part = Some((link, Touch::Part)),
            _ => {}
        }
    }
    part
}

/// The bits of `(driver, spring link)` and the finger there ([`Solutions::assemble`]).
type Solved = ([u64; 2], Option<FingerConfig>);

/// The bits of a driver angle and [`FingerLinkage::parallel`] there ([`Solutions::parallel`]).
type SolvedParallel = (u64, Option<FingerConfig>);

/// The linkage's solutions, the last few remembered: both fingers settle at the same driver
/// angle in turn, and in free air they probe the same spring-link angles, so the second finger
/// mostly asks what the first just did. A solution is a function of the angles alone: the
/// remembered one is the one the linkage would give again, bit for bit.
struct Solutions<'a> {
    linkage: &'a FingerLinkage,
    /// The last answers of [`Solutions::assemble`], the newest at `next - 1`.
    assembled: RefCell<[Option<Solved>; 4]>,
    next: Cell<usize>,
    /// Driver bits and [`FingerLinkage::parallel`] there, for the last two driver angles asked
    /// (a step asks the one it starts from and the one it goes to), the newer first.
    parallel: Cell<[Option<SolvedParallel>; 2]>,
}

impl<'a> Solutions<'a> {
    fn new(linkage: &'a FingerLinkage) -> Self {
        Solutions {
            linkage,
            assembled: RefCell::new([None; 4]),
            next: Cell::new(0),
            parallel: Cell::new([None; 2]),
        }
    }

    /// The finger at `(driver, spring_link)`: `None` if the loop cannot close there or a joint
    /// is out of range (the coupler past its stop included).
    fn assemble(&self, driver: f64, spring_link: f64) -> Option<FingerConfig> {
        let key = [driver.to_bits(), spring_link.to_bits()];
        let mut known = self.assembled.borrow_mut();
        if let Some((_, cfg)) = known.iter().flatten().find(|(k, _)| *k == key) {
            return *cfg;
        }
        let linkage = self.linkage;
        let cfg = linkage
            .assemble(driver, spring_link)
            .filter(|c| linkage.within_limits(c, 1e-9));
        let at = self.next.get();
        known[at] = Some((key, cfg));
        self.next.set((at + 1) % known.len());
        cfg
    }

    /// [`FingerLinkage::parallel`] at `driver`.
    fn parallel(&self, driver: f64) -> Option<FingerConfig> {
        let key = driver.to_bits();
        let known = self.parallel.get();
        if let Some((_, cfg)) = known.iter().flatten().find(|(k, _)| *k == key) {
            return *cfg;
        }
        let cfg = self.linkage.parallel(driver);
        self.parallel.set([Some((key, cfg)), known[0]]);
        cfg
    }

    /// The spring link's upper bound at `driver`: the coupler on its stop (the parallel mode),
    /// within the joint's range.
    fn spring_top(&self, driver: f64) -> f64 {
        let limit = self.linkage.limits.spring_link.1;
        self.parallel(driver)
            .map_or(limit, |c| c.spring_link)
            .min(limit)
    }
}

/// The state of the finger at `(driver, spring_link)`: `None` if the loop cannot close there or
/// a joint is out of range (the coupler past its stop included), else what it touches.
fn state(
    world: &dyn ClosingWorld,
    solutions: &Solutions,
    side: f64,
    driver: f64,
    spring_link: f64,
) -> Option<(FingerConfig, LinkTouch)> {
    let cfg = solutions.assemble(driver, spring_link)?;
    Some((cfg, touches(world, solutions.linkage, side, &cfg)))
}

/// Step of the spring link's search when something pushes it open (rad).
const SPRING_STEP: f64 = 0.0025;
/// How far the spring link may be pushed open in one driver step (rad).
const SPRING_REACH: f64 = 0.08;

/// Where the finger settles at driver angle `driver`, last at `from`: the
/// spring closes the link as far as it is free (up to the coupler's stop), and where the part
/// is in the way the link is pushed open to the nearest free angle — but only once the spring
/// link itself has met the part (`may_open`: the finger wraps around the part). A finger that
/// met the part with its pad first does not roll about the contact (friction holds it; the
/// driver stops). `Err` with what blocks the driver when no spring-link angle near its last one
/// is free; the touch that bounds the settled angle from above, if any, comes with it.
fn settle(
    world: &dyn ClosingWorld,
    solutions: &Solutions,
    side: f64,
    driver: f64,
    from: &FingerConfig,
    may_open: bool,
) -> Settled {
    // A touch of the support anywhere in the search ends the closing there: the finger would
    // meet the table on its way, whatever the part does.
    let linkage = solutions.linkage;
    let support = Cell::new(None);
    let probe = |q: f64| match state(world, solutions, side, driver, q) {
        Some((cfg, None)) => Ok(cfg),
        Some((_, Some(t @ (_, Touch::Support)))) => {
            support.set(support.get().or(Some(t)));
            Err(Some(t))
        }
        Some((_, touch)) => Err(touch),
        None => Err(None),
    };
    // While the finger wraps, only "free or not" matters (its first touch is the spring
    // link's already), and without a support nothing else is recorded: a spring-link angle at
    // which the spring link alone touches the part is not free, whatever the loop does there.
    // Its pose needs no loop solution (it turns about its pivot), so the searches about its
    // resting angle skip assembling the finger.
    let spring_alone = may_open && !world.has_support();
    let free = |q: f64| {
        if spring_alone {
            let spring = PlanarPose {
                origin: linkage.s,
                angle: q,
            };
            if world.touch(side, SPRING_LINK, &spring) == Touch::Part {
                return Err(Some((SPRING_LINK, Touch::Part)));
            }
        }
        probe(q)
    };
    // While wrapping, a pad that meets the part stops the curl (see `settle_search`).
    let pad_meets = |q: f64| {
        solutions.assemble(driver, q).is_some_and(|cfg| {
            let (_, pad) = cfg.distal_frames(linkage);
            world.touch(side, PAD, &pad) == Touch::Part
        })
    };
    let settled = settle_search(solutions, driver, from, may_open, &free, &pad_meets);
    match support.get() {
        Some(t) => Err(Some(t)),
        None => settled,
    }
}

/// The search of [`settle`], on the probe `free` (a free configuration, or what is in the way)
/// and `pad_meets` (whether the pad touches the part at a spring-link angle).
///
/// A wrapping finger whose curl is blocked is pushed open by the part — unless its pad is what
/// meets the part: the pad then presses the part (MuJoCo's Menagerie 2F-85 squeezes a bar near
/// the palm with its pads at the bar's lower corners, `data/gripper_truth/closing_2f85_power.json`)
/// and the finger stops there.
fn settle_search(
    solutions: &Solutions,
    driver: f64,
    from: &FingerConfig,
    may_open: bool,
    free: &dyn Fn(f64) -> Result<FingerConfig, LinkTouch>,
    pad_meets: &dyn Fn(f64) -> bool,
) -> Settled {
    let linkage = solutions.linkage;
    let top = solutions.spring_top(driver);
    // A finger resting on the coupler's stop stays on it while it is free there: the spring
    // holds it in the parallel mode (the real finger does not leave the stop in free air).
    // Its pad or follower meeting the part there stops the drivers; anything else in the way
    // (the spring link meeting the part) is left to the search from its last angle.
    if !may_open && from.spring_link == solutions.spring_top(from.driver) {
        match free(top) {
            Ok(cfg) => return Ok((cfg, None)),
            Err(t @ Some((FOLLOWER | PAD, Touch::Part))) => return Err(t),
            Err(_) => {}
        }
    }
    let previous = from.spring_link;
    let start = previous.min(top);
    // The largest free spring-link angle in [lo, hi], `lo` free (`best` there), `hi` not
    // (`bound` touching there).
    let bisect = |mut lo: f64, mut best: FingerConfig, mut hi: f64, mut bound: LinkTouch| {
        while hi - lo > DRIVER_TOLERANCE {
            let mid = 0.5 * (lo + hi);
            match free(mid) {
                Ok(c) => (lo, best) = (mid, c),
                Err(t) => (hi, bound) = (mid, t),
            }
        }
        (best, bound)
    };
    match free(start) {
        // Free: the spring closes the link on, to the stop or to the part, in steps no longer
        // than SPRING_STEP (a world that tests surfaces must not see a link jump into the part).
        Ok(cfg) => {
            let (mut lo, mut best) = (start, cfg);
            while lo < top {
                let next = (lo + SPRING_STEP).min(top);
                match free(next) {
                    Ok(c) => (lo, best) = (next, c),
                    Err(touch) => return Ok(bisect(lo, best, next, touch)),
                }
            }
            Ok((best, None))
        }
        Err(blocking) if !may_open => Err(blocking),
        Err(Some((_, Touch::Part))) if pad_meets(start) => Err(Some((PAD, Touch::Part))),
        Err(blocking) => {
            // In the way: the part pushes the link open to the nearest free angle below.
            let floor = (start - SPRING_REACH).max(linkage.limits.spring_link.0);
            let mut hi = start;
            let mut bound = blocking;
            let mut q = start - SPRING_STEP;
            while q >= floor {
                match free(q) {
                    Ok(cfg) => return Ok(bisect(q, cfg, hi, bound)),
                    Err(t) => (hi, bound) = (q, t),
                }
                q -= SPRING_STEP;
            }
            Err(blocking)
        }
    }
}

/// What one driver step ends in, for one finger.
enum Step {
    Moved(FingerConfig, LinkTouch),
    Stopped(LinkTouch),
    Middle,
}

/// The finger on side `side`, settled from `from` at driver angle `driver`.
fn step(
    world: &dyn ClosingWorld,
    solutions: &Solutions,
    side: f64,
    from: &FingerConfig,
    driver: f64,
    wrapping: bool,
) -> Step {
    match settle(world, solutions, side, driver, from, wrapping) {
        Ok((cfg, _)) if at_middle(solutions.linkage, &cfg) => Step::Middle,
        Ok((cfg, bound)) => Step::Moved(cfg, bound),
        Err(blocking) => Step::Stopped(blocking),
    }
}

/// Records a touch of the part as the finger's first, unless it has one.
fn note(result: &mut FingerClosing, touch: LinkTouch) {
    if let Some((link, Touch::Part)) = touch {
        result.first_touch.get_or_insert(link);
    }
}

/// Moves both fingers to the poses of a step in which both moved, and reports them.
fn take(
    steps: [Step; 2],
    at: &mut [FingerConfig; 2],
    result: &mut [FingerClosing; 2],
    trace: &mut dyn FnMut(&[FingerConfig; 2]),
) {
    for (k, s) in steps.into_iter().enumerate() {
        if let Step::Moved(cfg, bound) = s {
            note(&mut result[k], bound);
            at[k] = cfg;
        }
    }
    trace(at);
}

/// Driver travel within which a finger that touched nothing still meets the part when the
/// other finger's pad has stopped the drivers (rad): about 10 µm of pad travel, ten times
/// [`DRIVER_TOLERANCE`].
///
/// The part between the fingers is not fixed, and the pads are elastomer: where one pad meets
/// it first, the drivers press on and the part gives (or the pad does) by far more than this
/// before the grip is set. Without the slack a grasp centred on its bar to the micrometre (as
/// the seating centres them) would pinch or end on one side by which pad the rounding put a
/// micrometre nearer.
pub const CONTACT_SLACK: f64 = 10.0 * DRIVER_TOLERANCE;

/// The stop's steps `why`, with each finger that has touched nothing yet (`untouched`) and moved
/// freely while the other was stopped by the part replaced by `alone(k)` — finger `k` driven on
/// by [`CONTACT_SLACK`] — where that touches the part: the finger then ends where it is, its
/// first touch that one.
fn pushed_within_slack(
    mut why: [Step; 2],
    untouched: [bool; 2],
    alone: impl Fn(usize) -> Step,
) -> [Step; 2] {
    let stopped_by_part = |s: &Step| matches!(s, Step::Stopped(Some((_, Touch::Part))));
    let free = |s: &Step| matches!(s, Step::Moved(_, None));
    for k in 0..2 {
        if untouched[k] && free(&why[k]) && stopped_by_part(&why[1 - k]) {
            match alone(k) {
                Step::Stopped(t @ Some((_, Touch::Part))) => why[k] = Step::Stopped(t),
                Step::Moved(_, t @ Some((_, Touch::Part))) => why[k] = Step::Stopped(t),
                _ => {}
            }
        }
    }
    why
}

/// Closes both fingers from fully open (`[+x, −x]`). The two drivers turn together (the
/// 2F-85 drives both from one actuator; Menagerie ties their angles) in steps of
/// [`DRIVER_STEP`], each finger settling at every step (see the module documentation), until
/// a finger is blocked or touches the support, a finger reaches the middle, or the drivers
/// their limit; the stop is refined by bisection to [`DRIVER_TOLERANCE`].
pub fn close_fingers(world: &dyn ClosingWorld, linkage: &FingerLinkage) -> [FingerClosing; 2] {
    close_fingers_traced(world, linkage, &mut |_| {})
}

/// [`close_fingers`], reporting to `trace` every pose `[+x, −x]` the fingers pass through, from
/// the open one to the last: what the support must clear is all of them, not only the last.
pub fn close_fingers_traced(
    world: &dyn ClosingWorld,
    linkage: &FingerLinkage,
    trace: &mut dyn FnMut(&[FingerConfig; 2]),
) -> [FingerClosing; 2] {
    const SIDES: [f64; 2] = [1.0, -1.0];
    let (lo, hi) = linkage.limits.driver;
    let open = linkage.parallel(lo).expect("the open finger assembles");
    let mut result = [FingerClosing {
        config: open,
        kind: ClosingKind::Closed,
        first_touch: None,
        support: None,
    }; 2];
    let mut stuck_open = false;
    for (k, side) in SIDES.into_iter().enumerate() {
        if let Some((link, touch)) = touches(world, linkage, side, &open) {
            stuck_open = true;
            match touch {
                Touch::Support => result[k].support = Some((link, lo)),
                _ => {
                    result[k].first_touch = Some(link);
                    result[k].kind = ClosingKind::Stuck;
                }
            }
        }
    }
    trace(&[open; 2]);
    if stuck_open {
        return result;
    }
    let solutions = Solutions::new(linkage);
    let both = |at: &[FingerConfig; 2], driver: f64, result: &[FingerClosing; 2]| {
        [0, 1].map(|k| {
            let wrapping = result[k].first_touch == Some(SPRING_LINK);
            step(world, &solutions, SIDES[k], &at[k], driver, wrapping)
        })
    };
    let moved = |steps: &[Step; 2]| steps.iter().all(|s| matches!(s, Step::Moved(..)));
    let mut at = [open; 2];
    let mut met_in_middle = false;
    loop {
        let next = (at[0].driver + DRIVER_STEP).min(hi);
        if next <= at[0].driver {
            break;
        }
        let steps = both(&at, next, &result);
        if moved(&steps) {
            take(steps, &mut at, &mut result, trace);
            continue;
        }
        // The stop lies in (driver, next]: bisect it.
        let (mut blocked, mut why) = (next, steps);
        while blocked - at[0].driver > DRIVER_TOLERANCE {
            let mid = 0.5 * (at[0].driver + blocked);
            let steps = both(&at, mid, &result);
            if moved(&steps) {
                take(steps, &mut at, &mut result, trace);
            } else {
                (blocked, why) = (mid, steps);
            }
        }
        let untouched = [0, 1].map(|k| result[k].first_touch.is_none());
        let why = pushed_within_slack(why, untouched, |k| {
            step(
                world,
                &solutions,
                SIDES[k],
                &at[k],
                blocked + CONTACT_SLACK,
                false,
            )
        });
        for (k, s) in why.into_iter().enumerate() {
            match s {
                Step::Stopped(Some((link, Touch::Support))) => {
                    result[k].support = Some((link, blocked))
                }
                Step::Stopped(touch) | Step::Moved(_, touch) => note(&mut result[k], touch),
                Step::Middle => met_in_middle = true,
            }
        }
        break;
    }
    for (k, r) in result.iter_mut().enumerate() {
        let cfg = at[k];
        r.config = cfg;
        r.kind = match r.first_touch {
            None => ClosingKind::Closed,
            Some(FOLLOWER | PAD) => ClosingKind::Pinch,
            Some(SPRING_LINK) if met_in_middle || cfg.driver >= hi - DRIVER_TOLERANCE => {
                ClosingKind::Caged
            }
            Some(SPRING_LINK) => ClosingKind::Encompassing,
            Some(_) => ClosingKind::Stuck,
        };
    }
    result
}
