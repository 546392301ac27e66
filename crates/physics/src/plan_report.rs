//! What the grip check of one plan reports: each state of `rot` (status, required force,
//! friction use), the plan's verdict, what it warns of ([`GripWarning`]) and why a planner
//! would refuse the rotation ([`Unheld`]). The planner writes it as the plan file's `physics`
//! object; the words of the warnings and reasons are their `Display`.

use std::fmt;

use pregrasp_model::{GraspKind, SegmentName, Word};

use crate::part_mass::PartMass;
use crate::settings::PhysicsSettings;
use crate::statics::Equilibrium;
use crate::words::as_texts;

/// How one state ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StateStatus {
    Held,
    /// Only with more support friction: the part slides on the support.
    Slides,
    /// Not with any grip force.
    CannotHold,
}

/// One checked state of `rot`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct StateReport {
    /// Index of the `rot` point, or `None` for a state interpolated between two points.
    pub point: Option<usize>,
    /// Time since `rot` began (s).
    pub t: f64,
    /// Rotation of the part from P_init (degrees).
    pub theta_deg: f64,
    /// How many axis endpoints touch the support (0, 1 or 2).
    pub support_contacts: usize,
    pub status: StateStatus,
    /// N_min (N) when held.
    pub n_min: Option<f64>,
    /// Σ normal force at the support (N).
    pub support_normal: Option<f64>,
    /// |Σ tangential force| at the support (N).
    pub support_tangential: Option<f64>,
    /// Largest |t|/(μ n) at the support contacts.
    pub support_friction_use: Option<f64>,
    /// Largest |t|/(μ N) at the pads when they squeeze with the recommended force (with the
    /// gripper's largest force, 235 N for the 2F-85, when the part cannot be held).
    pub pad_friction_use: Option<f64>,
    #[serde(skip)]
    pub equilibrium: Option<Equilibrium>,
}

/// The verdict on one plan (the plan file's vocabulary).
pub use pregrasp_model::GripVerdict as Verdict;

/// The verdict by its plan-file word.
fn verdict_word<S: serde::Serializer>(v: &Verdict, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(v.as_str())
}

/// The check of one plan.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PlanPhysics {
    /// Index into the plan set's `plans`.
    pub plan: usize,
    pub candidate: usize,
    pub part: PartMass,
    pub settings: PhysicsSettings,
    /// The supportive arm, which holds `G_s` during `rot` (index into the plan set's `arms`).
    pub arm: usize,
    /// Pad gap used (m): `rot.grip_width`, or 0 when the plan has none.
    pub grip_width: f64,
    pub states: Vec<StateReport>,
    /// Index into `states` of the worst one (not held, else the largest N_min).
    pub worst: usize,
    /// Largest N_min (N) over the states, when all are held.
    pub n_max: Option<f64>,
    /// `safety_factor × n_max` (N).
    pub required: Option<f64>,
    /// The grip force to set: `required` clamped into the gripper's range (the 2F-85's 20–235
    /// N by default, [`PhysicsSettings::grip_force`]), when it holds.
    pub recommended: Option<f64>,
    #[serde(serialize_with = "verdict_word")]
    pub verdict: Verdict,
    /// The largest twist arm over the states (m, [`crate::twist`]): the moment per newton of
    /// weight only a twist of the pads holds.
    pub twist_arm: f64,
    /// Things the verdict alone does not say (axis off the support, ...).
    #[serde(serialize_with = "as_texts")]
    pub warnings: Vec<GripWarning>,
    /// Each closing segment of the plan (`sup1`, `mas1`, `sup2`, in plan order) with the grip
    /// force the plan closes it with.
    pub closings: Vec<ClosingForce>,
    /// The analysis stopped at the first state that cannot be held, or after the first state of
    /// a rotation that hangs on the pads' twist ([`screen_plan`](crate::screen_plan)): `worst`
    /// is where the failure begins, and the states after it were not checked.
    #[serde(skip)]
    pub stopped_at_failure: bool,
}

/// A closing segment and the grip force (N) the plan gives it (`segments[].grip_force`; for
/// `sup1` without one, the plan's recommended pinch force), `None` when it gives none (the power
/// grasps', until a check of the carried part computes them).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ClosingForce {
    #[serde(serialize_with = "word")]
    pub segment: SegmentName,
    /// The arm that closes (index into the plan set's `arms`).
    pub arm: usize,
    #[serde(serialize_with = "word")]
    pub grasp: GraspKind,
    pub grip_force: Option<f64>,
}

