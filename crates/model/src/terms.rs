//! The closed vocabularies of the plan format (`docs/plan-format.md`) as types: what the file
//! spells as strings (`"rot"`, `"planned"`, `"ccw"`, `"ur5e"`), the code matches as enums.
//!
//! Each value has exactly one word ([`Word::as_str`]) and is read back only from it
//! ([`Word::from_word`], which lists the allowed words when it refuses one). The file format's
//! crate (`pregrasp-io`) reads and writes them with these words; nothing here knows serde.

use std::fmt;
use std::str::FromStr;

use pregrasp_robot::UrModel;

/// A value of a closed vocabulary, spelled by one word.
pub trait Word: Sized + Copy + 'static {
    /// The word the plan file spells it with.
    fn as_str(self) -> &'static str;
    /// The value spelled `word`, or `"x" is not one of a, b, c`.
    fn from_word(word: &str) -> Result<Self, String>;
}

/// `"x" is not one of a, b, c` (the word clipped to 80 characters).
pub fn not_one_of<'w>(word: &str, allowed: impl Iterator<Item = &'w str>) -> String {
    format!(
        "{:?} is not one of {}",
        clip(word, 80),
        allowed.collect::<Vec<_>>().join(", ")
    )
}

/// `s` cut to `max` characters, saying how many more there were.
fn clip(s: &str, max: usize) -> String {
    let count = s.chars().count();
    if count <= max {
        return s.to_string();
    }
    let kept: String = s.chars().take(max).collect();
    format!("{kept}… ({} more characters)", count - max)
}

/// A closed vocabulary: each variant with its word in the file.
macro_rules! vocabulary {
    ($(#[$meta:meta])* $name:ident { $($(#[$vmeta:meta])* $variant:ident = $word:literal),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum $name {
            $($(#[$vmeta])* $variant),+
        }

        impl $name {
            /// Every value, in the format's order.
            pub const ALL: &'static [$name] = &[$($name::$variant),+];

            /// The word the file spells it with.
            pub fn as_str(self) -> &'static str {
                match self {
                    $($name::$variant => $word),+
                }
            }
        }

        impl Word for $name {
            fn as_str(self) -> &'static str {
                $name::as_str(self)
            }

            fn from_word(word: &str) -> Result<Self, String> {
                $name::ALL
                    .iter()
                    .copied()
                    .find(|v| v.as_str() == word)
                    .ok_or_else(|| not_one_of(word, $name::ALL.iter().map(|v| v.as_str())))
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.pad(self.as_str())
            }
        }

        impl FromStr for $name {
            type Err = String;

            fn from_str(s: &str) -> Result<Self, String> {
                <$name as Word>::from_word(s)
            }
        }
    };
}

vocabulary! {
    /// Whether the file holds plans (`status`).
    PlanStatus {
        Planned = "planned",
        NoPlan = "no_plan",
    }
}

vocabulary! {
    /// The four motions of a plan, in the order they run (`segments[].name`; the paper's
    /// μ_sup1, μ_rot, μ_mas1, μ_sup2).
    SegmentName {
        /// The supportive arm reaches the support grasp G_s.
        Sup1 = "sup1",
        /// The supportive arm turns the part about the axis.
        Rot = "rot",
        /// The master arm reaches its power grasp.
        Mas1 = "mas1",
        /// The supportive arm lets go and reaches its power grasp.
        Sup2 = "sup2",
    }
}

vocabulary! {
    /// What a segment's motion is (`segments[].kind`).
    SegmentKind {
        /// From where the arm is to a grasp, ending in a straight approach.
        Reach = "reach",
        /// Holding the part while it turns.
        Rotate = "rotate",
        /// Releasing one grasp (straight retreat) and reaching another.
        Regrasp = "regrasp",
    }
}

vocabulary! {
    /// Which grasp a segment ends at (`segments[].grasp`): the support grasp G_s (held by the
    /// precision point) or the arm's power grasp (by the power point).
    GraspKind {
        Support = "support",
        Power = "power",
    }
}

vocabulary! {
    /// The sense of a candidate's rotation about its axis `axis[1] − axis[0]`
    /// (`candidates[].direction`): right-handed (`ccw`) or the other way.
    RotationDirection {
        Ccw = "ccw",
        Cw = "cw",
    }
}

vocabulary! {
    /// The quasi-static grip check's verdict on a plan's rotation (`physics.verdict`).
    GripVerdict {
        /// Every state is held with a grip force within the gripper's range.
        Holds = "holds",
        /// Some state needs more than the gripper's 235 N (with the safety factor), or no
        /// force holds it.
        CannotHold = "cannot_hold",
        /// Some state needs more support friction than there is.
        SlidesAtSupport = "slides_at_support",
        /// The part hangs from the pinch on the pads' twist: it turns in the pads and its edge
        /// lifts off the support.
        LiftsOffSupport = "lifts_off_support",
    }
}

