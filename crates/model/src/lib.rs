//! The typed model pregrasp's crates share, built once and passed by reference: a plan set
//! (the cell, the candidates, the plans with typed segments and waypoints, [`plan`]), the plan
//! on one time line ([`timeline`], the only place its rules live), the plan format's closed
//! vocabularies ([`terms`]) and the ranges of its physical values ([`ranges`]). Nothing here
//! reads or writes files: `pregrasp-io` converts the model to and from the plan file, and the
//! planner, the checker, physics, the exports and the viewer take the model.

pub mod plan;
pub mod ranges;
pub mod terms;
pub mod timeline;

pub use plan::{
    as_written, pose_numbers, ArmSetup, Candidate, Closing, DescriptionRef, Grasps, ObjectSetup,
    PadContact, Plan, PlanSet, PlanSettings, Roles, Segment, Waypoint,
};
pub use ranges::{OutOfRange, PhysicsValue, ValueRange, MAX_MASS};
pub use terms::{
    GraspKind, GripVerdict, PlanStatus, RobotModel, RotationDirection, SegmentKind, SegmentName,
    Word,
};
pub use timeline::{Moment, Timeline, TimelineError, CONTACT_ZONE};
