//! Why a candidate has no plan, as data: the planner decides on these types and turns them into
//! words only where they are written (the plan file's `candidates[].outcome` and `reason`), by
//! `Display` ([`Rejection::named`] where the words name the arms).
//!
//! The words are part of the plan file: golden files hold them, so a change of wording is a
//! change of format.

use std::fmt;

use pregrasp_collision::Contact;
use pregrasp_io::plan_file::SegmentName;

use crate::poses::PoseRejection;
use crate::reach::ReachFailure;
use crate::rotate::RotationFailure;

/// The pinch cannot hold the part during μ_rot (`[physics] reject`): the grip check's reason
/// ([`crate::hold::HoldResult::rejection`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Unheld(pub pregrasp_physics::Unheld);

impl fmt::Display for Unheld {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

/// Why one motion of Algorithm 3 does not exist (the motion is named beside it).
#[derive(Clone, Debug, PartialEq)]
pub enum MotionFailure {
    /// μ_rot from one support-grasp solution.
    Rotation(RotationFailure),
    /// μ_rot does not start where the supportive arm stands after an executed `sup1`
    /// (`replan --from rot`).
    NotAtSup1End,
    /// A straight line or the transit of a reach motion.
    Reach(ReachFailure),
    /// Both grippers closed on the part at the end of μ_sup2: two bodies touch.
    FinalGrasp(Contact),
}

impl fmt::Display for MotionFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MotionFailure::Rotation(r) => r.fmt(f),
            MotionFailure::NotAtSup1End => {
                f.write_str("does not start where the supportive arm stands after sup1")
            }
            MotionFailure::Reach(r) => r.fmt(f),
            MotionFailure::FinalGrasp(c) => write!(f, "final grasp: {c}"),
        }
    }
}

/// Why Algorithm 3 (or a re-planning of what is left of a plan) found no integrated path: the
/// failure that got furthest.
#[derive(Clone, Debug, PartialEq)]
pub enum PathFailure {
    /// No support-grasp IK solution to start μ_rot from.
    NoSupportIk,
    /// No collision-free IK solution at the power grasps (re-planning from `mas1`).
    NoPowerIk,
    /// Motion `stage` failed: `cause`.
    Motion {
        stage: SegmentName,
        cause: MotionFailure,
    },
}

impl PathFailure {
    /// How far through Algorithm 3 (μ_rot < μ_sup1 < μ_mas1 < μ_sup2) the failure came.
    pub fn progress(&self) -> u8 {
        match self {
            PathFailure::NoSupportIk | PathFailure::NoPowerIk => 0,
            PathFailure::Motion { stage, .. } => match stage {
                SegmentName::Rot => 1,
                SegmentName::Sup1 => 2,
                SegmentName::Mas1 => 3,
                SegmentName::Sup2 => 4,
            },
        }
    }
}

impl fmt::Display for PathFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PathFailure::NoSupportIk => f.write_str("no support-grasp IK solution"),
            PathFailure::NoPowerIk => f.write_str("no collision-free IK at the power grasps"),
            PathFailure::Motion { stage, cause } => write!(f, "μ_{stage}: {cause}"),
        }
    }
}

/// The first rule of the plan checker a plan fails, as [`crate::check::RuleResult`] gives it
/// (rule 0 with the checker's own error when it could not be built).
#[derive(Clone, Debug, PartialEq)]
pub struct FailedRule {
    pub rule: u8,
    pub detail: String,
}

impl FailedRule {
    /// The first failed rule of `report`, if any.
    pub fn first(report: &crate::check::CheckReport) -> Option<FailedRule> {
        (report.rules.iter())
            .find(|r| r.ok == Some(false))
            .map(|r| FailedRule {
                rule: r.rule,
                detail: r.detail.clone(),
            })
    }
}

impl fmt::Display for FailedRule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "rule {} ({})", self.rule, self.detail)
    }
}

/// Why a candidate was rejected.
#[derive(Clone, Debug, PartialEq)]
pub enum Rejection {
    /// Algorithm 2 found no pose.
    NoPose(PoseRejection),
    /// Algorithm 2 found a pose, Algorithm 3 no integrated path.
    NoPath(PathFailure),
    /// The pinch cannot hold the part during μ_rot.
    Unheld(Unheld),
    /// The plan failed its re-verification.
    CheckFailed(FailedRule),
    /// The arms' start configurations are in collision.
    StartBlocked(Contact),
}

impl Rejection {
    /// The words of the plan file's `outcome` (after `"rejected: "`), naming the arms by
    /// `names`.
    pub fn named<'a>(&'a self, names: &'a [String; 2]) -> impl fmt::Display + 'a {
        Named(self, names)
    }
}

struct Named<'a>(&'a Rejection, &'a [String; 2]);

impl fmt::Display for Named<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Rejection::NoPose(r) => r.named(self.1).fmt(f),
            Rejection::NoPath(p) => p.fmt(f),
            Rejection::Unheld(u) => u.fmt(f),
            Rejection::CheckFailed(rule) => write!(f, "failed the plan check: {rule}"),
            Rejection::StartBlocked(c) => {
                write!(f, "start: {c} at the arms' start configurations")
            }
        }
    }
}