impl GripVerdict {
    /// In words, for people.
    pub fn describe(self) -> &'static str {
        match self {
            GripVerdict::Holds => "holds",
            GripVerdict::CannotHold => "cannot hold",
            GripVerdict::SlidesAtSupport => "slides at the support",
            GripVerdict::LiftsOffSupport => "lifts off the support",
        }
    }
}

impl SegmentName {
    /// The segment's kind: fixed per segment by the format.
    pub fn kind(self) -> SegmentKind {
        match self {
            SegmentName::Sup1 | SegmentName::Mas1 => SegmentKind::Reach,
            SegmentName::Rot => SegmentKind::Rotate,
            SegmentName::Sup2 => SegmentKind::Regrasp,
        }
    }

    /// The grasp the segment ends at (held throughout `rot`): fixed per segment.
    pub fn grasp(self) -> GraspKind {
        match self {
            SegmentName::Sup1 | SegmentName::Rot => GraspKind::Support,
            SegmentName::Mas1 | SegmentName::Sup2 => GraspKind::Power,
        }
    }

    /// Whether the master arm moves in it (`mas1`); the supportive arm moves in the others.
    pub fn by_master(self) -> bool {
        self == SegmentName::Mas1
    }
}

impl SegmentKind {
    /// Whether the gripper opens at the segment's first point and closes at its last
    /// (`reach`, `regrasp`); it stays closed through `rotate`.
    pub fn closes_at_end(self) -> bool {
        matches!(self, SegmentKind::Reach | SegmentKind::Regrasp)
    }
}

impl RotationDirection {
    /// `+1` for `ccw`, `−1` for `cw`: the sign of the rotation angle about the axis.
    pub fn sign(self) -> f64 {
        match self {
            RotationDirection::Ccw => 1.0,
            RotationDirection::Cw => -1.0,
        }
    }
}

/// `robots[].model`: a built-in arm by its lower-case name, or (extension) `"urdf"`, an arm
/// known only by its robot description (`robots[].urdf` names it). A plan file is
/// machine-written, so the word must be exact (scene files are lenient, see
/// [`UrModel::from_name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RobotModel {
    /// A built-in Universal Robots arm.
    Builtin(UrModel),
    /// The arm of the robot description `robots[].urdf` names.
    Described,
}

impl RobotModel {
    /// The word for an arm known only by its description.
    pub const DESCRIBED: &'static str = "urdf";

    /// The file's word.
    pub fn as_str(self) -> &'static str {
        match self {
            RobotModel::Builtin(m) => m.name(),
            RobotModel::Described => Self::DESCRIBED,
        }
    }

    /// The built-in model, if the arm is one.
    pub fn builtin(self) -> Option<UrModel> {
        match self {
            RobotModel::Builtin(m) => Some(m),
            RobotModel::Described => None,
        }
    }
}

impl Word for RobotModel {
    fn as_str(self) -> &'static str {
        RobotModel::as_str(self)
    }

    fn from_word(word: &str) -> Result<Self, String> {
        if word == Self::DESCRIBED {
            return Ok(RobotModel::Described);
        }
        UrModel::ALL
            .into_iter()
            .find(|m| m.name() == word)
            .map(RobotModel::Builtin)
            .ok_or_else(|| {
                let words = UrModel::ALL.iter().map(|m| m.name());
                not_one_of(word, words.chain([Self::DESCRIBED]))
            })
    }
}

impl fmt::Display for RobotModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_word_reads_back_as_its_value_and_others_are_refused() {
        for name in SegmentName::ALL {
            assert_eq!(SegmentName::from_word(name.as_str()).unwrap(), *name);
        }
        for status in PlanStatus::ALL {
            assert_eq!(status.as_str().parse::<PlanStatus>().unwrap(), *status);
        }
        for model in UrModel::ALL {
            let m = RobotModel::Builtin(model);
            assert_eq!(RobotModel::from_word(m.as_str()).unwrap(), m);
        }
        assert_eq!(
            RobotModel::from_word("urdf").unwrap(),
            RobotModel::Described
        );
        // Tables pad them like the strings they replaced.
        assert_eq!(format!("[{:4}]", RotationDirection::Cw), "[cw  ]");
        let err = SegmentName::from_word("Rot").unwrap_err();
        assert!(
            err.starts_with("\"Rot\" is not one of sup1, rot, mas1, sup2"),
            "{err}"
        );
        assert!(RobotModel::from_word("UR5e").is_err());
    }

    #[test]
    fn each_segment_has_the_kind_and_grasp_of_the_format() {
        use GraspKind::*;
        use SegmentKind::*;
        let table: Vec<(SegmentName, SegmentKind, GraspKind)> = SegmentName::ALL
            .iter()
            .map(|s| (*s, s.kind(), s.grasp()))
            .collect();
        assert_eq!(
            table,
            [
                (SegmentName::Sup1, Reach, Support),
                (SegmentName::Rot, Rotate, Support),
                (SegmentName::Mas1, Reach, Power),
                (SegmentName::Sup2, Regrasp, Power),
            ]
        );
    }
}
