//! Another arm in place of each UR5e of a generated scene: the scenes of the other-arm sweeps
//! (`pregrasp example generate --arm`), written by the one function the tests also read them
//! through, so a table's scene SHA-256 names the same bytes in both.
//!
//! A generated scene stands two UR5e at `[0, ±0.45, 0]` (world, metres), both starting in
//! [`crate::SceneLayout`]'s home posture. Another UR keeps all of it: only `model` changes. A
//! described arm (a URDF of `data/robots/`) has its own reach and its own home, so it also
//! brings its start and where its bases stand.

use std::path::{Path, PathBuf};

use pregrasp_robot::UrModel;

/// The described arms [`ArmInPlace::by_name`] knows, besides the UR models.
pub const DESCRIBED_ARMS: [&str; 2] = ["fr3", "xarm6"];

/// The arm put in place of each UR5e.
#[derive(Clone, Debug, PartialEq)]
pub enum ArmInPlace {
    /// Another UR model (`model = "<name>"`, everything else as generated).
    Ur(UrModel),
    /// An arm described by a URDF.
    Described {
        /// The robot's keys written in place of `model = "ur5e"` (`urdf = …` and what the arm
        /// needs besides: `tool_link`, `hold`).
        keys: String,
        /// The `start` joint vector, as written.
        start: &'static str,
        /// Where the bases stand: `[x, ±y, 0]`, as written.
        base: [&'static str; 2],
    },
}

/// Why an arm cannot be put in place.
#[derive(Debug, thiserror::Error)]
pub enum ArmInPlaceError {
    #[error(
        "unknown arm \"{0}\" (expected a UR model: {urs}, or a described arm: {described})",
        urs = pregrasp_io::scene::ROBOT_MODELS.join(", "),
        described = DESCRIBED_ARMS.join(", ")
    )]
    Unknown(String),
    #[error(
        "the {arm} is described by {path}, which cannot be read ({source}); run from the \
         repository's root or pass the directory holding {file} with --robots"
    )]
    Urdf {
        arm: &'static str,
        path: PathBuf,
        file: &'static str,
        source: std::io::Error,
    },
}

impl ArmInPlace {
    /// The arm called `name`: a UR model of the scene format (`"ur10e"`, say), or `"fr3"`, the
    /// Franka FR3 (elbow joint `fr3_joint3` held at 0, its "ready" posture, the bases 0.1 m
    /// nearer the part), or `"xarm6"`, the UFACTORY xArm6 (the bases also 0.1 m nearer the
    /// middle, for its 0.7 m reach). A described arm's URDF is read from `robots`
    /// (`data/robots` of the repository) and written as its absolute path.
    pub fn by_name(name: &str, robots: &Path) -> Result<Self, ArmInPlaceError> {
        if let Some(model) = UrModel::from_name(name) {
            return Ok(Self::Ur(model));
        }
        let urdf = |arm: &'static str, file: &'static str| {
            let path = robots.join(file);
            let found = path
                .canonicalize()
                .map_err(|source| ArmInPlaceError::Urdf {
                    arm,
                    path: path.clone(),
                    file,
                    source,
                })?;
            Ok::<_, ArmInPlaceError>(format!("{:?}", found.display().to_string()))
        };
        match name {
            "fr3" => Ok(Self::Described {
                keys: format!(
                    "urdf = {}\ntool_link = \"fr3_link8\"\nhold = {{ fr3_joint3 = 0.0 }}",
                    urdf("FR3", "fr3.urdf")?
                ),
                start: "[0.0, -0.7854, -2.3562, 0.0, 1.5708, 0.7854]",
                base: ["0.100", "0.450"],
            }),
            "xarm6" => Ok(Self::Described {
                keys: format!("urdf = {}", urdf("xArm6", "xarm6.urdf")?),
                start: "[0.0, -0.5, -0.8, 0.0, 1.3, 0.0]",
                base: ["0.100", "0.350"],
            }),
            _ => Err(ArmInPlaceError::Unknown(name.to_string())),
        }
    }

    /// A generated scene's text with this arm for each UR5e. The UR5e (and the UR5e's keys)
    /// give the text back unchanged.
    pub fn put_in(&self, text: &str) -> String {
        match self {
            Self::Ur(model) => {
                text.replace("model = \"ur5e\"", &format!("model = \"{}\"", model.name()))
            }
            Self::Described { keys, start, base } => {
                let [x, y] = base;
                let mut out = String::with_capacity(text.len() + 2 * keys.len());
                for line in text.lines() {
                    let line = if line.trim() == "model = \"ur5e\"" {
                        keys.clone()
                    } else if line == "base = { xyz = [0.000, 0.450, 0.000] }" {
                        format!("base = {{ xyz = [{x}, {y}, 0.000] }}")
                    } else if line == "base = { xyz = [0.000, -0.450, 0.000] }" {
                        format!("base = {{ xyz = [{x}, -{y}, 0.000] }}")
                    } else if line.starts_with("start = ") {
                        format!("start = {start}")
                    } else {
                        line.to_string()
                    };
                    out.push_str(&line);
                    out.push('\n');
                }
                out
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generated::generated_scene;
    use crate::parts::families::generate;
    use crate::Family;

    fn robots() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/robots")
    }

    #[test]
    fn every_line_an_arm_needs_is_replaced_and_no_other() {
        let text = generated_scene(&generate(Family::Frame, 3)).scene_toml;
        assert_eq!(
            ArmInPlace::by_name("ur5e", &robots())
                .unwrap()
                .put_in(&text),
            text
        );
        let ur10e = ArmInPlace::by_name("ur10e", &robots())
            .unwrap()
            .put_in(&text);
        assert_eq!(ur10e.matches("model = \"ur10e\"").count(), 2);
        assert!(!ur10e.contains("ur5e\""));
        for name in DESCRIBED_ARMS {
            let arm = ArmInPlace::by_name(name, &robots()).unwrap();
            let out = arm.put_in(&text);
            assert!(!out.contains("model = "), "{name}");
            assert_eq!(out.matches("urdf = ").count(), 2, "{name}");
            let ArmInPlace::Described { start, base, .. } = arm else {
                panic!("{name} is described")
            };
            assert_eq!(out.matches(&format!("start = {start}")).count(), 2);
            for y in [base[1].to_string(), format!("-{}", base[1])] {
                let line = format!("base = {{ xyz = [{}, {y}, 0.000] }}", base[0]);
                assert_eq!(out.matches(&line).count(), 1, "{name}: {line}");
            }
            // Nothing else moves: the lines not about the arms are the generated ones.
            let kept = |t: &str| {
                t.lines()
                    .filter(|l| !l.starts_with("base = ") && !l.starts_with("start = "))
                    .filter(|l| !l.starts_with("model = ") && !l.starts_with("urdf = "))
                    .filter(|l| !l.starts_with("tool_link = ") && !l.starts_with("hold = "))
                    .map(str::to_string)
                    .collect::<Vec<_>>()
            };
            assert_eq!(kept(&out), kept(&text), "{name}");
        }
    }

    #[test]
    fn an_unknown_arm_or_a_missing_urdf_says_what_to_do() {
        let e = ArmInPlace::by_name("ur7", &robots())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("\"ur7\"") && e.contains("ur16e") && e.contains("xarm6"),
            "{e}"
        );
        let e = ArmInPlace::by_name("fr3", Path::new("/nonexistent"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/nonexistent/fr3.urdf") && e.contains("--robots"),
            "{e}"
        );
    }
}