/// A vocabulary's value by its plan-file word.
fn word<W: Word, S: serde::Serializer>(v: &W, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(v.as_str())
}

impl PlanPhysics {
    /// The verdict is not "holds", or a warning was raised.
    pub fn flagged(&self) -> bool {
        self.verdict != Verdict::Holds || !self.warnings.is_empty()
    }

    /// Why the planner drops this plan's candidate (`[physics] reject`), or `None` if it holds.
    pub fn rejection(&self) -> Option<Unheld> {
        let worst = self.states.get(self.worst)?;
        let at = At {
            from: self.stopped_at_failure,
            theta_deg: worst.theta_deg,
            t: worst.t,
        };
        match self.verdict {
            Verdict::Holds => None,
            Verdict::LiftsOffSupport => self.warnings.iter().find_map(|w| match *w {
                GripWarning::HangsOnTwist { arm, max } => Some(Unheld::HangsOnTwist { arm, max }),
                _ => None,
            }),
            Verdict::SlidesAtSupport => Some(match self.warnings.first() {
                Some(&GripWarning::EdgeSlides { distance }) => Unheld::EdgeSlides { distance },
                _ => Unheld::SlidesAtSupport {
                    at,
                    mu_support: self.settings.mu_support,
                },
            }),
            Verdict::CannotHold => Some(match self.required {
                Some(required) => Unheld::NeedsMoreForce {
                    required,
                    safety_factor: self.settings.safety_factor,
                    n_max: self.n_max.unwrap_or(0.0),
                    at,
                    max_force: self.settings.grip_force.1,
                },
                None => Unheld::NoForce { at },
            }),
        }
    }
}

/// Something the verdict alone does not say about a plan's rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GripWarning {
    /// The points of the part resting on the support slide `distance` (m) along it during
    /// `rot`: the axis is not the part's real edge.
    EdgeSlides { distance: f64 },
    /// In `states` of the `of` states checked neither axis endpoint is within `within` (m) of
    /// the support.
    NoSupportContact {
        states: usize,
        of: usize,
        within: f64,
    },
    /// In `states` of the `of` states checked only one axis endpoint touches the support.
    OneSupportContact { states: usize, of: usize },
    /// `rot` records no grip width: both pad contacts are taken at the precision point.
    NoGripWidth,
    /// The pads must hold the part's weight `arm` (m) off the pinch by their twist, more than
    /// `max` ([`crate::twist::MAX_TWIST_ARM`]).
    HangsOnTwist { arm: f64, max: f64 },
}

impl fmt::Display for GripWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            GripWarning::EdgeSlides { distance } => write!(
                f,
                "the part's edge slides {:.1} mm along the support during rot: the rotation axis \
                 is not on the part's real edge",
                distance * 1e3
            ),
            GripWarning::NoSupportContact { states, of, within } => write!(
                f,
                "{states} of {of} states: neither axis endpoint is within {:.1} mm of the support \
                 — the part's edge is not on the line the plan claims, and the pads alone hold \
                 it there",
                within * 1e3
            ),
            GripWarning::OneSupportContact { states, of } => write!(
                f,
                "{states} of {of} states: only one axis endpoint touches the support"
            ),
            GripWarning::NoGripWidth => f.write_str(
                "rot has no grip_width: both pad contacts are taken at the precision point",
            ),
            GripWarning::HangsOnTwist { arm, max } => write!(
                f,
                "the part hangs from the pinch on the pads' twist, its weight {:.1} mm beyond \
                 it (at most {:.1} mm): it turns in the pads and its edge lifts",
                arm * 1e3,
                max * 1e3
            ),
        }
    }
}

/// Where along `rot` a rotation stops being held: `at θ = 12.0° (t = 1.50 s)`, or `from …` when
/// the screening stopped there ([`PlanPhysics::stopped_at_failure`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct At {
    pub from: bool,
    pub theta_deg: f64,
    pub t: f64,
}

impl fmt::Display for At {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} θ = {:.1}° (t = {:.2} s)",
            if self.from { "from" } else { "at" },
            self.theta_deg,
            self.t
        )
    }
}

