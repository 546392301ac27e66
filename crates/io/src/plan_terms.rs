//! The plan format's words for the model's closed vocabularies ([`pregrasp_model::terms`]:
//! `"rot"`, `"planned"`, `"ccw"`, `"ur5e"`), read and written by serde through [`word`], and the
//! candidates' `outcome` text ([`Outcome`]). A word outside the vocabulary is refused when the
//! file is read, with the allowed ones listed.

use std::fmt;
use std::str::FromStr;

pub use pregrasp_model::terms::{
    GraspKind, GripVerdict, PlanStatus, RobotModel, RotationDirection, SegmentKind, SegmentName,
    Word,
};
use pregrasp_robot::UrModel;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// `"x" is not one of a, b, c` (the word clipped to 80 characters).
fn not_one_of<'w>(word: &str, allowed: impl Iterator<Item = &'w str>) -> String {
    pregrasp_model::terms::not_one_of(word, allowed)
}

/// Serde for a vocabulary value by its word (`#[serde(with = "word")]`).
pub mod word {
    use super::*;

    pub fn serialize<W: Word, S: Serializer>(value: &W, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(value.as_str())
    }

    pub fn deserialize<'de, W: Word, D: Deserializer<'de>>(deserializer: D) -> Result<W, D::Error> {
        let word = String::deserialize(deserializer)?;
        W::from_word(&word).map_err(serde::de::Error::custom)
    }
}

/// What became of a rotation-axis candidate (`candidates[].outcome`): `planned`,
/// `rejected: <why>`, or `not evaluated…` (the planner did not get to it).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    Planned,
    /// Why not (non-empty).
    Rejected(String),
    /// What follows the words "not evaluated" (e.g. ` (axes only)`, `: not re-planned`).
    NotEvaluated(String),
}

impl Outcome {
    /// `not evaluated: <why>`.
    pub fn not_evaluated(why: impl fmt::Display) -> Outcome {
        Outcome::NotEvaluated(format!(": {why}"))
    }

    /// `rejected: <why>`.
    pub fn rejected(why: impl fmt::Display) -> Outcome {
        Outcome::Rejected(why.to_string())
    }
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Outcome::Planned => f.write_str("planned"),
            Outcome::Rejected(why) => write!(f, "rejected: {why}"),
            Outcome::NotEvaluated(rest) => write!(f, "not evaluated{rest}"),
        }
    }
}

impl FromStr for Outcome {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        if s == "planned" {
            return Ok(Outcome::Planned);
        }
        if let Some(why) = s.strip_prefix("rejected: ").filter(|w| !w.is_empty()) {
            return Ok(Outcome::Rejected(why.to_string()));
        }
        if let Some(rest) = s.strip_prefix("not evaluated") {
            return Ok(Outcome::NotEvaluated(rest.to_string()));
        }
        Err(format!(
            "{:?} is not \"planned\", \"rejected: <why>\" or \"not evaluated…\"",
            crate::text::clip(s, 80)
        ))
    }
}

impl Serialize for Outcome {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for Outcome {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

/// Serde for a UR model by its lower-case name: a plan file is machine-written, so the name
/// must be exact (scene files are lenient, see [`UrModel::from_name`]).
pub mod ur_model {
    use super::*;

    pub fn serialize<S: Serializer>(model: &UrModel, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(model.name())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<UrModel, D::Error> {
        let word = String::deserialize(deserializer)?;
        UrModel::ALL
            .into_iter()
            .find(|m| m.name() == word)
            .ok_or_else(|| {
                serde::de::Error::custom(not_one_of(&word, UrModel::ALL.iter().map(|m| m.name())))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize, Deserialize, Debug, PartialEq)]
    struct Named {
        #[serde(with = "word")]
        name: SegmentName,
        #[serde(with = "word")]
        model: RobotModel,
    }

    #[test]
    fn vocabulary_values_are_written_and_read_as_their_words() {
        for name in SegmentName::ALL {
            let v = Named {
                name: *name,
                model: RobotModel::Builtin(UrModel::Ur5e),
            };
            let json = serde_json::to_string(&v).unwrap();
            assert_eq!(json, format!("{{\"name\":\"{name}\",\"model\":\"ur5e\"}}"));
            assert_eq!(serde_json::from_str::<Named>(&json).unwrap(), v);
        }
        let err = serde_json::from_str::<Named>(r#"{"name":"Rot","model":"urdf"}"#).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("\"Rot\" is not one of sup1, rot, mas1, sup2"),
            "{err}"
        );
        let err = serde_json::from_str::<Named>(r#"{"name":"rot","model":"ur6"}"#).unwrap_err();
        assert!(err.to_string().contains("is not one of ur3e"), "{err}");
    }
}
