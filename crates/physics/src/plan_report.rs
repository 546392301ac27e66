//! What the grip check of one plan reports: each state of `rot` (status, required force,
//! friction use) and the plan's verdict, written as the plan file's `physics` object.

use pregrasp_io::plan_file::PhysicsJson;

use crate::part_mass::PartMass;
use crate::settings::PhysicsSettings;
use crate::statics::Equilibrium;

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
pub use pregrasp_io::plan_terms::GripVerdict as Verdict;

/// The verdict by its plan-file word.
fn verdict_word<S: serde::Serializer>(v: &Verdict, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(v.as_str())
}

/// The check of one plan.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PlanPhysics {
    /// Index into the plan file's `plans`.
    pub plan: usize,
    pub candidate: usize,
    pub part: PartMass,
    pub settings: PhysicsSettings,
    /// The supportive arm, which holds `G_s` during `rot`.
    pub robot: String,
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
    /// Things the verdict alone does not say (axis off the support, ...).
    pub warnings: Vec<String>,
    /// The analysis stopped at the first state that cannot be held ([`screen_plan`](crate::screen_plan)): `worst`
    /// is where the failure begins, and the states after it were not checked.
    #[serde(skip)]
    pub stopped_at_failure: bool,
}

impl PlanPhysics {
    /// The verdict is not "holds", or a warning was raised.
    pub fn flagged(&self) -> bool {
        self.verdict != Verdict::Holds || !self.warnings.is_empty()
    }

    /// The plan file's `physics` object of this plan: the worst state's numbers and the
    /// largest friction use over all states.
    pub fn to_json(&self) -> PhysicsJson {
        let max =
            |f: fn(&StateReport) -> Option<f64>| self.states.iter().filter_map(f).reduce(f64::max);
        let worst = self.states.get(self.worst);
        PhysicsJson {
            verdict: self.verdict,
            mass: self.part.mass,
            mass_source: self.part.source.clone(),
            mu_pad: self.settings.mu_pad,
            mu_support: self.settings.mu_support,
            safety_factor: self.settings.safety_factor,
            grip_force_min: self.n_max,
            grip_force_required: self.required,
            grip_force_recommended: self.recommended,
            pad_friction_use: max(|s| s.pad_friction_use),
            support_friction_use: max(|s| s.support_friction_use),
            support_normal_max: max(|s| s.support_normal),
            worst_t: worst.map_or(0.0, |s| s.t),
            worst_theta_deg: worst.map_or(0.0, |s| s.theta_deg),
            states: self.states.len(),
            warnings: self.warnings.clone(),
        }
    }

    /// Why the planner drops this plan's candidate (`[physics] reject`), or `None` if it holds.
    pub fn rejection(&self) -> Option<String> {
        let worst = self.states.get(self.worst)?;
        let at = format!(
            "{} θ = {:.1}° (t = {:.2} s)",
            if self.stopped_at_failure {
                "from"
            } else {
                "at"
            },
            worst.theta_deg,
            worst.t
        );
        match self.verdict {
            Verdict::Holds => None,
            Verdict::SlidesAtSupport => Some(match self.warnings.first() {
                Some(w) if w.contains("slides") => format!("physics: slides at the support: {w}"),
                _ => format!(
                    "physics: slides at the support {at} (μ_support = {})",
                    self.settings.mu_support
                ),
            }),
            Verdict::CannotHold => Some(match self.required {
                Some(r) => format!(
                    "physics: cannot hold: the pinch needs {r:.0} N (safety factor {} × {:.0} N {at}), \
                     more than the gripper's {:.0} N",
                    self.settings.safety_factor,
                    self.n_max.unwrap_or(0.0),
                    self.settings.grip_force.1
                ),
                None => format!("physics: cannot hold the part with any grip force {at}"),
            }),
        }
    }
}