/// Why the pinch does not hold the part during `rot` ([`PlanPhysics::rejection`]); its
/// `Display` is the candidate's outcome in the plan file (`physics: …`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unheld {
    /// The part's edge slides `distance` (m) along the support ([`GripWarning::EdgeSlides`]).
    EdgeSlides { distance: f64 },
    /// The support's friction `mu_support` cannot keep the part from sliding.
    SlidesAtSupport { at: At, mu_support: f64 },
    /// The pinch needs `required` = `safety_factor` × `n_max` (N), more than the gripper's
    /// `max_force`.
    NeedsMoreForce {
        required: f64,
        safety_factor: f64,
        n_max: f64,
        at: At,
        max_force: f64,
    },
    /// No grip force holds the part.
    NoForce { at: At },
    /// The part hangs on the pads' twist ([`GripWarning::HangsOnTwist`]).
    HangsOnTwist { arm: f64, max: f64 },
}

impl fmt::Display for Unheld {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Unheld::EdgeSlides { distance } => write!(
                f,
                "physics: slides at the support: {}",
                GripWarning::EdgeSlides { distance }
            ),
            Unheld::SlidesAtSupport { at, mu_support } => write!(
                f,
                "physics: slides at the support {at} (μ_support = {mu_support})"
            ),
            Unheld::NeedsMoreForce {
                required,
                safety_factor,
                n_max,
                at,
                max_force,
            } => write!(
                f,
                "physics: cannot hold: the pinch needs {required:.0} N (safety factor \
                 {safety_factor} × {n_max:.0} N {at}), more than the gripper's {max_force:.0} N"
            ),
            Unheld::NoForce { at } => {
                write!(f, "physics: cannot hold the part with any grip force {at}")
            }
            Unheld::HangsOnTwist { arm, max } => write!(
                f,
                "physics: lifts off the support: {}",
                GripWarning::HangsOnTwist { arm, max }
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{At, GripWarning, Unheld};
    use crate::part_mass::MassSource;

    /// The words the plan files and the planner's outcomes have always held.
    #[test]
    fn reasons_and_warnings_keep_their_words() {
        let slides = GripWarning::EdgeSlides { distance: 0.0123 };
        assert_eq!(
            slides.to_string(),
            "the part's edge slides 12.3 mm along the support during rot: the rotation axis is \
             not on the part's real edge"
        );
        assert_eq!(
            GripWarning::NoSupportContact {
                states: 3,
                of: 9,
                within: 0.006
            }
            .to_string(),
            "3 of 9 states: neither axis endpoint is within 6.0 mm of the support — the part's \
             edge is not on the line the plan claims, and the pads alone hold it there"
        );
        assert_eq!(
            GripWarning::OneSupportContact { states: 2, of: 9 }.to_string(),
            "2 of 9 states: only one axis endpoint touches the support"
        );
        assert_eq!(
            GripWarning::NoGripWidth.to_string(),
            "rot has no grip_width: both pad contacts are taken at the precision point"
        );
        let at = At {
            from: false,
            theta_deg: 12.34,
            t: 1.5,
        };
        let from = At { from: true, ..at };
        assert_eq!(
            Unheld::EdgeSlides { distance: 0.0123 }.to_string(),
            format!("physics: slides at the support: {slides}")
        );
        assert_eq!(
            Unheld::SlidesAtSupport {
                at,
                mu_support: 0.4
            }
            .to_string(),
            "physics: slides at the support at θ = 12.3° (t = 1.50 s) (μ_support = 0.4)"
        );
        assert_eq!(
            Unheld::NeedsMoreForce {
                required: 300.4,
                safety_factor: 2.0,
                n_max: 150.2,
                at: from,
                max_force: 235.0
            }
            .to_string(),
            "physics: cannot hold: the pinch needs 300 N (safety factor 2 × 150 N from θ = 12.3° \
             (t = 1.50 s)), more than the gripper's 235 N"
        );
        assert_eq!(
            Unheld::NoForce { at }.to_string(),
            "physics: cannot hold the part with any grip force at θ = 12.3° (t = 1.50 s)"
        );
        assert_eq!(MassSource::Plan.to_string(), "plan object.mass");
        assert_eq!(MassSource::Given("--mass").to_string(), "--mass");
        assert_eq!(
            MassSource::Density {
                density: 700.0,
                volume: 0.00459
            }
            .to_string(),
            "700 kg/m³ × mesh volume 0.004590 m³ (no mass given)"
        );
    }
}
